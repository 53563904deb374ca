//! The byte scripts the adapter targets read, and the runners that play them against an
//! [`Adapter`] while checking the entry points' invariants.
//!
//! A script's first byte picks the device ([`device_byte`]): the small [`crate::device::TestDevice`] or one of
//! the shipped profiles (`enip_profiles::Profile::NAMES`, saving to an erased
//! [`crate::store`]), so every adapter target runs with every device that ships. The rest is a sequence of operations, each starting with one op byte, so libFuzzer splits
//! the stream into accept/close/data events and chunk boundaries on its own.
//!
//! TCP op byte: bits 0-1 socket (3 is outside the adapter's sockets), bits 2-3 kind
//! (0 accept, 1 close, 2 data with a `u8` length, 3 data with a `u16` length), bits 4-6 time
//! step in 100 ms, bit 7 use a small (64-byte) reply buffer for this operation.
//!
//! UDP op byte: bits 0-1 kind (0 unicast datagram, 1 limited broadcast, 2 directed broadcast
//! or multicast, 3 time only), bits 2-4 time step in 100 ms, bits 5-6 sender, bit 7 small
//! reply buffer. A datagram's length is one byte, or 0xFF followed by a `u16`.

use core::net::{Ipv4Addr, SocketAddrV4};

use enip_profiles::Profile;
use enip_stack::config::{MAX_ENCAP_FRAME, MAX_PENDING_LIST_IDENTITY, MAX_SESSIONS};
use enip_stack::wire::cpf::{self, item_type};
use enip_stack::wire::encap::{command, Packet, HEADER_LEN};
use enip_stack::wire::message_router::ResponseRepr;
use enip_stack::wire::rr_data;
use enip_stack::{Adapter, Device, Duration, Instant, NetworkConfig, SocketId};

/// Seed of the adapter's generator in every target (session handles depend on it).
pub const ADAPTER_SEED: u64 = 0x0005_EED0_FE1F;
/// Size of the small reply buffer some operations use.
pub const SMALL_REPLY: usize = 64;

/// TCP kind: accept a connection on the socket.
pub const TCP_ACCEPT: u8 = 0 << 2;
/// TCP kind: the connection on the socket closed.
pub const TCP_CLOSE: u8 = 1 << 2;
/// TCP kind: data with a one-byte length.
pub const TCP_DATA8: u8 = 2 << 2;
/// TCP kind: data with a two-byte length.
pub const TCP_DATA16: u8 = 3 << 2;

/// UDP kind: a datagram to the adapter's own address.
pub const UDP_UNICAST: u8 = 0;
/// UDP kind: a datagram to 255.255.255.255.
pub const UDP_BROADCAST: u8 = 1;
/// UDP kind: a datagram to the subnet broadcast (or, with sender bit 5, a multicast group).
pub const UDP_DIRECTED: u8 = 2;
/// UDP kind: time passes, nothing is received.
pub const UDP_TICK: u8 = 3;

/// The interface the fuzzed adapter believes it has.
pub fn network() -> NetworkConfig {
    NetworkConfig::new_static(
        Ipv4Addr::new(198, 18, 0, 2),
        Ipv4Addr::new(255, 255, 255, 0),
        [0x02, 0, 0x5E, 0x10, 0, 2],
    )
}

/// A fresh adapter around `device` as every target builds it.
pub fn adapter<D: Device>(device: D) -> Adapter<D> {
    Adapter::new(device, network(), ADAPTER_SEED)
}

/// How many devices a script can pick: the test device and every compiled-in profile.
pub fn device_count() -> usize {
    1 + Profile::NAMES.len()
}

/// The first script byte that picks `name` ("test" or a `Profile::NAMES` entry).
pub fn device_byte(name: &str) -> u8 {
    let i = Profile::NAMES
        .iter()
        .position(|&n| n == name)
        .map_or(0, |i| i + 1);
    assert!(i > 0 || name == "test", "unknown device {name:?}");
    i as u8
}

/// The device picked by the script's first byte (modulo [`device_count`]: 0 the test
/// device, `i` the profile `Profile::NAMES[i - 1]`) and the rest of the script.
pub fn split_device(script: &[u8]) -> (Option<Profile>, &[u8]) {
    let Some((&b, rest)) = script.split_first() else {
        return (None, script);
    };
    let i = usize::from(b) % device_count();
    let profile = i
        .checked_sub(1)
        .and_then(|i| Profile::from_name(Profile::NAMES[i]));
    (profile, rest)
}

/// Runs `$run(adapter, rest)` with the adapter around the device `$script` picks.
macro_rules! with_device {
    ($script:expr, |$adapter:ident, $rest:ident| $body:expr) => {
        match $crate::script::split_device($script) {
            (None, $rest) => {
                let $adapter = $crate::script::adapter($crate::device::TestDevice::new());
                $body
            }
            (Some(mut p), $rest) => {
                p.attach_store($crate::store::erased());
                let $adapter = $crate::script::adapter(p);
                $body
            }
        }
    };
}
pub(crate) use with_device;

