//! The frames the link task handles that are not Class 1: TCP segments (to the encapsulation
//! port: to the adapter's TCP server, `super::super::tcp_link`; to a closed port: refused
//! with a RST), and everything else, which goes to the network stack (but what it must not
//! see, [`super::super::frame::kept_from_stack`]) and whose frames it sends, marked with the
//! DSCP of explicit messaging.

use core::net::Ipv4Addr;
use core::ops::Range;
use core::task::Context;

use embassy_net_driver::Driver;
use enip_stack::config::{ENCAP_PORT, TLS_PORT};
use enip_stack::{Instant, NetworkConfig};
use smoltcp::phy::ChecksumCapabilities;

use super::super::acd::passes_unaddressed;
use super::super::dscp;
use super::super::frame::{self, copy, send_copy};
use super::super::frames::{LinkFrames, TX_FRAMES};
use super::super::io_port::IoPort;
use super::super::stack_sums;
use super::super::tcp_frames::{self, Located};
use super::super::tcp_link;
use super::Pump;
use crate::clock::earliest;

impl<const STACK_SUMS: bool> Pump<'_, STACK_SUMS> {
    /// A received frame that is no O->T datagram (`from_host`: its IPv4 header held, from
    /// one host): unless the flood guard drops it, a TCP segment goes to the server if it is
    /// for the encapsulation port, to the stack if for the TLS port the runtime serves there,
    /// and is answered as one to a closed port otherwise (the stack, without TCP of its own,
    /// would answer "protocol unreachable"); anything else goes to the stack. Returns
    /// whether it went to the stack, and whether it was a TCP segment taken in here (its
    /// checksum held: its sender may be learned).
    pub(super) fn other_frame(
        &mut self,
        frame: &[u8],
        from_host: bool,
        frames: &LinkFrames,
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) -> (bool, bool) {
        if !self.flood_guard.admit(frame, me.ip, at) {
            return (false, false);
        }
        if let Some((src, range, port)) = from_host.then(|| tcp_frames::locate(frame, me)).flatten()
        {
            if port == ENCAP_PORT {
                return (false, self.ingest_tcp(frame, (src, range), io, me, at));
            }
            if port != TLS_PORT || !io.tls_port_open() {
                return (false, self.refuse_tcp(frame, (src, range, port), me));
            }
        } else if frame::kept_from_stack(frame, me) {
            return (false, false);
        }
        if STACK_SUMS {
            return (self.pass_checked(frame, frames), false);
        }
        // A frame longer than a queue slot is cut short, and the stack drops it.
        let _ = frames.rx.push(frame.len(), |room| copy(room, frame));
        (true, false)
    }

    /// The TCP segment `tcp` (its source, its place in `frame`) for the encapsulation port:
    /// to the server; true if it was well formed and its checksum held. Out of line: not on
    /// the Class 1 path.
    #[inline(never)]
    fn ingest_tcp(
        &mut self,
        frame: &[u8],
        (src, range): (Ipv4Addr, Range<usize>),
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) -> bool {
        let Some(segment) = frame.get(range) else {
            return false;
        };
        let verify = self.sums.tcp.rx();
        // A request may have moved the LLDP deadline (the LLDP Management object).
        self.lldp_stale = true;
        self.tcp.take(segment, (src, me.ip), verify, io, at)
    }

    /// The TCP segment in `frame` (its source, its place, its port) to a port nothing listens
    /// on: answered with a RST; true if it was whole and its checksum held. Out of line: not
    /// on the Class 1 path.
    #[inline(never)]
    fn refuse_tcp(
        &mut self,
        frame: &[u8],
        (src, range, port): Located,
        me: &NetworkConfig,
    ) -> bool {
        let Some(segment) = frame.get(range) else {
            return false;
        };
        let verify = self.sums.tcp.rx();
        self.tcp.refuse(segment, (src, me.ip, port), verify)
    }

    /// The rare work at `at` for the interface `me` (its link up or not): the
    /// interface address and link followed by Address Conflict Detection and its frame sent
    /// if due, the stack's frames sent, the encapsulation TCP served, the LLDPDU sent if due;
    /// then the earliest of their deadlines learned. Inlined into the pass, behind its
    /// check: a call apart cost an explicit request more than it saved a Class 1 cycle.
    #[inline(always)]
    pub(super) fn serve_others<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        frames: &LinkFrames,
        io: &dyn IoPort,
        (me, up): (&NetworkConfig, bool),
        at: Instant,
    ) {
        self.others_stale = false;
        self.guard.follow(me.ip, io, at);
        self.guard.link(up, at);
        let mut acd = self.guard.deadline(at);
        if acd.is_some_and(|d| d <= at) {
            self.send_acd_frame(cx, driver, at);
            acd = self.guard.deadline(at);
        }
        if !frames.tx.is_empty() {
            // The stack's frames may answer a request that moved the LLDP deadline.
            self.lldp_stale |= self.send_stack_frames(cx, driver, frames, io);
        }
        if self.tcp.due(at) {
            self.serve_tcp(cx, driver, io, me, at);
        }
        if up && (self.lldp_stale || self.lldp_next.is_some_and(|d| d <= at)) {
            self.send_lldp(cx, driver, io, at);
        }
        let lldp = self.lldp_next.filter(|_| up);
        self.others_next = earliest(
            earliest(lldp, self.tcp.deadline()),
            earliest(acd, self.stack_hold.until(frames.rx.is_full(), at)),
        );
    }

    /// Runs the encapsulation TCP's timers and sends what it owes; another task's deadline
    /// its requests moved (a Forward_Open) is asked in this pass. Out of line: not on the
    /// Class 1 path.
    #[inline(never)]
    pub(super) fn serve_tcp<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        io: &dyn IoPort,
        me: &NetworkConfig,
        at: Instant,
    ) {
        let from = tcp_link::LocalEnd {
            mac: self.mac,
            me,
            usable: self.guard.usable(),
        };
        let neighbors = (&mut self.neighbors, &self.sums);
        if !self.tcp.serve((cx, driver), io, &from, neighbors, at) {
            self.blocked = true;
        }
        if io.deadline_moved() {
            self.io_stale = true;
        }
    }

    /// Passes `frame` to the stack (true) unless a checksum the stack would have found bad
    /// drops it here, in its place (`STACK_SUMS`); checked in its queue slot.
    fn pass_checked(&self, frame: &[u8], frames: &LinkFrames) -> bool {
        let sums = &self.sums;
        let pushed = frames.rx.push(frame.len(), |room| {
            // A frame longer than a queue slot is cut short, and the stack drops it.
            copy(room, frame);
            stack_sums::each(room, sums, false)
        });
        let kept = !matches!(pushed, Ok(false));
        if !kept {
            frames.rx.drop_last();
        }
        kept
    }

    /// Sends the frames the stack queued, explicit messaging marked with its DSCP; drops them
    /// while the address may not be used (but those of a DHCP client). True if it sent any.
    #[inline(never)]
    pub(super) fn send_stack_frames<D: Driver>(
        &mut self,
        cx: &mut Context<'_>,
        driver: &mut D,
        frames: &LinkFrames,
        io: &dyn IoPort,
    ) -> bool {
        if frames.tx.is_empty() {
            return false;
        }
        let dscp = io.explicit_dscp();
        let sums = &self.sums;
        // With the stack's checksums done here, every one is filled after the marking.
        let none = ChecksumCapabilities::ignored();
        let mark_sums = if STACK_SUMS { &none } else { sums };
        // The stack waits for room only when it found the queue full (`NetDriver`).
        let was_full = frames.tx.is_full();
        let mut sent = false;
        let usable = self.guard.usable();
        for _ in 0..TX_FRAMES {
            if frames.tx.is_empty() {
                break;
            }
            let Some(tx) = driver.transmit(cx) else {
                break;
            };
            let _ = frames.tx.pop(|frame| {
                if usable || passes_unaddressed(frame) {
                    dscp::mark_explicit(frame, dscp, mark_sums);
                    if STACK_SUMS {
                        stack_sums::each(frame, sums, true);
                    }
                    send_copy(tx, frame);
                }
            });
            sent = true;
        }
        if sent && was_full {
            frames.wake_stack();
        }
        sent
    }
}
