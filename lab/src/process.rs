//! Child processes with bounded waits: one-shot commands with a deadline, and long-running
//! children (the board, tshark) whose output is collected line by line (and optionally
//! written to a log file) and which are stopped, by their own process id, when dropped.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

use rustix::process::{kill_process, Pid, Signal};

/// How often a waiting loop looks at a child.
const POLL: Duration = Duration::from_millis(20);
/// How long output is still collected after a child ended.
const PIPE_GRACE: Duration = Duration::from_secs(2);

/// SIGINT, as [`signal`] and [`LoggedChild::stop`] take it.
pub const SIGINT: i32 = Signal::INT.as_raw();
/// SIGTERM.
pub const SIGTERM: i32 = Signal::TERM.as_raw();
/// SIGKILL.
pub const SIGKILL: i32 = Signal::KILL.as_raw();

/// Sends the signal numbered `sig` to process `pid` (errors, e.g. an already gone process,
/// are ignored, and so are a pid or signal number that are not one).
pub fn signal(pid: i32, sig: i32) {
    if let (Some(pid), Some(sig)) = (Pid::from_raw(pid), Signal::from_named_raw(sig)) {
        let _ = kill_process(pid, sig);
    }
}

/// Runs `cmd` to completion with `stdin` as input, killing it after `timeout`.
pub fn run_bounded(
    mut cmd: Command,
    stdin: Option<&[u8]>,
    timeout: Duration,
) -> io::Result<Output> {
    cmd.stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn()?;
    let input = stdin.unwrap_or_default().to_vec();
    let mut pipe_in = child.stdin.take();
    // Detached: a child that never reads its input must not hold this function up.
    thread::spawn(move || {
        if let Some(p) = pipe_in.as_mut() {
            // A child that exits without reading its input is not an error here.
            let _ = p.write_all(&input);
        }
    });
    let out = drain(child.stdout.take());
    let err = drain(child.stderr.take());
    let status = wait_until(&mut child, Instant::now() + timeout)?;
    let (stdout, stderr) = (collect(&out), collect(&err));
    match status {
        Some(status) => Ok(Output {
            status,
            stdout,
            stderr,
        }),
        None => Err(io::Error::new(
            io::ErrorKind::TimedOut,
            format!(
                "{cmd:?} still running after {timeout:?}; killed. stderr: {}",
                String::from_utf8_lossy(&stderr)
            ),
        )),
    }
}

/// Waits for `child` until `deadline`; kills it (by pid) and returns `None` if it is late.
fn wait_until(child: &mut Child, deadline: Instant) -> io::Result<Option<ExitStatus>> {
    loop {
        if let Some(s) = child.try_wait()? {
            return Ok(Some(s));
        }
        if Instant::now() >= deadline {
            child.kill()?;
            child.wait()?;
            return Ok(None);
        }
        thread::sleep(POLL);
    }
}

/// Reads `pipe` to its end on a thread; the bytes arrive on the returned channel.
fn drain(pipe: Option<impl Read + Send + 'static>) -> Receiver<Vec<u8>> {
    let (tx, rx) = mpsc::channel();
    thread::spawn(move || {
        let mut buf = Vec::new();
        if let Some(mut p) = pipe {
            let _ = p.read_to_end(&mut buf);
        }
        let _ = tx.send(buf);
    });
    rx
}

/// What a [`drain`] thread read, waiting at most [`PIPE_GRACE`] (a grandchild may still hold
/// the pipe open after the child ended).
fn collect(rx: &Receiver<Vec<u8>>) -> Vec<u8> {
    rx.recv_timeout(PIPE_GRACE).unwrap_or_default()
}

/// A long-running child whose stdout and stderr lines are logged and can be waited for.
#[derive(Debug)]
pub struct LoggedChild {
    name: String,
    child: Child,
    lines: Receiver<String>,
    log: Arc<Mutex<Vec<String>>>,
}

impl LoggedChild {
    /// Spawns `cmd` under the label `name`, collecting its output.
    pub fn spawn(name: &str, cmd: Command) -> io::Result<Self> {
        Self::spawn_logged(name, cmd, None)
    }

