//! The TAP rig: a [`Lab`] (a namespace holding a TAP device, 198.18.0.1/24 on the kernel
//! side), optionally tshark capturing on it, and a board attached to the TAP at 198.18.0.2/24
//! with its own TCP/IP stack: the `enip-host` program, a program built on `enip_host::run`,
//! or the emulated board in QEMU. These are the boards' only launchers. Dropping the rig
//! stops the board and tshark and deletes the namespace, also when a test panics.

use std::ffi::OsStr;
use std::io;
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use enip_stack::wire::encap::{command, EncapRepr, HEADER_LEN};
use enip_stack::wire::Writer;

use crate::capture::Capture;
use crate::netns::{Lab, Namespace};
use crate::process::{LoggedChild, SIGTERM};

pub use crate::netns::{BOARD_CIDR, BOARD_IP, BROADCAST_IP, HOST_IP, PREFIX};

/// The TAP device's name inside the namespace (unless [`Options::tap`] names another).
pub const TAP: &str = "enip0";
/// `ENIP_HOST_LINK=bind` runs every host board the tests start on kernel sockets
/// ([`Board::HostBind`]) instead of a TAP; `ENIP_HOST_LINK=fleet` the same, as one device of
/// a fleet of two in one process ([`Board::HostFleet`]).
pub const LINK_ENV: &str = "ENIP_HOST_LINK";
/// `ENIP_TAP_QEMU_ELF=<elf>` runs the tests that start the host board with the generic
/// profile and no extra arguments on that emulated board's ELF instead (e.g. the hostile
/// battery on the firmware, with its stack's high-water mark read at the end of each).
pub const QEMU_BOARD_ENV: &str = "ENIP_TAP_QEMU_ELF";
/// The other device of a [`Board::HostFleet`], at the next address.
pub const NEIGHBOUR_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 3);
/// The encapsulation port.
pub const ENCAP_PORT: u16 = enip_stack::config::ENCAP_PORT;
/// What the host board prints once it serves.
pub const LISTENING: &str = "enip-host: listening on";
/// What any `enip_host::run` program prints once it serves (after its own name).
const PROGRAM_READY: &str = ": listening on";
/// How long the host board (or a program) may take to come up.
const BOARD_START: Duration = Duration::from_secs(10);
/// What the emulated board prints once its sockets listen.
const QEMU_READY: &str = "listening on";
/// How long QEMU may take to boot the emulated board.
const QEMU_BOOT: Duration = Duration::from_secs(30);
/// What the emulated board prints when it panics, faults or its watchdog fires (each ends in
/// a reset).
const QEMU_FAULTS: [&str; 3] = ["PANIC", "HARDFAULT", "WATCHDOG"];
/// Reachability probes sent after start-up (15 s: a board that probes its address for
/// conflicts, as the emulated board's default image does, sends its first IP packet 6 to
/// 9 s after it starts).
const PROBES: u32 = 60;
/// How long each probe waits for its answer.
const PROBE_WAIT: Duration = Duration::from_millis(250);
/// How long a stopped board may take to end after SIGTERM.
const STOP_GRACE: Duration = Duration::from_secs(3);

/// The board's encapsulation endpoint.
pub const fn board_addr() -> SocketAddr {
    SocketAddr::V4(SocketAddrV4::new(BOARD_IP, ENCAP_PORT))
}

/// The variable naming the emulated board's ELF built with `profile`:
/// `ENIP_QEMU_<PROFILE>_ELF` (`position-servo` -> `ENIP_QEMU_POSITION_SERVO_ELF`).
pub fn qemu_elf_var(profile: &str) -> String {
    format!("ENIP_QEMU_{}_ELF", profile.to_uppercase().replace('-', "_"))
}

/// The emulated board's ELF built with `profile`, from [`qemu_elf_var`]; without it, says
/// loudly that the caller's QEMU test is skipped and returns `None`.
pub fn qemu_elf(profile: &str) -> Option<PathBuf> {
    let var = qemu_elf_var(profile);
    let elf = std::env::var_os(&var).map(PathBuf::from);
    if elf.is_none() {
        eprintln!("SKIPPED: set {var} to an enip-qemu-mps2 ELF built with the {profile} profile");
    }
    elf
}

