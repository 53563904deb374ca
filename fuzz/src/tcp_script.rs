//! The byte scripts the `tcp_server` target reads: segments from four peers (three hosts,
//! one of them on a second port), time passing
//! and sends, played against the encapsulation port's TCP (`enip_stack::tcp::TcpServer`)
//! with a real [`Adapter`] behind it (the first byte picks the device, as
//! [`crate::script`]'s scripts do), checking the server's invariants.
//!
//! Op byte: bits 0-1 kind (0 and 1 a segment, 2 time passes and the timers run, 3 the
//! server sends what it owes), bits 2-3 peer (3 is the first peer's address on another
//! port), bits 4-7 the time step in 10 ms. A segment follows as: flags (1 byte: SYN, ACK,
//! FIN, RST, PSH in bits 0-4; bit 5 an MSS option from the next two bytes), the sequence
//! number as an offset from the peer's last one (2 bytes), the acknowledgment number as an
//! offset from the server's last sequence number to the peer (2 bytes), the window (2 bytes),
//! the data's length (1 byte) and the data.

use core::net::{Ipv4Addr, SocketAddrV4};
use std::collections::HashMap;

use enip_stack::config::{MAX_ENCAP_FRAME, MAX_SESSIONS};
use enip_stack::tcp::{Flags, Outgoing, Segment, TcpApp, TcpServer, MSS};
use enip_stack::{Adapter, Device, Duration, Instant, SocketId, TcpOutcome};

use crate::script::{with_device, Cursor};

/// The server of the adapter's sessions.
type Server = TcpServer<MAX_SESSIONS, MAX_ENCAP_FRAME>;

/// The adapter behind the server, with what the server told it checked: a connection is
/// accepted before it is fed or closed, and closed once.
struct Checked<D: Device> {
    adapter: Adapter<D>,
    open: [bool; MAX_SESSIONS],
}

impl<D: Device> Checked<D> {
    fn slot(&mut self, id: SocketId) -> &mut bool {
        self.open
            .get_mut(usize::from(id.0))
            .expect("a connection number past the sessions")
    }
}

impl<D: Device> TcpApp for Checked<D> {
    fn accepted(&mut self, id: SocketId, peer: SocketAddrV4, now: Instant) {
        assert!(!*self.slot(id), "connection {} accepted twice", id.0);
        *self.slot(id) = true;
        self.adapter.tcp_accept(id, peer, now);
    }

    fn receive(&mut self, id: SocketId, data: &[u8], now: Instant, reply: &mut [u8]) -> TcpOutcome {
        assert!(
            *self.slot(id),
            "data for connection {} before its accept",
            id.0
        );
        assert!(!data.is_empty(), "fed nothing");
        assert!(
            reply.len() >= MAX_ENCAP_FRAME,
            "a reply buffer short of a frame"
        );
        let outcome = self.adapter.tcp_receive(id, data, now, reply);
        assert!(outcome.consumed <= data.len() && outcome.reply_len <= reply.len());
        outcome
    }

    fn closed(&mut self, id: SocketId, now: Instant) {
        assert!(
            *self.slot(id),
            "connection {} closed twice or never opened",
            id.0
        );
        *self.slot(id) = false;
        self.adapter.tcp_close(id, now);
    }

    fn idle_deadline(&self, id: SocketId) -> Option<Instant> {
        self.adapter.tcp_deadline(id)
    }
}

/// Plays a script; panics on a broken invariant (the adapter's pairing above; a segment
/// longer than the peer's maximum segment size or than the replies kept; a RST answering a
/// RST; a SYN that is not a SYN-ACK, or a SYN cookie to no SYN; time the timers asked for
/// not honoured).
pub fn run_tcp_server(script: &[u8]) {
    with_device!(script, |adapter, rest| run(adapter, rest))
}

/// The peers: three hosts' ports, and the first host on another port.
fn peer(i: u8) -> SocketAddrV4 {
    let host = if i == 3 { 1 } else { 1 + i };
    SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, host), 40_000 + u16::from(i))
}

