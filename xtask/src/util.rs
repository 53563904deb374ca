//! Running commands with headers and timing, the step list with its summary, and small
//! helpers (paths, probing for programs, Ctrl-C).

use std::fmt;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, LazyLock};
use std::time::{Duration, Instant};

/// Why a command or step failed.
#[derive(Debug)]
pub struct Error(pub String);

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error(e.to_string())
    }
}

/// Result of an xtask operation.
pub type Result<T = ()> = std::result::Result<T, Error>;

/// Shorthand for an [`Error`] from a message.
pub fn err<T>(msg: impl Into<String>) -> Result<T> {
    Err(Error(msg.into()))
}

pub use enip_lab::paths::{root, target_dir};

/// The `cargo` the xtask was started by (or `cargo` from `PATH`).
pub fn cargo() -> Command {
    let mut c = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    c.current_dir(root());
    c
}

/// A `cargo` for a specific toolchain (`cargo +nightly ...`), bypassing the running cargo so
/// rustup picks the toolchain.
pub fn cargo_toolchain(toolchain: &str) -> Command {
    let mut c = Command::new("cargo");
    c.arg(format!("+{toolchain}")).current_dir(root());
    // The running cargo exports its own toolchain's variables; let rustup choose afresh.
    for v in ["RUSTC", "RUSTDOC", "CARGO", "RUSTUP_TOOLCHAIN"] {
        c.env_remove(v);
    }
    c
}

/// A printable form of `cmd`.
pub fn show(cmd: &Command) -> String {
    let mut s = cmd.get_program().to_string_lossy().into_owned();
    for a in cmd.get_args() {
        let a = a.to_string_lossy();
        if a.contains(' ') || a.is_empty() {
            s.push_str(&format!(" '{a}'"));
        } else {
            s.push(' ');
            s.push_str(&a);
        }
    }
    s
}

/// Runs `cmd` with inherited output; fails unless it exits 0.
pub fn run(cmd: &mut Command) -> Result {
    println!("$ {}", show(cmd));
    let status = cmd
        .status()
        .map_err(|e| Error(format!("cannot start `{}`: {e}", show(cmd))))?;
    check(cmd, status)
}

/// Runs `cmd` with output discarded; fails unless it exits 0.
pub fn run_quiet(cmd: &mut Command) -> Result {
    let status = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map_err(|e| Error(format!("cannot start `{}`: {e}", show(cmd))))?;
    check(cmd, status)
}

fn check(cmd: &Command, status: ExitStatus) -> Result {
    if status.success() {
        Ok(())
    } else {
        err(format!("`{}` failed ({status})", show(cmd)))
    }
}

/// The standard output of `cmd` if it runs and exits 0.
pub fn output(cmd: &mut Command) -> Option<String> {
    let out = cmd.stderr(Stdio::null()).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
}

/// True if `program` is an executable file on `PATH`.
pub fn have(program: &str) -> bool {
    let Some(path) = std::env::var_os("PATH") else {
        return false;
    };
    std::env::split_paths(&path).any(|dir| is_executable(&dir.join(program)))
}

fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    p.metadata()
        .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

/// True when running as root.
pub fn is_root() -> bool {
    output(Command::new("id").arg("-u")).is_some_and(|s| s.trim() == "0")
}

/// Prints a banner that stands out in a long CI log.
pub fn loud(msg: &str) {
    let bar = "!".repeat(78);
    println!("{bar}\n!! {msg}\n{bar}");
}

/// Seconds with one decimal.
pub fn secs(d: Duration) -> String {
    format!("{:.1} s", d.as_secs_f64())
}

/// How a step ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// It ran and succeeded.
    Passed,
    /// It could not run here (a tool or a test file is missing); said loudly.
    Skipped,
    /// It failed.
    Failed,
}

/// A sequence of steps, each with a header, a duration and an outcome, and a summary.
#[derive(Debug, Default)]
pub struct Steps {
    done: Vec<(String, Outcome, Duration)>,
}

impl Steps {
    /// Runs step `name`: `f` returns whether it ran (`Passed`) or was skipped (`Skipped`).
    /// Returns `false` if it failed.
    pub fn run(&mut self, name: &str, f: impl FnOnce() -> Result<Outcome>) -> bool {
        let n = self.done.len() + 1;
        println!("\n==> [{n}] {name}");
        let start = Instant::now();
        let outcome = match f() {
            Ok(_) if interrupted() => {
                println!("error: interrupted");
                Outcome::Failed
            }
            Ok(o) => o,
            Err(e) => {
                println!("error: {e}");
                Outcome::Failed
            }
        };
        let took = start.elapsed();
        let word = match outcome {
            Outcome::Passed => "ok",
            Outcome::Skipped => "SKIPPED",
            Outcome::Failed => "FAILED",
        };
        println!("<== [{n}] {name}: {word} in {}", secs(took));
        self.done.push((name.to_string(), outcome, took));
        outcome != Outcome::Failed
    }

    /// Prints every step and the closing `N passed, M failed` line; true if none failed.
    pub fn summary(&self) -> bool {
        println!("\nSummary:");
        for (name, outcome, took) in &self.done {
            println!("  {:<8} {:>9}  {name}", format!("{outcome:?}"), secs(*took));
        }
        let count = |o| self.done.iter().filter(|(_, x, _)| *x == o).count();
        let (passed, failed, skipped) = (
            count(Outcome::Passed),
            count(Outcome::Failed),
            count(Outcome::Skipped),
        );
        if skipped > 0 {
            println!("{passed} passed, {failed} failed, {skipped} skipped");
        } else {
            println!("{passed} passed, {failed} failed");
        }
        failed == 0
    }
}

/// Set by SIGINT or SIGTERM once [`catch_interrupts`] ran.
static INTERRUPTED: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));

/// Makes Ctrl-C (SIGINT) and SIGTERM set a flag instead of killing the xtask, so it can
/// clean up; children in the foreground process group still get the signal themselves.
pub fn catch_interrupts() {
    for s in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        if let Err(e) = signal_hook::flag::register(s, Arc::clone(&INTERRUPTED)) {
            loud(&format!("cannot catch signal {s}: {e}"));
        }
    }
}

/// True once SIGINT or SIGTERM arrived after [`catch_interrupts`].
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}
