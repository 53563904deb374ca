//! Packet captures with tshark inside the test namespace, and the check that every captured
//! frame dissects cleanly: no malformed packet and no expert info of warning severity or worse.

use std::io;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::netns::Namespace;
use crate::process::{run_bounded, LoggedChild, SIGINT};

/// How long tshark may take to start capturing, and to read a capture back.
const TSHARK_TIMEOUT: Duration = Duration::from_secs(30);

/// How long the last frames may wait in the kernel's capture ring.
const FLUSH: Duration = Duration::from_millis(800);

/// Display filter for frames that did not dissect cleanly (tshark 4.0 field names; expert
/// severities are 0x00600000 warning and 0x00800000 error).
const PROBLEMS: &str = "_ws.malformed || _ws.expert.severity >= 0x00600000";

/// A running tshark writing `path`.
#[derive(Debug)]
pub struct Capture {
    tshark: LoggedChild,
    path: PathBuf,
}

impl Capture {
    /// Starts capturing on `iface` inside `ns` into `path`; returns once tshark captures.
    pub fn start(ns: &Namespace, iface: &str, path: &Path) -> io::Result<Self> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        // dumpcap may run as another user: let it create the file.
        let _ = std::fs::remove_file(path);
        let mut cmd = ns.command("tshark");
        cmd.args(["-q", "-n", "-i", iface, "-w"]).arg(path);
        let mut tshark = LoggedChild::spawn("tshark", cmd)?;
        tshark.wait_for_line("Capture started", TSHARK_TIMEOUT)?;
        Ok(Capture {
            tshark,
            path: path.to_path_buf(),
        })
    }

    /// Stops tshark (SIGINT, so the file is complete) and returns the capture file.
    pub fn stop(mut self) -> PathBuf {
        // dumpcap reads the kernel's packet ring one block at a time (a block retires after
        // its 250 ms read timeout) and drops a partial block when interrupted: let it retire.
        std::thread::sleep(FLUSH);
        self.tshark.stop(SIGINT, Duration::from_secs(5));
        self.path.clone()
    }
}

/// Frames of the capture `path` within `scope` (a display filter, e.g.
/// `ip.src == 198.18.0.2`; empty for all frames) that are malformed or carry expert info of
/// warning severity or worse, one summary line each. Expert messages listed in `tolerated`
/// do not count.
pub fn problems(path: &Path, scope: &str, tolerated: &[&str]) -> io::Result<Vec<String>> {
    let filter = if scope.is_empty() {
        PROBLEMS.to_string()
    } else {
        format!("({PROBLEMS}) && ({scope})")
    };
    let mut cmd = Command::new("tshark");
    cmd.args(["-n", "-r"])
        .arg(path)
        .args(["-Y", &filter, "-T", "fields"]);
    cmd.args(["-E", "separator=|", "-E", "aggregator=;"]);
    for field in FIELDS {
        cmd.args(["-e", field]);
    }
    let out = run_bounded(cmd, None, TSHARK_TIMEOUT)?;
    if !out.status.success() {
        return Err(io::Error::other(format!(
            "tshark -r {} failed: {}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        )));
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| counts(l, tolerated))
        .map(str::to_string)
        .collect())
}

/// Fields printed per problem frame; [`counts`] relies on the order of the first three.
const FIELDS: [&str; 7] = [
    "_ws.malformed",
    "_ws.expert.severity",
    "_ws.expert.message",
    "frame.number",
    "ip.src",
    "ip.dst",
    "_ws.col.Info",
];

/// Expert severity "warning".
const WARNING: u32 = 0x0060_0000;

/// True if the problem line `l` is malformed or has a warning that is not tolerated.
fn counts(l: &str, tolerated: &[&str]) -> bool {
    let mut f = l.split('|');
    let (malformed, severities, messages) = (f.next(), f.next(), f.next());
    if malformed.is_some_and(|m| !m.is_empty()) {
        return true;
    }
    let severities = severities.unwrap_or_default().split(';');
    let messages = messages.unwrap_or_default().split(';');
    severities
        .zip(messages)
        .any(|(s, m)| s.parse::<u32>().map_or(true, |s| s >= WARNING) && !tolerated.contains(&m))
}

/// Number of frames in the capture `path` that match the display filter `filter`.
pub fn count(path: &Path, filter: &str) -> io::Result<usize> {
    let mut cmd = Command::new("tshark");
    cmd.args(["-n", "-r"])
        .arg(path)
        .args(["-Y", filter, "-T", "fields", "-e", "frame.number"]);
    let out = run_bounded(cmd, None, TSHARK_TIMEOUT)?;
    Ok(String::from_utf8_lossy(&out.stdout).lines().count())
}

#[cfg(test)]
mod tests {
    use super::counts;

    #[test]
    fn malformed_frames_and_warnings_count_unless_tolerated() {
        // malformed | severities | messages | frame | src | dst | info
        assert!(counts("1|||7|198.18.0.1|198.18.0.2|x", &[]));
        let warning = "|6291456|Bad length|7|198.18.0.2|198.18.0.1|x";
        assert!(counts(warning, &[]));
        assert!(!counts(warning, &["Bad length"]));
        let note_and_error = "|4194304;8388608|Just a note;Broken|9|a|b|x";
        assert!(counts(note_and_error, &["Just a note"]));
        assert!(!counts(note_and_error, &["Broken"]));
        assert!(!counts("|4194304|Just a note|9|a|b|x", &[]));
    }
}