/// The TCP peer (the scanner) of `socket`.
pub fn tcp_peer(socket: u8) -> SocketAddrV4 {
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50_000 + u16::from(socket))
}

/// A cursor over the script bytes.
pub(crate) struct Cursor<'a>(pub(crate) &'a [u8]);

impl<'a> Cursor<'a> {
    pub(crate) fn u8(&mut self) -> Option<u8> {
        let (&b, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(b)
    }
    pub(crate) fn u16(&mut self) -> Option<u16> {
        Some(u16::from_le_bytes([self.u8()?, self.u8()?]))
    }
    /// Up to `n` bytes (fewer at the end of the script).
    pub(crate) fn take(&mut self, n: usize) -> &'a [u8] {
        let (head, rest) = self.0.split_at(n.min(self.0.len()));
        self.0 = rest;
        head
    }
}

/// Asserts that `reply` is one well-formed encapsulation frame.
pub fn check_frame(reply: &[u8]) {
    let p = Packet::new_checked(reply).expect("reply is not a complete encapsulation frame");
    assert_eq!(
        HEADER_LEN + usize::from(p.length()),
        reply.len(),
        "reply length field disagrees with the reply length"
    );
    assert_eq!(p.options(), 0, "reply options must be zero");
}

/// Asserts that the Message Router reply a successful SendRRData or SendUnitData reply
/// carries is well formed: a data item (after the sequence count when connected) holding a
/// reply service with bit 7 set, a reserved byte 0, the general status and the additional
/// status inside the item.
pub fn check_cip(frame: &[u8]) {
    let Ok(p) = Packet::new_checked(frame) else {
        return;
    };
    let (kind, skip) = match p.command() {
        command::SEND_RR_DATA => (item_type::UNCONNECTED_DATA, 0),
        command::SEND_UNIT_DATA => (item_type::CONNECTED_DATA, 2),
        _ => return,
    };
    if p.status() != 0 {
        return;
    }
    let rr = rr_data::Packet::new_checked(p.data()).expect("reply interface handle, timeout");
    let c = cpf::Packet::new_checked(rr.cpf()).expect("reply CPF");
    let item = c.find(kind).expect("reply data item");
    let body = item.data.get(skip..).expect("sequence count");
    let r = ResponseRepr::parse(body).expect("a Message Router reply in the data item");
    assert!(
        r.service & 0x80 != 0,
        "reply service without bit 7: {body:02x?}"
    );
    assert_eq!(body[1], 0, "reply reserved byte: {body:02x?}");
}

/// Plays a TCP script; `on_reply(socket, frame)` sees every reply. Panics on a broken
/// invariant: a reply longer than its buffer or malformed (down to the Message Router reply,
/// [`check_cip`]), no progress on non-empty data, more consumed than given.
pub fn run_tcp(script: &[u8], on_reply: impl FnMut(u8, &[u8])) {
    with_device!(script, |adapter, rest| run_tcp_on(adapter, rest, on_reply))
}

fn run_tcp_on<D: Device>(
    mut adapter: Adapter<D>,
    script: &[u8],
    mut on_reply: impl FnMut(u8, &[u8]),
) {
    let mut now = Instant::from_micros(1_000_000);
    let mut reply = [0u8; MAX_ENCAP_FRAME];
    let mut c = Cursor(script);
    while let Some(op) = c.u8() {
        let socket = op & 0x03;
        now = now.add(Duration::from_millis(100 * u64::from((op >> 4) & 0x07)));
        let limit = if op & 0x80 != 0 {
            SMALL_REPLY
        } else {
            MAX_ENCAP_FRAME
        };
        let peer = tcp_peer(socket);
        let data = match op & 0x0C {
            TCP_ACCEPT => {
                adapter.tcp_accept(SocketId(socket), peer, now);
                continue;
            }
            TCP_CLOSE => {
                adapter.tcp_close(SocketId(socket), now);
                continue;
            }
            TCP_DATA8 => {
                let n = c.u8().unwrap_or(0);
                c.take(usize::from(n))
            }
            _ => {
                let n = c.u16().unwrap_or(0);
                c.take(usize::from(n))
            }
        };
        let buf = &mut reply[..limit];
        feed_tcp(&mut adapter, socket, data, now, buf, &mut on_reply);
    }
}

