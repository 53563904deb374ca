//! The emulated board: `qemu-system-arm -M mps2-an386` running the `enip-qemu-mps2` ELF with
//! its LAN9118 on a TAP device inside a [`Lab`] namespace, and `cargo xtask qemu`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use crate::boards;
use crate::netns::{Lab, BOARD_CIDR};
use crate::setup;
use crate::util::{self, err, interrupted, Result};

/// What the board logs once its sockets listen.
const READY: &str = "listening on";
/// The longest a boot may take before it counts as failed.
const BOOT_TIMEOUT: Duration = Duration::from_secs(20);
/// `cargo xtask qemu` stops the board after this long at the latest.
const INTERACTIVE_LIMIT: Duration = Duration::from_secs(3600);

/// A running emulated board; stopped (killed and reaped) when dropped.
pub struct Qemu {
    child: Child,
    log: PathBuf,
}

impl Qemu {
    /// Boots `elf` attached to the TAP of `lab`, its UART going to `log`, and waits until the
    /// board says it listens.
    pub fn boot(lab: &Lab, elf: &Path, log: &Path) -> Result<Qemu> {
        Qemu::boot_with(lab, elf, log, &[])
    }

    /// Like [`Qemu::boot`], with `extra` arguments for QEMU (e.g. its `-d` logging).
    pub fn boot_with(lab: &Lab, elf: &Path, log: &Path, extra: &[&str]) -> Result<Qemu> {
        let file = fs::File::create(log)?;
        let mut cmd = lab.command("qemu-system-arm");
        cmd.args(["-M", "mps2-an386", "-nographic", "-kernel"])
            .arg(elf)
            .args(["-net", "nic,netdev=n0,model=lan9118", "-netdev"])
            .arg(format!(
                "tap,id=n0,ifname={},script=no,downscript=no",
                lab.tap
            ))
            .args(extra)
            .stdin(Stdio::null())
            .stdout(file.try_clone()?)
            .stderr(file);
        println!("$ {}  (log: {})", util::show(&cmd), log.display());
        let mut qemu = Qemu {
            child: cmd.spawn()?,
            log: log.to_path_buf(),
        };
        let start = Instant::now();
        while !qemu.log_text().contains(READY) {
            if let Some(status) = qemu.child.try_wait()? {
                return err(format!("QEMU exited during boot ({status})"));
            }
            if start.elapsed() > BOOT_TIMEOUT || interrupted() {
                return err(format!("the board did not come up in {BOOT_TIMEOUT:?}"));
            }
            sleep(Duration::from_millis(100));
        }
        Ok(qemu)
    }

    /// Everything the board logged so far.
    pub fn log_text(&self) -> String {
        fs::read_to_string(&self.log).unwrap_or_default()
    }

    /// Fails if QEMU exited or the board panicked.
    pub fn check_alive(&mut self) -> Result {
        if let Some(status) = self.child.try_wait()? {
            return err(format!("QEMU exited ({status})"));
        }
        if self.log_text().contains("PANIC") {
            return err("the board panicked");
        }
        Ok(())
    }

    /// Prints the last `n` lines of the board's log.
    pub fn print_log_tail(&self, n: usize) {
        let text = self.log_text();
        let lines: Vec<&str> = text.lines().collect();
        println!("--- last lines of {} ---", self.log.display());
        for l in lines.iter().skip(lines.len().saturating_sub(n)) {
            println!("  | {l}");
        }
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Installs QEMU if it is missing (Debian package `qemu-system-arm`).
pub fn ensure_installed() -> Result {
    if util::have("qemu-system-arm") {
        return Ok(());
    }
    setup::apt_install(&["qemu-system-arm"])
}

/// Fails unless running as root (network namespaces and TAP devices need it).
pub fn require_root(what: &str) -> Result {
    if util::is_root() {
        Ok(())
    } else {
        err(format!(
            "{what}: network namespaces need root; run it as root (or with sudo)"
        ))
    }
}

/// `cargo xtask qemu [--profile NAME]`: builds the board, boots it in namespace `enip-qemu`
/// (TAP `enipqemu0`, the board at 198.18.0.2/24) and keeps it running until Ctrl-C.
pub fn run_interactive(profile: &str) -> Result {
    require_root("qemu")?;
    util::catch_interrupts();
    setup::rust_target()?;
    ensure_installed()?;
    let elf = boards::build(boards::QEMU, profile)?;
    let dir = util::target_dir().join("qemu");
    fs::create_dir_all(&dir)?;
    let lab = Lab::create("enip-qemu", "enipqemu0")?;
    let mut qemu = Qemu::boot(&lab, &elf, &dir.join("board.log"))?;
    qemu.print_log_tail(5);
    println!(
        "\nThe emulated board runs profile {profile} at {BOARD_CIDR} in namespace {ns}. \
         Talk to it from there, e.g.\n  ip netns exec {ns} {python} -c \
         \"from pycomm3 import CIPDriver; print(CIPDriver.list_identity('198.18.0.2'))\"\n\
         Ctrl-C stops it (it stops by itself after {limit} min).",
        ns = lab.name,
        python = setup::venv_python().display(),
        limit = INTERACTIVE_LIMIT.as_secs() / 60,
    );
    let start = Instant::now();
    while !interrupted() && start.elapsed() < INTERACTIVE_LIMIT {
        qemu.check_alive()?;
        sleep(Duration::from_millis(200));
    }
    qemu.print_log_tail(10);
    drop(qemu);
    drop(lab);
    println!("qemu: board stopped, namespace enip-qemu deleted");
    Ok(())
}
