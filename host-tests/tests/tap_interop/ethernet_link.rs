//! The Ethernet Link object's interface counters (attribute 4) count the frames the board's
//! link task really receives and sends: pycomm3 reads them before and after traffic of known
//! kinds and counts (the peer's own), tshark's capture of the whole run bounds them from
//! above, and Get_And_Clear zeroes them; on the host board (TAP) and on the emulated board.

use std::path::Path;
use std::time::Duration;

use host_tests::capture;
use host_tests::peers;
use host_tests::rig::{Rig, BOARD_IP, BROADCAST_IP, TAP};
use serde_json::{json, Value};

use crate::common;

/// Unicast ListIdentity requests (each answered), broadcast datagrams, and frames of an
/// EtherType the board does not handle, that the peer sends between two readings.
const UNICAST: u32 = 20;
const NUCAST: u32 = 10;
const UNKNOWN: u32 = 5;
/// A unicast ListIdentity request on the wire: Ethernet, IPv4 and UDP headers, the
/// 24-byte encapsulation header, the FCS.
const LIST_IDENTITY_OCTETS: u32 = 14 + 20 + 8 + 24 + 4;
/// The smallest frame on the wire, FCS included.
const MIN_OCTETS: u32 = 64;

/// The eleven counters of attribute 4, from the peer's hex.
fn counters(out: &Value, key: &str) -> [u32; 11] {
    let hex = out[key]
        .as_str()
        .unwrap_or_else(|| panic!("{key} in {out}"));
    let bytes: Vec<u8> = (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
        .collect();
    assert_eq!(bytes.len(), 44, "{key}: {hex}");
    let mut c = [0u32; 11];
    for (v, chunk) in c.iter_mut().zip(bytes.chunks(4)) {
        *v = u32::from_le_bytes(chunk.try_into().unwrap());
    }
    c
}

const IN_OCTETS: usize = 0;
const IN_UCAST: usize = 1;
const IN_NUCAST: usize = 2;
const IN_ERRORS: usize = 4;
const IN_UNKNOWN: usize = 5;
const OUT_OCTETS: usize = 6;
const OUT_UCAST: usize = 7;
const OUT_NUCAST: usize = 8;

#[test]
#[ignore = "needs root, tshark and the Python peers"]
fn ethernet_link_counters_count_real_frames() {
    let name = "ethernet_link_counters";
    let out = counted_around_known_traffic(common::start(name));
    check_capture(&out, &common::scratch(&format!("{name}.pcapng")));
}

/// The same on the emulated board (LAN9118 in QEMU): the same firmware, another driver.
#[test]
#[ignore = "needs root, QEMU, tshark, the Python peers and ENIP_QEMU_POSITION_SERVO_ELF"]
fn ethernet_link_counters_count_real_frames_qemu() {
    let Some(elf) = host_tests::rig::qemu_elf("position-servo") else {
        return;
    };
    let pcap = common::scratch("ethernet_link_counters_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("boot: {e}"));
    let out = counted_around_known_traffic(rig);
    check_capture(&out, &pcap);
}

/// Runs the peer on `rig`'s board, checks what it read against its own traffic, stops the
/// rig (checking its capture dissects cleanly); returns the peer's report.
fn counted_around_known_traffic(rig: Rig) -> Value {
    let input = json!({
        "host": BOARD_IP.to_string(),
        "broadcast": BROADCAST_IP.to_string(),
        "iface": TAP,
        "unicast": UNICAST,
        "nucast": NUCAST,
        "unknown": UNKNOWN,
    });
    let out = peers::run(
        rig.ns(),
        "ethernet_link_counters.py",
        &input,
        Duration::from_secs(60),
    )
    .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    eprintln!("peer: {out}");
    let (before, after) = (counters(&out, "before"), counters(&out, "after"));
    let moved = |i: usize| after[i].wrapping_sub(before[i]);
    let replies = out["replies"].as_u64().unwrap() as u32;
    assert_eq!(replies, UNICAST, "every ListIdentity answered: {out}");

    // At least the peer's own frames moved each counter, besides pycomm3's TCP segments.
    assert!(moved(IN_UCAST) >= UNICAST, "in unicast: {out}");
    assert!(moved(IN_NUCAST) >= NUCAST, "in non-unicast: {out}");
    assert!(moved(IN_UNKNOWN) >= UNKNOWN, "in unknown protocols: {out}");
    let octets_in = UNICAST * LIST_IDENTITY_OCTETS + (NUCAST + UNKNOWN) * MIN_OCTETS;
    assert!(moved(IN_OCTETS) >= octets_in, "in octets: {out}");
    assert!(moved(OUT_UCAST) >= replies, "out unicast: {out}");
    assert!(
        moved(OUT_OCTETS) >= replies * LIST_IDENTITY_OCTETS,
        "out octets: {out}"
    );

    // Get_And_Clear answers the counts at that moment (no fewer than just read), then they
    // start again from zero: the next reading holds only the few frames since.
    let (cleared, since) = (counters(&out, "cleared"), counters(&out, "after_clear"));
    for i in [
        IN_OCTETS, IN_UCAST, IN_NUCAST, IN_UNKNOWN, OUT_OCTETS, OUT_UCAST,
    ] {
        assert!(cleared[i] >= after[i], "counter {i} at the clear: {out}");
    }
    assert!(
        since[IN_UCAST] <= 4,
        "unicast frames since the clear: {out}"
    );
    assert!(
        since[OUT_UCAST] <= 4,
        "unicast frames sent since the clear: {out}"
    );
    assert!(since[IN_OCTETS] < cleared[IN_OCTETS], "{out}");
    let media = out["media"].as_str().unwrap();
    assert_eq!(
        media,
        "0".repeat(96),
        "no MAC-level error on an emulated link"
    );

    common::finish(rig);
    out
}

/// Everything the board counted up to the peer's "after" reading (nothing was cleared
/// before it) is in the capture of the whole run, `pcap`.
fn check_capture(out: &Value, pcap: &Path) {
    let after = counters(out, "after");
    let mac = out["mac"].as_str().unwrap();
    let mac: Vec<String> = (0..6).map(|i| mac[2 * i..2 * i + 2].to_string()).collect();
    let mac = mac.join(":");
    let captured = |filter: String| capture::count(pcap, &filter).expect("read capture") as u32;
    let to_board = format!("(eth.dst == {mac} || eth.dst.ig == 1) && eth.src != {mac}");
    let received = captured(to_board.clone());
    let counted_in = after[IN_UCAST] + after[IN_NUCAST] + after[IN_UNKNOWN] + after[IN_ERRORS];
    assert!(
        counted_in <= received,
        "counted {counted_in} frames in, the capture holds {received}"
    );
    let unknown = captured(format!("({to_board}) && !ip && !arp && !lldp"));
    assert!(
        after[IN_UNKNOWN] <= unknown,
        "unknown: {unknown} captured, {out}"
    );
    let sent = captured(format!("eth.src == {mac}"));
    let counted_out = after[OUT_UCAST] + after[OUT_NUCAST];
    assert!(
        counted_out <= sent,
        "counted {counted_out} frames out, the capture holds {sent}"
    );
}
