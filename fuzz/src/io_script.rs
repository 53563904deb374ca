//! The script the `adapter_io` target reads: TCP sessions (Forward_Open, Forward_Close,
//! SendUnitData), Class 1 datagrams on UDP 2222, time steps and input triggers, with the
//! adapter polled after every operation as a runtime would.
//!
//! The first byte picks the device (see [`crate::script::split_device`]). Op byte: bits 0-2 kind, bits 3-7 argument `a`:
//! 0 accept on socket `a & 3`; 1 close socket `a & 3`; 2 TCP data on socket `a & 3`
//! (`u16` length, then the bytes); 3 a datagram on UDP 2222 from sender `a & 3` (`u16`
//! length, then the bytes); 4 time passes `a + 1` ms; 5 time passes `a` x 100 ms;
//! 6 `trigger_input` for the device's assembly `a & 3` (in `Device::assemblies` order; one
//! past the last is an instance no device has); 7 a datagram on UDP 44818
//! (`u8` length) to the adapter.
//!
//! Invariants checked after every operation: `poll_io` hands out at most one datagram per
//! connection for one instant, each no longer than the buffer and well formed, and once it and
//! `poll_udp` return `None`, `next_deadline` is in the future (a runtime never spins).

use core::net::{Ipv4Addr, SocketAddrV4};

use enip_stack::config::{MAX_CONNECTIONS, MAX_ENCAP_FRAME};
use enip_stack::wire::io_datagram;
use enip_stack::{Adapter, Device, Duration, Instant, SocketId};

use crate::script::{check_frame, drain, feed_tcp, network, tcp_peer, with_device, Cursor};

/// Kind: accept a TCP connection.
pub const ACCEPT: u8 = 0;
/// Kind: close a TCP connection.
pub const CLOSE: u8 = 1;
/// Kind: TCP data.
pub const TCP_DATA: u8 = 2;
/// Kind: a Class 1 datagram.
pub const IO_DATA: u8 = 3;
/// Kind: milliseconds pass.
pub const WAIT_MS: u8 = 4;
/// Kind: tenths of seconds pass.
pub const WAIT_100MS: u8 = 5;
/// Kind: an input assembly has new data.
pub const TRIGGER: u8 = 6;
/// Kind: a datagram on UDP 44818.
pub const UDP_DATA: u8 = 7;

/// Where Class 1 datagrams come from: the scanner (same IP as its TCP connection) on two
/// ports, another host, and the scanner on a low port.
pub const IO_SENDERS: [SocketAddrV4; 4] = [
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 2222),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 2223),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 3), 2222),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 1),
];

/// What the script saw, for the seed self-check.
#[derive(Debug, Default, Clone, Copy)]
pub struct IoStats {
    /// Class 1 datagrams accepted with new data.
    pub accepted: usize,
    /// T->O datagrams produced.
    pub produced: usize,
}

/// Plays an I/O script; `on_reply` sees every TCP reply. Panics on a broken invariant.
pub fn run_io(script: &[u8], on_reply: impl FnMut(u8, &[u8])) -> IoStats {
    with_device!(script, |adapter, rest| run_io_on(adapter, rest, on_reply))
}

fn run_io_on<D: Device>(
    mut adapter: Adapter<D>,
    script: &[u8],
    mut on_reply: impl FnMut(u8, &[u8]),
) -> IoStats {
    let mut stats = IoStats::default();
    let mut now = Instant::from_micros(1_000_000);
    let mut reply = [0u8; MAX_ENCAP_FRAME];
    let mut c = Cursor(script);
    while let Some(op) = c.u8() {
        let a = op >> 3;
        let socket = a & 3;
        match op & 0x07 {
            ACCEPT => adapter.tcp_accept(SocketId(socket), tcp_peer(socket), now),
            CLOSE => adapter.tcp_close(SocketId(socket), now),
            TCP_DATA => {
                let n = c.u16().unwrap_or(0);
                let data = c.take(usize::from(n));
                feed_tcp(&mut adapter, socket, data, now, &mut reply, &mut on_reply);
            }
            IO_DATA => {
                let n = c.u16().unwrap_or(0);
                let data = c.take(usize::from(n));
                let from = IO_SENDERS[usize::from(socket)];
                if matches!(
                    adapter.io_receive(from, data, now),
                    Ok(enip_stack::io::Accepted::NewData)
                ) {
                    stats.accepted += 1;
                }
            }
            WAIT_MS => now = now.add(Duration::from_millis(u64::from(a) + 1)),
            WAIT_100MS => now = now.add(Duration::from_millis(100 * u64::from(a))),
            TRIGGER => {
                let instance = adapter
                    .device()
                    .assemblies()
                    .get(usize::from(socket))
                    .map_or(0xFFFF, |a| a.instance);
                adapter.trigger_input(instance);
            }
            _ => {
                let n = c.u8().unwrap_or(0);
                let data = c.take(usize::from(n));
                let from = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 44818);
                let len = adapter.udp_receive(from, network().ip, data, now, &mut reply);
                if len > 0 {
                    check_frame(&reply[..len]);
                }
            }
        }
        stats.produced += poll(&mut adapter, now, &mut reply);
    }
    stats
}

/// Polls like a runtime at `now`; returns how many T->O datagrams were produced.
fn poll<D: Device>(adapter: &mut Adapter<D>, now: Instant, out: &mut [u8]) -> usize {
    let limit = out.len();
    // The device's own time (a drive moving, a limit switch turning), as a runtime runs it.
    let _ = adapter.poll_device(now);
    let mut produced = 0;
    while let Some((_to, len)) = adapter.poll_io(now, out) {
        produced += 1;
        assert!(
            produced <= MAX_CONNECTIONS,
            "poll_io produced more datagrams for one instant than there are connections"
        );
        assert!(len <= limit, "T->O datagram longer than the buffer");
        if len > 0 {
            io_datagram::Packet::new_checked(&out[..len]).expect("T->O datagram is well formed");
        }
    }
    drain(adapter, now, out, &mut |_, _| {});
    if let Some(next) = adapter.next_deadline() {
        assert!(
            next > now,
            "next_deadline {next:?} is not after {now:?} although everything was polled"
        );
    }
    produced
}