/// A board the rig can start on its TAP.
#[derive(Debug, Clone, Copy)]
pub enum Board<'a> {
    /// The host board `bin` (`enip-host`) running `profile`, with `extra` arguments (e.g.
    /// `--nv-file PATH`); it comes up at `answers_at` (its `--ip` is [`BOARD_CIDR`] unless its
    /// non-volatile file says otherwise).
    Host {
        /// The `enip-host` binary.
        bin: &'a Path,
        /// Its `--profile`.
        profile: &'a str,
        /// More arguments.
        extra: &'a [&'a str],
        /// The address it answers at.
        answers_at: Ipv4Addr,
    },
    /// The host board `bin` on the kernel's sockets (`--bind 198.18.0.2`) running
    /// `profile` with `extra` arguments, in a namespace of its own joined to the peers' by a
    /// veth pair.
    HostBind {
        /// The `enip-host` binary.
        bin: &'a Path,
        /// Its `--profile`.
        profile: &'a str,
        /// More arguments.
        extra: &'a [&'a str],
    },
    /// Like [`Board::HostBind`], as the device `dut` of a device list (`--devices`) whose
    /// other device, `neighbour`, a generic one, serves at [`NEIGHBOUR_IP`] in the same
    /// process; `extra` may only be `--nv-file PATH` (the device's `nv_file`).
    HostFleet {
        /// The `enip-host` binary.
        bin: &'a Path,
        /// The profile of `dut`.
        profile: &'a str,
        /// More arguments.
        extra: &'a [&'a str],
    },
    /// A program built on `enip_host::run` (its own device, no `--profile`).
    Program {
        /// The program.
        bin: &'a Path,
    },
    /// The emulated board's ELF in QEMU (mps2-an386, LAN9118 on the TAP; the ELF has
    /// 198.18.0.2/24 built in).
    Qemu {
        /// The `enip-qemu-mps2` ELF.
        elf: &'a Path,
        /// More arguments for QEMU (e.g. its `-d` tracing).
        extra: &'a [&'a str],
    },
    /// Like [`Board::Qemu`], on another of QEMU's machines with the LAN9118 (`mps2-an385`,
    /// `mps2-an500`, `mps2-an505`): an `enip-qemu-mps2` ELF built for that machine.
    QemuMachine {
        /// QEMU's `-M`.
        machine: &'a str,
        /// The `enip-qemu-mps2` ELF built for it.
        elf: &'a Path,
        /// More arguments for QEMU.
        extra: &'a [&'a str],
    },
}

impl Board<'_> {
    /// The command that starts the board on `tap` inside `lab`.
    fn command(&self, lab: &Lab) -> io::Result<Command> {
        let log_level = std::env::var("RUST_LOG").unwrap_or("info".into());
        Ok(match *self {
            Board::Host {
                bin,
                profile,
                extra,
                ..
            } => {
                let mut cmd = host_command(lab, bin);
                cmd.args(["--profile", profile])
                    .args(extra)
                    .env("RUST_LOG", log_level);
                cmd
            }
            Board::HostBind {
                bin,
                profile,
                extra,
            } => {
                let mut cmd = lab.board_command(bin);
                cmd.args(["--bind", &BOARD_IP.to_string(), "--profile", profile])
                    .args(extra)
                    .env("RUST_LOG", log_level);
                cmd
            }
            Board::HostFleet {
                bin,
                profile,
                extra,
            } => {
                let list = fleet_list(profile, extra)?;
                lab.add_board_addresses(&[format!("{NEIGHBOUR_IP}/{PREFIX}")])?;
                let mut cmd = lab.board_command(bin);
                cmd.arg("--devices").arg(list).env("RUST_LOG", log_level);
                cmd
            }
            Board::Program { bin } => {
                let mut cmd = host_command(lab, bin);
                cmd.env("RUST_LOG", log_level);
                cmd
            }
            Board::Qemu { elf, extra } => qemu_command(lab, QEMU_MACHINE, elf, extra),
            Board::QemuMachine {
                machine,
                elf,
                extra,
            } => qemu_command(lab, machine, elf, extra),
        })
    }

    /// Its label in messages, what it prints once it serves, and how long that may take.
    fn start_up(&self) -> (&'static str, &'static str, Duration) {
        match self {
            Board::Host { .. } => ("enip-host", LISTENING, BOARD_START),
            Board::HostBind { .. } => ("enip-host --bind", LISTENING, BOARD_START),
            // The devices open in the list's order; the loop serves once the last has.
            Board::HostFleet { .. } => ("enip-host --devices", FLEET_READY, BOARD_START),
            Board::Program { .. } => ("program", PROGRAM_READY, BOARD_START),
            Board::Qemu { .. } | Board::QemuMachine { .. } => ("qemu", QEMU_READY, QEMU_BOOT),
        }
    }

    fn answers_at(&self) -> Ipv4Addr {
        match self {
            Board::Host { answers_at, .. } => *answers_at,
            Board::HostBind { .. }
            | Board::HostFleet { .. }
            | Board::Program { .. }
            | Board::Qemu { .. }
            | Board::QemuMachine { .. } => BOARD_IP,
        }
    }
}