fn run<D: Device>(adapter: Adapter<D>, script: &[u8]) {
    let mut app = Checked {
        adapter,
        open: [false; MAX_SESSIONS],
    };
    let mut server = Server::new(0x7C9);
    let mut now = Instant::from_micros(1_000_000);
    // Per peer: its next sequence number, the server's last one to it, its MSS.
    let mut seq = [1000u32, 2000, 3000, 4000];
    let mut theirs = [0u32; 4];
    let mut mss = [MSS; 4];
    // Every SYN's peer and sequence number, with the largest maximum segment size a SYN of
    // that number named (the bound of whatever connection it opens: a half-open one keeps
    // the first SYN's, a cookie the size of the SYN it answered).
    let mut syns: HashMap<(usize, u32), u16> = HashMap::new();
    let mut c = Cursor(script);
    while let Some(op) = c.u8() {
        now = now.add(Duration::from_millis(10 * u64::from(op >> 4)));
        let who = (op >> 2) & 0x03;
        let i = usize::from(who);
        match op & 0x03 {
            0 | 1 => {
                let Some(bits) = c.u8() else { break };
                let flags = Flags {
                    syn: bits & 0x01 != 0,
                    ack: bits & 0x02 != 0,
                    fin: bits & 0x04 != 0,
                    rst: bits & 0x08 != 0,
                    psh: bits & 0x10 != 0,
                };
                let option = if bits & 0x20 != 0 { c.u16() } else { None };
                let (Some(ds), Some(da), Some(window), Some(len)) =
                    (c.u16(), c.u16(), c.u16(), c.u8())
                else {
                    break;
                };
                let payload = c.take(usize::from(len));
                seq[i] = seq[i].wrapping_add(u32::from(ds));
                if flags.syn {
                    let size = option.unwrap_or(536).clamp(48, MSS);
                    let kept = syns.entry((i, seq[i])).or_insert(size);
                    *kept = (*kept).max(size);
                }
                let segment = Segment {
                    peer: peer(who),
                    seq: seq[i],
                    ack: theirs[i].wrapping_add(u32::from(da)),
                    flags,
                    window,
                    mss: option,
                    payload,
                };
                if let Some(answer) = server.process(&segment, now, &mut app) {
                    assert!(!flags.rst, "a RST answered");
                    assert_eq!(answer.peer, segment.peer);
                    if answer.flags.syn {
                        // A SYN cookie: it answers a SYN, and its connection, if the ACK
                        // comes, keeps to a size not over that SYN's.
                        assert!(flags.syn && !flags.ack && answer.ack == seq[i].wrapping_add(1));
                        check(&answer, &[], MSS);
                        mss[i] = syns.get(&(i, seq[i])).copied().unwrap_or(536);
                        theirs[i] = answer.seq;
                    } else {
                        assert!(answer.flags.rst, "neither a RST nor a SYN cookie");
                    }
                }
            }
            2 => {
                server.poll(now, &mut app);
                if let Some(next) = server.deadline(&app) {
                    assert!(next > now || server.owes(), "a timer left due at {now:?}");
                }
            }
            _ => {
                for _ in 0..32 {
                    let Some(sent) = server.transmit(now) else {
                        break;
                    };
                    let to = (0..4u8).find(|&j| peer(j) == sent.segment.peer);
                    let j = usize::from(to.expect("a segment to nobody"));
                    if sent.segment.flags.syn {
                        // The connection the SYN-ACK answers takes that SYN's size.
                        let syn = syns.get(&(j, sent.segment.ack.wrapping_sub(1)));
                        mss[j] = *syn.expect("a SYN-ACK to no SYN");
                    }
                    check(&sent.segment, sent.payload, mss[j]);
                    theirs[j] = sent.segment.seq;
                }
            }
        }
        let _ = server.take_reset();
    }
}

/// A segment the server sent: within its peer's MSS `mss` and the replies kept; a SYN only
/// as a SYN-ACK with our MSS.
fn check(out: &Outgoing, payload: &[u8], mss: u16) {
    assert!(
        payload.len() <= usize::from(mss),
        "a segment over the peer's MSS"
    );
    assert!(payload.len() <= 2 * MAX_ENCAP_FRAME);
    if out.flags.syn {
        assert!(out.flags.ack && out.mss == Some(MSS) && payload.is_empty() && !out.flags.fin);
    }
    if out.flags.rst {
        assert!(payload.is_empty() && !out.flags.syn && !out.flags.fin);
    }
}
