//! `io_cycle N`: drives the sans-IO adapter with the generic profile through N Class 1
//! cycles (consume one O->T datagram, produce one T->O datagram) after opening one
//! exclusive-owner connection. Run under callgrind by `cargo xtask bench` for instruction
//! counts (two runs of different N, so set-up cancels out), and natively for time per cycle.

use std::hint::black_box;
use std::net::{Ipv4Addr, SocketAddrV4};
use std::time::Instant as WallClock;

use enip_firmware::profiles::generic::Generic;
use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator;
use enip_stack::wire::epath::{LogicalType, Segment};
use enip_stack::wire::forward_open::{ForwardOpen, ForwardOpenReply, NetworkParams, Triad};
use enip_stack::wire::Writer;
use enip_stack::{Adapter, Instant, NetworkConfig, SocketId};

const RPI_US: u64 = 1_000;

/// Opens the generic profile's exclusive owner (150 -> 100, config 151); returns its O->T ID.
fn open(adapter: &mut Adapter<Generic>) -> u32 {
    let scanner = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50_000);
    adapter.tcp_accept(SocketId(0), scanner, Instant(0));
    let mut frame = vec![0u8; MAX_ENCAP_FRAME];
    let mut reply = vec![0u8; MAX_ENCAP_FRAME];
    let n = originator::register_session(&mut frame).expect("frame");
    let out = adapter.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
    let session = u32::from_le_bytes(reply[4..8].try_into().expect("handle"));
    assert_eq!(out.reply_len, 28);
    let path = [0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100];
    let fo = ForwardOpen {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x5C00_0000,
        triad: Triad {
            connection_serial: 1,
            vendor_id: 0xF00D,
            originator_serial: 1,
        },
        timeout_multiplier: 2,
        o_t_rpi: RPI_US as u32,
        o_t_params: NetworkParams::from_u16(0x4800 | 38),
        t_o_rpi: RPI_US as u32,
        t_o_params: NetworkParams::from_u16(0x4800 | 34),
        transport: 0x01,
        path: &path,
    };
    let mut data = [0u8; 64];
    let mut w = Writer::new(&mut data);
    fo.emit(&mut w).expect("forward open");
    let len = w.len();
    let cm = [
        Segment::Logical(LogicalType::Class, 6),
        Segment::Logical(LogicalType::Instance, 1),
    ];
    let n = originator::send_rr_data(&mut frame, session, None, |w| {
        originator::request(w, 0x54, &cm, &data[..len])
    })
    .expect("frame");
    let out = adapter.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
    let r = originator::parse_reply(&reply[..out.reply_len]).expect("reply");
    let resp = r.response.expect("response");
    assert_eq!(resp.general_status, 0, "Forward_Open refused");
    ForwardOpenReply::parse(resp.data)
        .expect("reply data")
        .o_t_connection_id
}

fn main() {
    let cycles: u64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let net = NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [2, 0, 0, 0, 0, 2],
    );
    let mut adapter = Adapter::new(Generic::new(), net, 1);
    let o_t = open(&mut adapter);
    let scanner = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 2222);
    // The O->T datagram is built once; each cycle only patches its two sequence numbers, so
    // the count is the adapter's work, not the originator's.
    let mut rx = [0u8; 64];
    let n = originator::io_datagram(&mut rx, o_t, 0, 0, Some(true), &[0x5A; 32]).expect("datagram");
    let mut tx = [0u8; 128];
    let mut produced = 0u64;
    let started = WallClock::now();
    for k in 1..=cycles {
        let now = Instant(k * RPI_US);
        rx[10..14].copy_from_slice(&(k as u32).to_le_bytes());
        rx[18..20].copy_from_slice(&(k as u16).to_le_bytes());
        let _ = black_box(adapter.io_receive(scanner, black_box(&rx[..n]), now));
        while let Some((_, len)) = adapter.poll_io(now, &mut tx) {
            black_box(&tx[..len]);
            produced += 1;
        }
    }
    let elapsed = started.elapsed();
    assert!(produced >= cycles, "every cycle produces");
    println!(
        "{{\"cycles\":{cycles},\"produced\":{produced},\"ns_per_cycle\":{:.1}}}",
        elapsed.as_nanos() as f64 / cycles as f64
    );
}
