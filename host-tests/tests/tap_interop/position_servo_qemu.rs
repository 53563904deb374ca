//! The QEMU board (`qemu-system-arm -M mps2-an386`, LAN9118 on a TAP) as a target of the
//! PositionServo scenarios: a fresh namespace with the TAP at 198.18.0.1/24, a capture, and
//! the ELF (which has 198.18.0.2/24 built in). Dropping it stops QEMU and tshark and deletes
//! the namespace.

use std::io;
use std::path::{Path, PathBuf};

use crate::position_servo::Target;
use host_tests::capture;
use host_tests::netns::Namespace;
use host_tests::rig::Rig;

/// Expert messages expected because the board restarts on the Identity Reset of example
/// 6.3: the pre-reset TCP connection's next segment gets a reset from the new board.
const RESTART: &[&str] = &["Connection reset (RST)"];
/// The emulated board in its rig, and where its capture goes.
pub struct QemuBoard {
    rig: Rig,
    pcap: PathBuf,
}

impl Target for QemuBoard {
    fn ns(&self) -> &Namespace {
        self.rig.ns()
    }
    fn log(&self) -> String {
        self.rig.board_log()
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
        let pcap = crate::position_servo::pcap("position_servo_qemu");
        let rig = Rig::start_qemu(elf, Some(&pcap))?;
        Ok(QemuBoard { rig, pcap })
    }

    /// Stops the board (failing if it died or panicked) and checks the capture like the host
    /// tests do: every frame dissects cleanly (bar the [`RESTART`] reset). Returns the
    /// capture file.
    pub fn finish(self) -> PathBuf {
        let log = self.rig.board_log();
        assert!(!log.contains("PANIC"), "the board panicked:\n{log}");
        self.rig.finish().unwrap_or_else(|e| panic!("{e}"));
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