/// The machine of [`Board::Qemu`].
const QEMU_MACHINE: &str = "mps2-an386";

/// `qemu-system-arm -M machine` inside `lab` booting `elf`, its LAN9118 on the lab's TAP,
/// with `extra` arguments.
fn qemu_command(lab: &Lab, machine: &str, elf: &Path, extra: &[&str]) -> Command {
    let mut cmd = lab.command("qemu-system-arm");
    cmd.args(["-M", machine, "-nographic", "-kernel"])
        .arg(elf)
        .args(["-net", "nic,netdev=n0,model=lan9118", "-netdev"])
        .arg(format!(
            "tap,id=n0,ifname={},script=no,downscript=no",
            lab.tap
        ))
        .args(extra);
    cmd
}

/// What a [`Board::HostFleet`] prints once its last device serves.
const FLEET_READY: &str = "enip-host: neighbour: listening on";

/// Writes the device list of a [`Board::HostFleet`] running `profile` with `extra`
/// arguments, in the target directory; returns its path.
fn fleet_list(profile: &str, extra: &[&str]) -> io::Result<PathBuf> {
    let nv = match extra {
        [] => String::new(),
        ["--nv-file", path] => format!("nv_file = {path:?}\n"),
        _ => {
            return Err(io::Error::other(format!(
                "a fleet's device takes no {extra:?} (only --nv-file PATH)"
            )))
        }
    };
    let list = format!(
        "[[device]]\nname = \"dut\"\naddress = \"{BOARD_IP}\"\nprofile = {profile:?}\n{nv}\n\
         [[device]]\nname = \"neighbour\"\naddress = \"{NEIGHBOUR_IP}\"\n\
         profile = \"generic\"\nserial_number = 2\n"
    );
    let dir = crate::paths::target_dir().join("tmp");
    std::fs::create_dir_all(&dir)?;
    let path = dir.join(format!("fleet-{}-{profile}.toml", std::process::id()));
    std::fs::write(&path, list)?;
    Ok(path)
}

/// `bin --tap TAP --ip 198.18.0.2/24 --acd off` inside `lab`: tests that are not about
/// Address Conflict Detection start without its seconds of probing (those that are pass
/// `--acd on` among their extra arguments, which come later and win).
fn host_command(lab: &Lab, bin: impl AsRef<OsStr>) -> Command {
    let mut cmd = lab.command(bin);
    cmd.args(["--tap", &lab.tap, "--ip", BOARD_CIDR, "--acd", "off"]);
    cmd
}

/// Where a rig runs and what it records besides the board's output in memory.
#[derive(Debug, Clone, Copy, Default)]
pub struct Options<'a> {
    /// A fixed namespace name (a stale one is replaced); `None` for a name of its own.
    pub namespace: Option<&'a str>,
    /// The TAP device's name; `None` for [`TAP`].
    pub tap: Option<&'a str>,
    /// A tshark capture of the TAP into this file.
    pub capture: Option<&'a Path>,
    /// A copy of the board's output in this file.
    pub log_file: Option<&'a Path>,
}

/// A namespace with a TAP link, an optional capture on it, and the board on the other end.
/// Fields drop in order: board, capture, namespace.
#[derive(Debug)]
pub struct Rig {
    board: LoggedChild,
    capture: Option<Capture>,
    lab: Lab,
    /// The emulated board's ELF, if the board is one: its stack is read before it stops.
    qemu_elf: Option<PathBuf>,
}

