//! The TAP test rig: a fresh namespace holding a TAP device (198.18.0.1/24 on the kernel
//! side), optionally tshark capturing on it, and a board attached to the TAP at 198.18.0.2/24
//! with its own TCP/IP stack: the `enip-host` program or the emulated board in QEMU. Dropping the rig stops the board and tshark and
//! deletes the namespace, also when a test panics.

use std::io;
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::capture::Capture;
use crate::enip::{command, Header};
use crate::netns::Namespace;
use crate::process::LoggedChild;

/// The TAP device's name inside the namespace.
pub const TAP: &str = "enip0";
/// The kernel's address on the TAP (where every peer runs).
pub const HOST_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
/// The board's address (its own smoltcp stack, not a kernel address).
pub const BOARD_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
/// The subnet's directed broadcast address.
pub const BROADCAST_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 255);
/// Prefix length of the test subnet.
pub const PREFIX: u8 = 24;
/// The encapsulation port.
pub const ENCAP_PORT: u16 = 44818;
/// `ENIP_HOST_LINK=bind` runs the host board on kernel sockets over a veth pair.
pub const LINK_ENV: &str = "ENIP_HOST_LINK";
/// The board's end of the veth pair in bind mode (in the board's own namespace).
const BOARD_VETH: &str = "enipb0";
/// What the board prints once it serves.
pub const LISTENING: &str = "enip-host: listening on";
/// What any `enip_host::run` program prints once it serves (after its own name).
const PROGRAM_READY: &str = ": listening on";
/// How long the board may take to come up.
const BOARD_START: Duration = Duration::from_secs(10);
/// What the emulated board prints once its sockets listen.
const QEMU_READY: &str = "listening on";
/// How long QEMU may take to boot the emulated board.
const QEMU_BOOT: Duration = Duration::from_secs(30);
/// Reachability probes sent after start-up.
const PROBES: u32 = 40;
/// How long each probe waits for its answer.
const PROBE_WAIT: Duration = Duration::from_millis(250);

/// The board's encapsulation endpoint.
pub const fn board_addr() -> SocketAddr {
    SocketAddr::V4(SocketAddrV4::new(BOARD_IP, ENCAP_PORT))
}

/// A namespace with a TAP link, an optional capture on it, and the board on the other end.
/// Fields drop in order: board, capture, namespace, the board's own namespace (bind mode).
#[derive(Debug)]
pub struct Rig {
    board: LoggedChild,
    capture: Option<Capture>,
    ns: Namespace,
    /// Held only to be deleted last.
    _board_ns: Option<Namespace>,
}

impl Rig {
    /// Starts the host board `bin` with `--profile profile`, capturing into `capture` if given.
    pub fn start(bin: &Path, profile: &str, capture: Option<&Path>) -> io::Result<Self> {
        Self::start_with_args(bin, profile, &[], capture)
    }

    /// Like [`Rig::start`], with `extra` arguments for the board (e.g. `--nvram FILE`).
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
    /// `ENIP_HOST_LINK=bind` in the environment the board runs on kernel sockets instead
    /// ([`Rig::start_bind`]).
    pub fn start_at(
        bin: &Path,
        profile: &str,
        extra: &[&str],
        capture: Option<&Path>,
        board_ip: Ipv4Addr,
    ) -> io::Result<Self> {
        if std::env::var_os(LINK_ENV).is_some_and(|v| v == "bind") {
            return Self::start_bind(bin, profile, extra, capture);
        }
        Self::launch_at(
            capture,
            "enip-host",
            LISTENING,
            BOARD_START,
            board_ip,
            |ns| {
                let mut cmd = ns.command(bin);
                cmd.args(["--tap", TAP, "--ip", &format!("{BOARD_IP}/{PREFIX}")])
                    .args(["--profile", profile])
                    .args(extra)
                    .env(
                        "RUST_LOG",
                        std::env::var("RUST_LOG").unwrap_or("info".into()),
                    );
                cmd
            },
        )
    }

    /// Starts the host board `bin` on kernel sockets (`--bind`): a veth pair between the
    /// peers' namespace (198.18.0.1/24, the capture's side) and a namespace of the board's own
    /// (198.18.0.2/24), so every frame crosses a link as on the TAP.
    pub fn start_bind(
        bin: &Path,
        profile: &str,
        extra: &[&str],
        capture: Option<&Path>,
    ) -> io::Result<Self> {
        let ns = Namespace::create()?;
        let board_ns = Namespace::create()?;
        ns.exec_checked(
            "ip",
            &[
                "link",
                "add",
                TAP,
                "type",
                "veth",
                "peer",
                "name",
                BOARD_VETH,
                "netns",
                board_ns.name(),
            ],
        )?;
        for (n, dev, ip) in [(&ns, TAP, HOST_IP), (&board_ns, BOARD_VETH, BOARD_IP)] {
            n.exec_checked(
                "ip",
                &["addr", "add", &format!("{ip}/{PREFIX}"), "dev", dev],
            )?;
            n.exec_checked("ip", &["link", "set", dev, "up"])?;
        }
        let capture = capture.map(|p| Capture::start(&ns, TAP, p)).transpose()?;
        let mut cmd = board_ns.command(bin);
        cmd.args(["--bind", &BOARD_IP.to_string(), "--profile", profile])
            .args(extra)
            .env(
                "RUST_LOG",
                std::env::var("RUST_LOG").unwrap_or("info".into()),
            );
        let mut board = LoggedChild::spawn("enip-host --bind", cmd)?;
        board.wait_for_line(LISTENING, BOARD_START)?;
        let rig = Rig {
            board,
            capture,
            ns,
            _board_ns: Some(board_ns),
        };
        rig.wait_reachable(BOARD_IP)?;
        Ok(rig)
    }

