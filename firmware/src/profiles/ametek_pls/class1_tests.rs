//! Class 1 through the stack's `Adapter` entry points in virtual time: a scanner's session,
//! the Forward_Open of §3.1 (150/100/1 at 10 ms), O->T data with the run/idle header, T->O
//! data read back; Acknowledge edges, Idle and the watchdog timeout as the device sees them.

extern crate std;

use core::net::{Ipv4Addr, SocketAddrV4};
use std::vec;
use std::vec::Vec;

use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, Segment};
use enip_stack::wire::forward_open::{ForwardOpen, ForwardOpenReply, NetworkParams, Triad};
use enip_stack::wire::Writer;
use enip_stack::{Adapter, Instant, NetworkConfig, SocketId};

use super::leds::NetworkStatus;
use super::tests::{execute, le, pls_object, programmed, request, words};
use super::AmetekPls;

const SCANNER: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
const RPI_US: u32 = 10_000;

/// An adapter over the programmed PLS, a scanner session, and an exclusive owner.
struct Scanner {
    adapter: Adapter<AmetekPls>,
    session: u32,
    o_t: u32,
    sequence: u16,
    now: u64,
    /// The O->T data repeated every RPI, as a scanner does (`None`: the scanner is gone).
    cyclic: Option<(bool, [u16; 7])>,
}

impl Scanner {
    fn tcp(&mut self, frame: &[u8]) -> Vec<u8> {
        let mut reply = vec![0u8; MAX_ENCAP_FRAME];
        let out = self
            .adapter
            .tcp_receive(SocketId(0), frame, Instant(self.now), &mut reply);
        reply.truncate(out.reply_len);
        reply
    }

    /// Opens 150/100 with configuration 1; the Forward_Open's general status.
    fn open(pls: AmetekPls) -> (Self, u8) {
        let net = NetworkConfig::new_static(
            Ipv4Addr::new(198, 18, 0, 2),
            Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 2],
        );
        let mut s = Scanner {
            adapter: Adapter::new(pls, net, 7),
            session: 0,
            o_t: 0,
            sequence: 0,
            now: 0,
            cyclic: None,
        };
        s.adapter
            .tcp_accept(SocketId(0), SocketAddrV4::new(SCANNER, 50000), Instant(0));
        let mut buf = [0u8; 64];
        let n = originator::register_session(&mut buf).unwrap();
        let reply = s.tcp(&buf[..n]);
        s.session = u32::from_le_bytes(reply[4..8].try_into().unwrap());
        let mut path = [0u8; 32];
        let mut w = Writer::new(&mut path);
        for seg in [
            Segment::Logical(LogicalType::Class, 4),
            Segment::Logical(LogicalType::Instance, 1),
            Segment::Logical(LogicalType::ConnectionPoint, 150),
            Segment::Logical(LogicalType::ConnectionPoint, 100),
        ] {
            seg.emit(&mut w).unwrap();
        }
        let n = w.len();
        let fo = ForwardOpen {
            large: false,
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            o_t_connection_id: 0,
            t_o_connection_id: 0x7000_0001,
            triad: Triad {
                connection_serial: 1,
                vendor_id: 0x1337,
                originator_serial: 0xC0FFEE,
            },
            timeout_multiplier: 0,
            o_t_rpi: RPI_US,
            o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 14)),
            t_o_rpi: RPI_US,
            t_o_params: NetworkParams::from_u16(0x4800 | (2 + 34)),
            transport: 0x01,
            path: &path[..n],
        };
        let mut data = [0u8; 128];
        let mut w = Writer::new(&mut data);
        fo.emit(&mut w).unwrap();
        let len = w.len();
        let cm = [
            Segment::Logical(LogicalType::Class, 6),
            Segment::Logical(LogicalType::Instance, 1),
        ];
        let mut frame = vec![0u8; MAX_ENCAP_FRAME];
        let n = originator::send_rr_data(&mut frame, s.session, None, |w| {
            originator::request(w, 0x54, &cm, &data[..len])
        })
        .unwrap();
        let reply = s.tcp(&frame[..n]);
        let r = originator::parse_reply(&reply).unwrap().response.unwrap();
        if r.general_status == 0 {
            s.o_t = ForwardOpenReply::parse(r.data).unwrap().o_t_connection_id;
        }
        let status = r.general_status;
        (s, status)
    }

    /// Sends O->T data `w` (Run or Idle) now, and then every RPI.
    fn send(&mut self, run: bool, w: [u16; 7]) {
        self.cyclic = Some((run, w));
        self.datagram(run, w);
    }

    fn datagram(&mut self, run: bool, w: [u16; 7]) {
        self.sequence = self.sequence.wrapping_add(1);
        let mut buf = [0u8; 64];
        let n = originator::io_datagram(
            &mut buf,
            self.o_t,
            u32::from(self.sequence),
            self.sequence,
            Some(run),
            &le(&w),
        )
        .unwrap();
        let from = SocketAddrV4::new(SCANNER, 2222);
        self.adapter
            .io_receive(from, &buf[..n], Instant(self.now))
            .unwrap();
    }

    /// Advances `ms` milliseconds, running the device and producing; the last T->O data.
    fn advance(&mut self, ms: u64) -> Option<Vec<u16>> {
        let mut last = None;
        for _ in 0..ms {
            self.now += 1000;
            if let Some((run, w)) = self
                .cyclic
                .filter(|_| self.now.is_multiple_of(u64::from(RPI_US)))
            {
                self.datagram(run, w);
            }
            self.adapter.poll_device(Instant(self.now));
            let mut out = [0u8; 256];
            while let Some((_, n)) = self.adapter.poll_io(Instant(self.now), &mut out) {
                // Encapsulation-free datagram: CPF items, then sequence count and 34 bytes.
                last = Some(words(&out[n - 34..n]));
            }
        }
        last
    }
}