impl Rig {
    /// Starts the host board `bin` with `--profile profile`, capturing into `capture` if given.
    pub fn start(bin: &Path, profile: &str, capture: Option<&Path>) -> io::Result<Self> {
        Self::start_with_args(bin, profile, &[], capture)
    }

    /// Like [`Rig::start`], with `extra` arguments for the board (e.g. `--nv-file PATH`).
    pub fn start_with_args(
        bin: &Path,
        profile: &str,
        extra: &[&str],
        capture: Option<&Path>,
    ) -> io::Result<Self> {
        Self::start_at(bin, profile, extra, capture, BOARD_IP)
    }

    /// Like [`Rig::start_with_args`], for a board that comes up at `board_ip` (in
    /// 198.18.0.0/24) instead of its `--ip` (e.g. from its `--nv-file`). With
    /// `ENIP_HOST_LINK=bind` ([`LINK_ENV`]) the board runs on kernel sockets instead
    /// ([`Board::HostBind`]), always at 198.18.0.2.
    pub fn start_at(
        bin: &Path,
        profile: &str,
        extra: &[&str],
        capture: Option<&Path>,
        board_ip: Ipv4Addr,
    ) -> io::Result<Self> {
        if let Some(elf) = std::env::var_os(QEMU_BOARD_ENV) {
            if profile == "generic" && extra.is_empty() && board_ip == BOARD_IP {
                let elf = PathBuf::from(elf);
                return Self::start_qemu(&elf, capture);
            }
        }
        let link = std::env::var_os(LINK_ENV);
        if link.as_ref().is_some_and(|v| v == "bind") {
            let board = Board::HostBind {
                bin,
                profile,
                extra,
            };
            return Self::launch(board, &Options::capturing(capture));
        }
        if link.is_some_and(|v| v == "fleet") {
            let board = Board::HostFleet {
                bin,
                profile,
                extra,
            };
            return Self::launch(board, &Options::capturing(capture));
        }
        let board = Board::Host {
            bin,
            profile,
            extra,
            answers_at: board_ip,
        };
        Self::launch(board, &Options::capturing(capture))
    }

    /// Starts `bin`, a program built on `enip_host::run` (its own device, no `--profile`),
    /// capturing into `capture` if given.
    pub fn start_program(bin: &Path, capture: Option<&Path>) -> io::Result<Self> {
        Self::launch(Board::Program { bin }, &Options::capturing(capture))
    }

    /// Boots the emulated board's ELF `elf` in QEMU, capturing into `capture` if given.
    pub fn start_qemu(elf: &Path, capture: Option<&Path>) -> io::Result<Self> {
        Self::launch(
            Board::Qemu { elf, extra: &[] },
            &Options::capturing(capture),
        )
    }

    /// The namespace and TAP, the capture, then `board`, which must print that it serves
    /// within its start-up bound and then answer a ListIdentity.
    pub fn launch(board: Board<'_>, options: &Options<'_>) -> io::Result<Self> {
        let answers_at = board.answers_at();
        let rig = Self::launch_unverified(board, options)?;
        rig.wait_reachable(answers_at)?;
        Ok(rig)
    }

    /// Like [`Rig::launch`], returning once the board printed that it serves, without
    /// waiting for it to answer: for a board expected not to (its address taken by another
    /// host).
    pub fn launch_unverified(board: Board<'_>, options: &Options<'_>) -> io::Result<Self> {
        let tap = options.tap.unwrap_or(TAP);
        let lab = match (&board, options.namespace) {
            (Board::HostBind { .. } | Board::HostFleet { .. }, _) => Lab::create_veth(tap)?,
            (_, Some(name)) => Lab::create(name, tap)?,
            (_, None) => Lab::create_unique(tap)?,
        };
        let capture = options
            .capture
            .map(|p| Capture::start(lab.ns(), tap, p))
            .transpose()?;
        let (name, ready, bound) = board.start_up();
        let mut child = LoggedChild::spawn_logged(name, board.command(&lab)?, options.log_file)?;
        child.wait_for_line(ready, bound)?;
        let qemu_elf = match board {
            Board::Qemu { elf, .. } | Board::QemuMachine { elf, .. } => Some(elf.to_path_buf()),
            _ => None,
        };
        Ok(Rig {
            board: child,
            capture,
            lab,
            qemu_elf,
        })
    }

