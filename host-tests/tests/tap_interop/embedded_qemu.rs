//! The emulated board's embedded guarantees, on its test image (`ENIP_QEMU_FAULTS_ELF`:
//! the generic profile built with `ENIP_TEST_FAULTS=on` and `ENIP_ACD=off`, whose
//! diagnostics object answers service 0x4B, "fault on purpose"):
//!
//! - the call stack's high-water mark is readable with pycomm3 (vendor class 0x3A0);
//! - a recursion that runs off the bottom of the stack ends in the HardFault handler (the
//!   board links with flip-link: the stack sits below the statics), which reports the
//!   overflow on the UART and resets the machine;
//! - an executor hung on purpose stops feeding the CMSDK watchdog: its NMI reports it, its
//!   second expiry resets the machine;
//! - a panic is reported and resets the machine.
//!
//! After each, the board boots again and answers ListIdentity and pycomm3. A second test
//! reads the high-water mark after 10 Class 1 connections at 1 ms (the rig reads it again
//! when it stops the board, as it does for every test on the emulated board).
//!
//! `ENIP_QEMU_FAULTS_MACHINE` boots the image on another of QEMU's machines (`mps2-an385`,
//! `mps2-an500`, `mps2-an505`: a test image built for it), `mps2-an386` by default.

use std::time::{Duration, Instant};

use host_tests::enip::{mr_request, Client};
use host_tests::netns::Namespace;
use host_tests::peers;
use host_tests::rig::{Board, Options, Rig, BOARD_IP};
use host_tests::scanner::{exchange, open_generic, Session};
use serde_json::{json, Value};

use crate::common::{NAME, REPLY};

/// The variable naming the test image.
const ELF_VAR: &str = "ENIP_QEMU_FAULTS_ELF";
/// Class 0x3A0 (a 16-bit logical class segment), instance 1.
const DIAGNOSTICS: [u8; 6] = [0x21, 0x00, 0xA0, 0x03, 0x24, 0x01];
/// The test image's "fault on purpose" service.
const PROVOKE: u8 = 0x4B;
/// What the board prints when it starts.
const BOOT: &str = "enip-qemu-mps2: booting";
/// How long a fault may take to be reported: the watchdog's NMI comes after one 2 s stage.
const REPORTED: Duration = Duration::from_secs(6);
/// How long the reset and the new boot may take after the report (the watchdog's second
/// stage is 2 s).
const REBOOTED: Duration = Duration::from_secs(15);

/// Class 1 load of the second test: connections, RPI, timeout multiplier code (5: x128, as
/// the smoke run's, for an emulated board on a shared host) and how long.
const CONNECTIONS: usize = 10;
const RPI: Duration = Duration::from_millis(1);
const MULTIPLIER: u8 = 5;
const LOAD: Duration = Duration::from_secs(4);

/// The diagnostics object read with pycomm3 once the board answers a pycomm3 ListIdentity
/// (waiting up to `wait` for it).
fn diagnostics(ns: &Namespace, wait: u64) -> Value {
    let input = json!({"host": "198.18.0.2", "wait": wait});
    let timeout = Duration::from_secs(wait + 20);
    peers::run(ns, "board_diagnostics.py", &input, timeout)
        .unwrap_or_else(|e| panic!("pycomm3 reading the diagnostics object: {e}"))
}

/// Asks the board to fault with `kind` (1 hang, 2 stack overflow, 3 panic); no reply is
/// expected.
fn provoke(ns: &Namespace, kind: u8) {
    let mut c = Client::connect(ns, REPLY).expect("connect");
    c.register(REPLY).expect("register");
    let _ = c.request(
        &mr_request(PROVOKE, &DIAGNOSTICS, &[kind]),
        Duration::from_millis(500),
    );
}

