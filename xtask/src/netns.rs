//! A private network namespace holding one TAP device at 198.18.0.1/24, for running a board
//! (host binary or QEMU) and its peers where no traffic can leave. Deleted on drop.

use std::process::Command;

use crate::util::{run_quiet, Result};

/// The namespace side of the TAP link.
pub const SCANNER_CIDR: &str = "198.18.0.1/24";
/// The board's address on the link.
pub const BOARD_IP: &str = "198.18.0.2";
/// The board's address with its prefix.
pub const BOARD_CIDR: &str = "198.18.0.2/24";

/// A namespace with a TAP device, removed (with everything in it) when dropped.
pub struct Lab {
    /// Namespace name.
    pub name: String,
    /// TAP device name inside it.
    pub tap: String,
}

impl Lab {
    /// Creates namespace `name` (replacing a stale one) with TAP `tap` up at [`SCANNER_CIDR`].
    pub fn create(name: &str, tap: &str) -> Result<Lab> {
        delete(name);
        run_quiet(Command::new("ip").args(["netns", "add", name]))?;
        let lab = Lab {
            name: name.to_string(),
            tap: tap.to_string(),
        };
        lab.ip(&["link", "set", "lo", "up"])?;
        lab.ip(&["tuntap", "add", "dev", tap, "mode", "tap"])?;
        lab.ip(&["addr", "add", SCANNER_CIDR, "dev", tap])?;
        lab.ip(&["link", "set", tap, "up"])?;
        Ok(lab)
    }

    fn ip(&self, args: &[&str]) -> Result {
        run_quiet(self.command("ip").args(args))
    }

    /// A command that runs `program` inside the namespace.
    pub fn command(&self, program: &str) -> Command {
        let mut c = Command::new("ip");
        c.args(["netns", "exec", &self.name, program]);
        c
    }
}

impl Drop for Lab {
    fn drop(&mut self) {
        delete(&self.name);
    }
}

/// Deletes namespace `name` if it exists, killing what still runs in it.
pub fn delete(name: &str) {
    if let Ok(out) = Command::new("ip").args(["netns", "pids", name]).output() {
        for pid in String::from_utf8_lossy(&out.stdout).split_whitespace() {
            let _ = Command::new("kill").args(["-9", pid]).status();
        }
    }
    let _ = Command::new("ip")
        .args(["netns", "del", name])
        .stderr(std::process::Stdio::null())
        .status();
}
