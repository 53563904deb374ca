//! Address Conflict Detection: the input is a script of received Ethernet frames, each
//! `[milliseconds to wait: u8][length: u8][frame]`, run against the stack's `Acd` state
//! machine probing and then defending 198.18.0.2 (the link task's use of it). Every frame is
//! read as ARP by `Arp::from_frame` and, if it is one, processed; between frames the
//! machine sends what is due. Checked: what it sends parses back as its own ARP request
//! about the address, a conflict it reports round-trips through TCP/IP attribute 11's
//! bytes, it defends only an announced address, the address is usable only in the ongoing
//! phase, and a lost address stays lost.
#![no_main]

use std::net::Ipv4Addr;

use enip_stack::acd::{Acd, Arp, LastConflict, Phase, Verdict, ARP_FRAME_LEN};
use enip_stack::Instant;
use libfuzzer_sys::fuzz_target;

/// The adapter's MAC and address under test.
const MAC: [u8; 6] = [0x02, 0x00, 0x5E, 0x10, 0x00, 0x02];
const IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);

/// What the machine sends at `now`, checked to be its own ARP request about [`IP`].
fn dispatch(acd: &mut Acd, now: Instant) {
    while let Some(frame) = acd.dispatch(now) {
        let mut buf = [0u8; ARP_FRAME_LEN];
        let n = frame.write(MAC, IP, &mut buf);
        let arp = Arp::from_frame(&buf[..n]).expect("our own frame is ARP");
        assert_eq!((arp.op, arp.sender_mac, arp.target_ip), (1, MAC, IP));
        assert!(arp.sender_ip == IP || arp.sender_ip.is_unspecified());
        if acd.poll_at().is_none_or(|at| at > now) {
            break;
        }
    }
}

/// A conflict's attribute 11 bytes read back as the same conflict.
fn conflict_round_trips(last: LastConflict) {
    assert_eq!(LastConflict::from_bytes(&last.to_bytes()), Some(last));
}

fuzz_target!(|data: &[u8]| {
    let mut acd = Acd::new(MAC, u64::from(data.first().copied().unwrap_or(0)));
    let mut now = Instant::from_micros(1_000_000);
    acd.start(IP, now);
    let mut rest = data.get(1..).unwrap_or(&[]);
    let mut lost = false;
    while let [wait, len, tail @ ..] = rest {
        now = Instant::from_micros(now.as_micros() + u64::from(*wait) * 20_000);
        dispatch(&mut acd, now);
        let (frame, next) = tail.split_at(usize::from(*len).min(tail.len()));
        rest = next;
        if let Some(arp) = Arp::from_frame(frame) {
            assert_eq!(Arp::parse(&frame[14..]), Some(arp));
            match acd.process(&arp, now) {
                Verdict::None => {}
                Verdict::Defend(last) => {
                    // Once an announcement is out the address is claimed and defended
                    // (RFC 5227 section 2.3), though only used once the last one is.
                    assert!(
                        matches!(acd.phase(), Phase::Announcing { .. } | Phase::Ongoing),
                        "defending an address not announced: {:?}",
                        acd.phase()
                    );
                    conflict_round_trips(last);
                }
                Verdict::Lost(last) => {
                    lost = true;
                    conflict_round_trips(last);
                }
            }
        }
        assert_eq!(acd.usable(), acd.phase() == Phase::Ongoing);
        if lost {
            assert!(
                !acd.usable(),
                "a lost address in use again without a new start"
            );
        }
    }
    dispatch(&mut acd, Instant::from_micros(now.as_micros() + 60_000_000));
});