/// Waits until the board's log holds `needle` at least `count` times; returns how long.
fn wait_for_log(rig: &Rig, needle: &str, count: usize, within: Duration) -> Duration {
    let start = Instant::now();
    while rig.board_log().matches(needle).count() < count {
        assert!(
            start.elapsed() < within,
            "no {count} x {needle:?} in the log within {within:?}:\n{}",
            rig.board_log()
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    start.elapsed()
}

/// The figures of a diagnostics reading, checked for sense.
fn stack_figures(d: &Value) -> (u64, u64, u64) {
    assert_eq!(d["product_name"], NAME, "{d}");
    let (size, painted, deepest) = (
        d["size"].as_u64().expect("size"),
        d["painted"].as_u64().expect("painted"),
        d["deepest"].as_u64().expect("deepest"),
    );
    assert!(
        0 < deepest && deepest < painted && painted <= size,
        "stack figures out of order: {d}"
    );
    (size, painted, deepest)
}

/// Boots the test image `elf` on the machine `ENIP_QEMU_FAULTS_MACHINE` names (mps2-an386
/// by default).
fn boot(elf: &std::path::Path) -> Rig {
    let machine = std::env::var("ENIP_QEMU_FAULTS_MACHINE").unwrap_or("mps2-an386".into());
    let board = Board::QemuMachine {
        machine: &machine,
        elf,
        extra: &[],
    };
    Rig::launch(board, &Options::default()).expect("boot the test image")
}

#[test]
#[ignore]
fn qemu_overflow_hang_and_panic_each_end_in_a_reset() {
    let Some(elf) = std::env::var_os(ELF_VAR) else {
        eprintln!("SKIPPED: set {ELF_VAR} to an enip-qemu-mps2 ELF built with ENIP_TEST_FAULTS=on");
        return;
    };
    let rig = boot(std::path::Path::new(&elf));
    let (size, painted, deepest) = stack_figures(&diagnostics(rig.ns(), 10));
    println!("stack at boot: {deepest} of {painted} painted bytes, region {size}");
    let cases: [(u8, &str, &str); 3] = [
        (2, "stack overflow", "HARDFAULT: stack overflow"),
        (1, "hung executor", "WATCHDOG: no progress"),
        (3, "panic", "PANIC: "),
    ];
    for (kind, what, report) in cases {
        let boots = rig.board_log().matches(BOOT).count();
        let start = Instant::now();
        provoke(rig.ns(), kind);
        let reported = wait_for_log(&rig, report, 1, REPORTED);
        wait_for_log(&rig, BOOT, boots + 1, REBOOTED);
        let back = diagnostics(rig.ns(), 15);
        stack_figures(&back);
        let log = rig.board_log();
        let line = log.lines().find(|l| l.contains(report)).unwrap_or_default();
        println!(
            "{what}: reported after {reported:?} ({line}), serving again (ListIdentity, \
             pycomm3) after {:?}",
            start.elapsed()
        );
    }
    let log = rig.board_log();
    assert!(log.contains("resetting"), "{log}");
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
}

#[test]
#[ignore]
fn qemu_stack_mark_after_ten_connections_at_1_ms() {
    let Some(elf) = std::env::var_os(ELF_VAR) else {
        eprintln!("SKIPPED: set {ELF_VAR} to an enip-qemu-mps2 ELF built with ENIP_TEST_FAULTS=on");
        return;
    };
    let mut rig = boot(std::path::Path::new(&elf));
    let (_, _, at_boot) = stack_figures(&diagnostics(rig.ns(), 10));
    let record = rig
        .ns()
        .inside(|| -> std::io::Result<_> {
            let mut s = Session::connect(BOARD_IP, REPLY)?;
            let opened = open_generic(&mut s, CONNECTIONS, RPI.as_micros() as u32, MULTIPLIER)?;
            exchange(BOARD_IP, &opened, RPI, LOAD, |k| [k as u8; 32])
        })
        .expect("namespace")
        .expect("10 connections at 1 ms");
    let received: usize = record.packets.values().map(Vec::len).sum();
    assert!(
        record.packets.len() == CONNECTIONS && received > 0,
        "T->O from {} connections, {received} packets",
        record.packets.len()
    );
    let (_, painted, after) = stack_figures(&diagnostics(rig.ns(), 5));
    assert!(after >= at_boot, "the mark went down: {at_boot} -> {after}");
    // The load neither starved the watchdog nor faulted.
    rig.check_alive()
        .unwrap_or_else(|e| panic!("{e}:\n{}", rig.board_log()));
    println!(
        "stack: {at_boot} bytes at boot, {after} after {CONNECTIONS} x 1 ms for {LOAD:?} \
         ({} O->T sent, {received} T->O received; {painted} painted)",
        record.sent
    );
    rig.finish().unwrap_or_else(|e| panic!("{e}"));
}