    /// Waits (bounded) until the board answers a unicast ListIdentity, so that address
    /// resolution and start-up are over before a test measures anything.
    fn wait_reachable(&self, board_ip: Ipv4Addr) -> io::Result<()> {
        let board = SocketAddrV4::new(board_ip, ENCAP_PORT);
        let mut probe = [0u8; HEADER_LEN];
        let header = EncapRepr {
            command: command::LIST_IDENTITY,
            length: 0,
            session_handle: 0,
            status: 0,
            sender_context: [0; 8],
            options: 0,
        };
        header
            .emit(&mut Writer::new(&mut probe))
            .map_err(|e| io::Error::other(format!("ListIdentity probe: {e}")))?;
        let answered = self.lab.ns().inside(|| -> io::Result<bool> {
            let s = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0))?;
            s.set_read_timeout(Some(PROBE_WAIT))?;
            let mut buf = [0u8; 512];
            for _ in 0..PROBES {
                s.send_to(&probe, board)?;
                if s.recv_from(&mut buf).is_ok() {
                    return Ok(true);
                }
            }
            Ok(false)
        })??;
        if answered {
            Ok(())
        } else {
            Err(io::Error::other(format!(
                "the board does not answer ListIdentity; log:\n{}",
                self.board.output()
            )))
        }
    }

    /// The namespace every peer must run in.
    pub fn ns(&self) -> &Namespace {
        self.lab.ns()
    }

    /// Everything the board logged so far.
    pub fn board_log(&self) -> String {
        self.board.output()
    }

    /// The last `n` lines the board logged.
    pub fn board_log_tail(&self, n: usize) -> String {
        self.board.tail(n)
    }

    /// Fails if the board exited or logged a panic, a HardFault or its watchdog firing.
    pub fn check_alive(&mut self) -> io::Result<()> {
        if let Some(status) = self.board.exited() {
            return Err(io::Error::other(format!("the board exited ({status})")));
        }
        let output = self.board.output();
        if let Some(fault) = QEMU_FAULTS.iter().find(|f| output.contains(**f)) {
            return Err(io::Error::other(format!("the board reported {fault}")));
        }
        Ok(())
    }

    /// Stops the board (failing if it had died on its own) and the capture; returns the
    /// capture file, if any. An emulated board's stack high-water mark is read and reported
    /// first ([`crate::diagnostics::report_stack_use`]).
    pub fn finish(mut self) -> io::Result<Option<PathBuf>> {
        if let Some(status) = self.board.exited() {
            return Err(io::Error::other(format!(
                "the board died during the test ({status}); log:\n{}",
                self.board.output()
            )));
        }
        if let Some(elf) = &self.qemu_elf {
            crate::diagnostics::report_stack_use(self.lab.ns(), elf);
        }
        self.board.stop(SIGTERM, STOP_GRACE);
        Ok(self.capture.take().map(Capture::stop))
    }
}

impl<'a> Options<'a> {
    /// A namespace of its own with the TAP [`TAP`], capturing into `capture` if given.
    pub fn capturing(capture: Option<&'a Path>) -> Self {
        Options {
            capture,
            ..Options::default()
        }
    }

    /// A namespace with a name of its own (two runs on one machine, e.g. two checkouts'
    /// tests or benchmarks, do not replace each other's) with the TAP `tap`, the board's
    /// output copied to `log`.
    pub fn logged(tap: &'a str, log: &'a Path) -> Self {
        Options {
            namespace: None,
            tap: Some(tap),
            capture: None,
            log_file: Some(log),
        }
    }

    /// The fixed namespace `namespace` with the TAP `tap`, the board's output copied to `log`
    /// (what a command run by hand uses, so its names are known and its log kept).
    pub fn named(namespace: &'a str, tap: &'a str, log: &'a Path) -> Self {
        Options {
            namespace: Some(namespace),
            tap: Some(tap),
            capture: None,
            log_file: Some(log),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn qemu_elf_variables_follow_the_profile_names() {
        assert_eq!(
            qemu_elf_var("position-servo"),
            "ENIP_QEMU_POSITION_SERVO_ELF"
        );
        assert_eq!(qemu_elf_var("generic"), "ENIP_QEMU_GENERIC_ELF");
    }
}
