//! The QEMU board (`qemu-system-arm -M mps2-an386`, LAN9118 on a TAP) as a target of the
//! PositionServo scenarios: a fresh namespace with the TAP at 198.18.0.1/24, a capture, and
//! the ELF (which has 198.18.0.2/24 built in). Dropping it stops QEMU and tshark and deletes
//! the namespace.

use std::io;
use std::net::{SocketAddrV4, UdpSocket};
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::position_servo::Target;
use host_tests::capture::{self, Capture};
use host_tests::enip::{command, Header};
use host_tests::netns::Namespace;
use host_tests::process::LoggedChild;
use host_tests::rig::{board_addr, HOST_IP, PREFIX, TAP};

/// Expert messages expected because the board restarts on the Identity Reset of example
/// 6.3: the pre-reset TCP connection's next segment gets a reset from the new board.
const RESTART: &[&str] = &["Connection reset (RST)"];
/// What the board prints once its sockets listen.
const READY: &str = "listening on";
/// How long QEMU may take to boot the board.
const BOOT: Duration = Duration::from_secs(30);
/// ListIdentity probes after boot, each waiting this long.
const PROBES: u32 = 40;
const PROBE_WAIT: Duration = Duration::from_millis(250);

/// The emulated board in its namespace. Fields drop in order: board, capture, namespace.
pub struct QemuBoard {
    board: LoggedChild,
    capture: Option<Capture>,
    pcap: PathBuf,
    ns: Namespace,
}

impl Target for QemuBoard {
    fn ns(&self) -> &Namespace {
        &self.ns
    }
    fn log(&self) -> String {
        self.board.output()
    }
    fn restarts_on_reset(&self) -> bool {
        true
    }
    fn slack_ms(&self) -> f64 {
        40.0
    }
}

impl QemuBoard {
    /// Boots `elf` and waits until it answers a ListIdentity.
    pub fn boot(elf: &Path) -> io::Result<Self> {
        let ns = Namespace::create()?;
        ns.exec_checked("ip", &["tuntap", "add", "dev", TAP, "mode", "tap"])?;
        ns.exec_checked(
            "ip",
            &["addr", "add", &format!("{HOST_IP}/{PREFIX}"), "dev", TAP],
        )?;
        ns.exec_checked("ip", &["link", "set", TAP, "up"])?;
        let pcap = crate::position_servo::pcap("position_servo_qemu");
        let capture = Some(Capture::start(&ns, TAP, &pcap)?);
        let mut cmd = ns.command("qemu-system-arm");
        cmd.args(["-M", "mps2-an386", "-nographic", "-kernel"])
            .arg(elf)
            .args(["-net", "nic,netdev=n0,model=lan9118", "-netdev"])
            .arg(format!("tap,id=n0,ifname={TAP},script=no,downscript=no"));
        let mut board = LoggedChild::spawn("qemu", cmd)?;
        board.wait_for_line(READY, BOOT)?;
        let qemu = QemuBoard {
            board,
            capture,
            pcap,
            ns,
        };
        qemu.wait_reachable()?;
        Ok(qemu)
    }

    fn wait_reachable(&self) -> io::Result<()> {
        let probe = Header::new(command::LIST_IDENTITY).frame(&[]);
        let answered = self.ns.inside(|| -> io::Result<bool> {
            let s = UdpSocket::bind(SocketAddrV4::new(HOST_IP, 0))?;
            s.set_read_timeout(Some(PROBE_WAIT))?;
            let mut buf = [0u8; 512];
            for _ in 0..PROBES {
                s.send_to(&probe, board_addr())?;
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
                "the QEMU board does not answer ListIdentity; log:\n{}",
                self.board.output()
            )))
        }
    }

    /// Stops the board (failing if it died or panicked) and checks the capture like the host
    /// tests do: every frame dissects cleanly (bar the [`RESTART`] reset). Returns the
    /// capture file.
    pub fn finish(mut self) -> PathBuf {
        let log = self.board.output();
        assert!(
            self.board.exited().is_none(),
            "QEMU exited during the test:\n{log}"
        );
        assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
        self.board.stop(libc::SIGTERM, Duration::from_secs(3));
        if let Some(c) = self.capture.take() {
            c.stop();
        }
        let enip = capture::count(&self.pcap, "enip").expect("read capture");
        assert!(enip > 0, "no EtherNet/IP frame in {}", self.pcap.display());
        let bad = capture::problems(&self.pcap, "", RESTART).expect("read capture");
        assert!(
            bad.is_empty(),
            "{}:\n{}",
            self.pcap.display(),
            bad.join("\n")
        );
        self.pcap.clone()
    }
}
