//! [`StopFile`]: a run that may end early when another process creates a file, e.g. the
//! benchmark's trace reader once it has counted what it wanted.

use std::path::PathBuf;
use std::time::{Duration, Instant};

/// How often the file is looked for: a run at thousands of packets a second pays one `stat`
/// per period, not one per packet.
pub const LOOK_EVERY: Duration = Duration::from_millis(50);

/// The file whose existence ends a run early (`None`: the run goes its whole length).
#[derive(Debug, Clone)]
pub struct StopFile {
    path: Option<PathBuf>,
    next_look: Instant,
}

impl StopFile {
    /// Ends the run once `path` exists (never with `None`).
    pub fn new(path: Option<PathBuf>) -> StopFile {
        StopFile {
            path,
            next_look: Instant::now(),
        }
    }

    /// True once the file exists; looks at most every [`LOOK_EVERY`].
    pub fn asked(&mut self) -> bool {
        let Some(path) = &self.path else {
            return false;
        };
        let now = Instant::now();
        if now < self.next_look {
            return false;
        }
        self.next_look = now + LOOK_EVERY;
        path.exists()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn none_never_stops_and_a_file_stops_once_it_exists() {
        assert!(!StopFile::new(None).asked());
        let path = std::env::temp_dir().join(format!("stop-file-test-{}", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let mut stop = StopFile::new(Some(path.clone()));
        assert!(!stop.asked());
        std::fs::write(&path, b"").unwrap();
        // Seen within a few periods (looked at once a period).
        let seen = (0..20).any(|_| {
            std::thread::sleep(LOOK_EVERY / 2);
            stop.asked()
        });
        std::fs::remove_file(&path).unwrap();
        assert!(seen);
    }
}