#[test]
fn class1_exclusive_owner_at_10_ms() {
    let (mut s, status) = Scanner::open(programmed());
    assert_eq!(status, 0);
    s.send(true, [1, 0, 0, 0, 0, 0, 0]);
    let t_o = s.advance(25).expect("T->O data every 10 ms");
    let ns = || s.adapter.device().leds().network_status();
    assert_eq!(ns(), NetworkStatus::Connected);
    assert_eq!(t_o.len(), 17);
    assert_eq!(t_o[14..17], [0, 0, 0]);
    // An invalid Set while connected: the error is in the next T->O datagram.
    let mut bad = pls_object();
    bad[0] = 1;
    let mut pls_set = request(0x10, 0xC1, 1, Some(1), &le(&bad));
    let mut reply = [0u8; 64];
    let n = s.adapter.execute(&pls_set, Instant(s.now), &mut reply);
    assert_eq!(reply[2], 0x09, "{:?}", &reply[..n]);
    assert_eq!(s.advance(15).unwrap()[14..17], [1, 1, 1]);
    // Acknowledge 0 -> 1 over O->T clears it.
    s.send(true, [1 | 4, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[14..17], [0, 0, 0]);
    // Home 150: output 1 on.
    pls_set = request(0x10, 0xC1, 1, Some(36), &le(&[1, 150, 0, 0, 0, 0, 0, 0, 0]));
    s.adapter.execute(&pls_set, Instant(s.now), &mut reply);
    assert_eq!(reply[2], 0);
    let t_o = s.advance(15).unwrap();
    assert_eq!((t_o[0], t_o[10]), (150, 1));
    // While owned, an explicit Set of the output assembly is refused (0x10).
    let owned = request(0x10, 0x04, 150, Some(3), &[0; 14]);
    s.adapter.execute(&owned, Instant(s.now), &mut reply);
    assert_eq!(reply[2], 0x10);
    // Idle: outputs disabled.
    s.send(false, [1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[10], 0);
    s.send(true, [1, 0, 0, 0, 0, 0, 0]);
    assert_eq!(s.advance(15).unwrap()[10], 1);
    // No O->T for longer than the watchdog (4 x 10 ms): the owner is gone, outputs off.
    s.cyclic = None;
    s.advance(100);
    assert!(s.adapter.connections().is_empty());
    assert_eq!(
        s.adapter.device().leds().network_status(),
        NetworkStatus::TimedOut
    );
    let mut pls = s.adapter.into_device();
    let w = words(&execute(&mut pls, &request(0x0E, 0x04, 100, Some(3), &[])).1);
    assert_eq!(w[10], 0);
}