    /// Like [`LoggedChild::spawn`], also writing every output line to the file `log` if given
    /// (created afresh).
    pub fn spawn_logged(name: &str, mut cmd: Command, log_file: Option<&Path>) -> io::Result<Self> {
        let file = log_file.map(File::create).transpose()?;
        let file = Arc::new(Mutex::new(file));
        cmd.stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = cmd.spawn()?;
        let (tx, lines) = mpsc::channel();
        let log = Arc::new(Mutex::new(Vec::new()));
        let out = child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>);
        let err = child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>);
        for pipe in [out, err].into_iter().flatten() {
            let (tx, log, file) = (tx.clone(), Arc::clone(&log), Arc::clone(&file));
            thread::spawn(move || {
                for line in BufReader::new(pipe).lines().map_while(Result::ok) {
                    if let Ok(mut l) = log.lock() {
                        l.push(line.clone());
                    }
                    if let Ok(mut f) = file.lock() {
                        if let Some(f) = f.as_mut() {
                            // The file is a convenience copy; the lines are kept in memory.
                            let _ = writeln!(f, "{line}");
                        }
                    }
                    let _ = tx.send(line);
                }
            });
        }
        Ok(LoggedChild {
            name: name.to_string(),
            child,
            lines,
            log,
        })
    }

    /// Waits up to `timeout` for an output line containing `needle`; fails if the child
    /// exits or stays silent about it.
    pub fn wait_for_line(&mut self, needle: &str, timeout: Duration) -> io::Result<String> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self
                .lines
                .recv_timeout(left.min(Duration::from_millis(200)))
            {
                Ok(line) if line.contains(needle) => return Ok(line),
                Ok(_) | Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(self.failure(&format!("exited before printing {needle:?}")))
                }
            }
            if let Some(s) = self.child.try_wait()? {
                return Err(self.failure(&format!("exited ({s}) before printing {needle:?}")));
            }
            if left.is_zero() {
                return Err(self.failure(&format!("did not print {needle:?} within {timeout:?}")));
            }
        }
    }

    /// The child's process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// The exit status, if the child has already ended.
    pub fn exited(&mut self) -> Option<ExitStatus> {
        self.child.try_wait().ok().flatten()
    }

    /// Everything the child printed so far.
    pub fn output(&self) -> String {
        self.log.lock().map(|l| l.join("\n")).unwrap_or_default()
    }

    /// The last `n` lines the child printed.
    pub fn tail(&self, n: usize) -> String {
        let Ok(l) = self.log.lock() else {
            return String::new();
        };
        l[l.len().saturating_sub(n)..].join("\n")
    }

    /// Sends `sig`, waits up to `grace` for the child to end, then kills it.
    pub fn stop(&mut self, sig: i32, grace: Duration) {
        if self.exited().is_some() {
            return;
        }
        if let Ok(pid) = i32::try_from(self.child.id()) {
            signal(pid, sig);
        }
        if let Err(e) = wait_until(&mut self.child, Instant::now() + grace) {
            eprintln!("warning: stopping {}: {e}", self.name);
        }
    }

    fn failure(&self, what: &str) -> io::Error {
        io::Error::other(format!("{} {what}; output:\n{}", self.name, self.output()))
    }
}

impl Drop for LoggedChild {
    fn drop(&mut self) {
        self.stop(SIGTERM, Duration::from_secs(3));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_bounded_feeds_stdin_and_returns_output_and_status() {
        let mut c = Command::new("sh");
        c.args(["-c", "read x; echo out $x; echo err >&2; exit 3"]);
        let o = run_bounded(c, Some(b"in\n"), Duration::from_secs(10)).unwrap();
        assert_eq!(o.stdout, b"out in\n");
        assert_eq!(o.stderr, b"err\n");
        assert_eq!(o.status.code(), Some(3));
    }

    #[test]
    fn run_bounded_kills_a_late_child() {
        let mut c = Command::new("sleep");
        c.arg("30");
        let start = Instant::now();
        let e = run_bounded(c, None, Duration::from_millis(200)).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::TimedOut);
        assert!(start.elapsed() < Duration::from_secs(10), "{e}");
    }

    #[test]
    fn logged_child_waits_for_a_line_keeps_its_log_and_stops() {
        let file = std::env::temp_dir().join(format!("enip-lab-{}.log", std::process::id()));
        let mut c = Command::new("sh");
        // One pipe: the lines arrive in order (stdout and stderr are read apart).
        c.args(["-c", "echo one; echo two; exec sleep 30"]);
        let mut child = LoggedChild::spawn_logged("sh", c, Some(&file)).unwrap();
        let line = child.wait_for_line("two", Duration::from_secs(10)).unwrap();
        assert_eq!(line, "two");
        assert_eq!(child.tail(1), "two");
        assert_eq!(child.output(), "one\ntwo");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "one\ntwo\n");
        assert!(child.exited().is_none());
        child.stop(SIGTERM, Duration::from_secs(5));
        assert!(child.exited().is_some());
        let _ = std::fs::remove_file(&file);
    }

    #[test]
    fn wait_for_line_fails_when_the_child_ends_first() {
        let mut c = Command::new("sh");
        c.args(["-c", "echo nope >&2"]);
        let mut child = LoggedChild::spawn("sh", c).unwrap();
        let e = child
            .wait_for_line("ready", Duration::from_secs(10))
            .unwrap_err();
        assert!(e.to_string().contains("nope"), "{e}");
    }
}