    /// Starts `bin`, a program built on `enip_host::run` (its own device, no `--profile`),
    /// capturing into `capture` if given.
    pub fn start_program(bin: &Path, capture: Option<&Path>) -> io::Result<Self> {
        Self::launch(capture, "program", PROGRAM_READY, BOARD_START, |ns| {
            let mut cmd = ns.command(bin);
            cmd.args(["--tap", TAP, "--ip", &format!("{BOARD_IP}/{PREFIX}")])
                .env(
                    "RUST_LOG",
                    std::env::var("RUST_LOG").unwrap_or("info".into()),
                );
            cmd
        })
    }

    /// Boots the emulated board's ELF `elf` in QEMU (mps2-an386, LAN9118 on the TAP; the ELF
    /// has 198.18.0.2/24 built in), capturing into `capture` if given.
    pub fn start_qemu(elf: &Path, capture: Option<&Path>) -> io::Result<Self> {
        Self::launch(capture, "qemu", QEMU_READY, QEMU_BOOT, |ns| {
            let mut cmd = ns.command("qemu-system-arm");
            cmd.args(["-M", "mps2-an386", "-nographic", "-kernel"])
                .arg(elf)
                .args(["-net", "nic,netdev=n0,model=lan9118", "-netdev"])
                .arg(format!("tap,id=n0,ifname={TAP},script=no,downscript=no"));
            cmd
        })
    }

    /// The namespace and TAP, the capture, then the board `board` builds, which must print
    /// `ready` within `start` and then answer ListIdentity.
    fn launch(
        capture: Option<&Path>,
        name: &str,
        ready: &str,
        start: Duration,
        board: impl FnOnce(&Namespace) -> Command,
    ) -> io::Result<Self> {
        Self::launch_at(capture, name, ready, start, BOARD_IP, board)
    }

    /// [`Rig::launch`] for a board that answers at `board_ip`.
    fn launch_at(
        capture: Option<&Path>,
        name: &str,
        ready: &str,
        start: Duration,
        board_ip: Ipv4Addr,
        board: impl FnOnce(&Namespace) -> Command,
    ) -> io::Result<Self> {
        let ns = Namespace::create()?;
        ns.exec_checked("ip", &["tuntap", "add", "dev", TAP, "mode", "tap"])?;
        ns.exec_checked(
            "ip",
            &["addr", "add", &format!("{HOST_IP}/{PREFIX}"), "dev", TAP],
        )?;
        ns.exec_checked("ip", &["link", "set", TAP, "up"])?;
        let capture = capture.map(|p| Capture::start(&ns, TAP, p)).transpose()?;
        let mut board = LoggedChild::spawn(name, board(&ns))?;
        board.wait_for_line(ready, start)?;
        let rig = Rig {
            board,
            capture,
            ns,
            _board_ns: None,
        };
        rig.wait_reachable(board_ip)?;
        Ok(rig)
    }

    /// Waits (bounded) until the board answers a unicast ListIdentity, so that address
    /// resolution and start-up are over before a test measures anything.
    fn wait_reachable(&self, board_ip: Ipv4Addr) -> io::Result<()> {
        let board = SocketAddrV4::new(board_ip, ENCAP_PORT);
        let probe = Header::new(command::LIST_IDENTITY).frame(&[]);
        let answered = self.ns.inside(|| -> io::Result<bool> {
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
        &self.ns
    }

    /// Everything the board logged so far.
    pub fn board_log(&self) -> String {
        self.board.output()
    }

    /// Stops the board (failing if it had died on its own) and the capture; returns the
    /// capture file, if any.
    pub fn finish(mut self) -> io::Result<Option<PathBuf>> {
        if let Some(status) = self.board.exited() {
            return Err(io::Error::other(format!(
                "the board died during the test ({status}); log:\n{}",
                self.board.output()
            )));
        }
        self.board.stop(libc::SIGTERM, Duration::from_secs(3));
        Ok(self.capture.take().map(Capture::stop))
    }
}