/// Feeds `data` received on `socket` until it is all consumed or the adapter closes the
/// connection (then closes it, as a runtime would), checking every outcome.
pub fn feed_tcp<D: Device>(
    adapter: &mut Adapter<D>,
    socket: u8,
    data: &[u8],
    now: Instant,
    reply: &mut [u8],
    on_reply: &mut impl FnMut(u8, &[u8]),
) {
    let limit = reply.len();
    let _ = adapter.tcp_deadline(SocketId(socket));
    let mut rest = data;
    // Each call consumes at least one byte, so this many calls always suffice.
    let mut calls_left = data.len() + 1;
    loop {
        assert!(calls_left > 0, "tcp_receive made no progress");
        calls_left -= 1;
        let out = adapter.tcp_receive(SocketId(socket), rest, now, reply);
        assert!(out.reply_len <= limit, "reply longer than the reply buffer");
        assert!(out.consumed <= rest.len(), "consumed more than was given");
        if out.reply_len > 0 {
            let frame = &reply[..out.reply_len];
            check_frame(frame);
            check_cip(frame);
            on_reply(socket, frame);
        }
        if out.close {
            if usize::from(socket) < MAX_SESSIONS {
                adapter.tcp_close(SocketId(socket), now);
            }
            return;
        }
        assert!(
            rest.is_empty() || out.consumed > 0,
            "tcp_receive consumed nothing of non-empty data without closing"
        );
        rest = &rest[out.consumed..];
        if rest.is_empty() {
            return;
        }
    }
}

const SENDERS: [SocketAddrV4; 4] = [
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 44818),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 3), 50_000),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 4), 2222),
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 1),
];

/// Plays a UDP script; `on_reply(destination, frame)` sees every reply, immediate (sent back to
/// the sender) or delayed. Panics on a broken invariant: a reply longer than its buffer or
/// malformed, a due reply left queued, a deadline in the past after polling, or a queue that
/// does not drain.
pub fn run_udp(script: &[u8], on_reply: impl FnMut(SocketAddrV4, &[u8])) {
    with_device!(script, |adapter, rest| run_udp_on(adapter, rest, on_reply))
}

fn run_udp_on<D: Device>(
    mut adapter: Adapter<D>,
    script: &[u8],
    mut on_reply: impl FnMut(SocketAddrV4, &[u8]),
) {
    let mut now = Instant::from_micros(1_000_000);
    let mut reply = [0u8; MAX_ENCAP_FRAME];
    let mut c = Cursor(script);
    while let Some(op) = c.u8() {
        now = now.add(Duration::from_millis(100 * u64::from((op >> 2) & 0x07)));
        let from = SENDERS[usize::from((op >> 5) & 0x03)];
        let limit = if op & 0x80 != 0 {
            SMALL_REPLY
        } else {
            MAX_ENCAP_FRAME
        };
        let to = match op & 0x03 {
            UDP_UNICAST => Some(network().ip),
            UDP_BROADCAST => Some(Ipv4Addr::BROADCAST),
            UDP_DIRECTED if op & 0x20 != 0 => Some(Ipv4Addr::new(224, 0, 0, 1)),
            UDP_DIRECTED => Some(Ipv4Addr::new(198, 18, 0, 255)),
            _ => None,
        };
        if let Some(to) = to {
            let n = match c.u8().unwrap_or(0) {
                0xFF => c.u16().unwrap_or(0),
                n => u16::from(n),
            };
            let datagram = c.take(usize::from(n));
            let len = adapter.udp_receive(from, to, datagram, now, &mut reply[..limit]);
            assert!(len <= limit, "UDP reply longer than the reply buffer");
            if len > 0 {
                check_frame(&reply[..len]);
                on_reply(from, &reply[..len]);
            }
        }
        drain(&mut adapter, now, &mut reply[..limit], &mut on_reply);
    }
    // Long after every possible delay, nothing may be left waiting.
    let later = now.add(Duration::from_secs(10));
    drain(&mut adapter, later, &mut reply, &mut on_reply);
    assert_eq!(
        adapter.next_deadline(),
        None,
        "delayed replies never drained"
    );
}

/// Sends every delayed reply due at `now` and checks what is left is in the future.
pub(crate) fn drain<D: Device>(
    adapter: &mut Adapter<D>,
    now: Instant,
    out: &mut [u8],
    on_reply: &mut impl FnMut(SocketAddrV4, &[u8]),
) {
    let limit = out.len();
    for _ in 0..=MAX_PENDING_LIST_IDENTITY {
        let Some((to, len)) = adapter.poll_udp(now, out) else {
            if let Some(next) = adapter.next_deadline() {
                assert!(next > now, "a due reply was not handed out by poll_udp");
            }
            return;
        };
        assert!(len <= limit, "delayed reply longer than the buffer");
        if len > 0 {
            check_frame(&out[..len]);
            on_reply(to, &out[..len]);
        }
    }
    panic!("poll_udp handed out more replies than can be queued");
}
