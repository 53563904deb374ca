//! The loop of the kernel sockets runtime: any number of [`Node`]s on one thread, each woken
//! only by its own sockets or its own deadline.
//!
//! One `epoll` set ([`Epoll`]) holds every node's sockets under keys naming the node; the
//! nodes' next deadlines are kept in a binary heap. Each turn wakes the nodes whose deadline
//! passed (popping the heap), waits until the earliest remaining deadline or a socket, and
//! wakes the nodes whose sockets became ready: the work of a wake-up is that of the nodes it
//! concerns, whatever the number of nodes (a heap push or pop is `O(log n)`). One netlink
//! watch serves them all: an interface change (rare) reads every node's interface again.
//!
//! One thread rather than one per device: a device's work per Class 1 cycle is a few
//! microseconds, so one thread holds hundreds of devices at a 10 ms RPI, without locks and
//! without a thread's stack and scheduling per device; a fleet larger than one core can
//! serve is split into several processes, each its own loop.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use enip_stack::{Device, Instant};

use super::node::{Node, SLOTS};
use super::poll::{until, Clock, Epoll};
use super::DATAGRAM_LEN;
use crate::device_log;
use crate::netlink::Watch;

/// The key of the netlink watch (no node's).
const WATCH: u64 = u64::MAX;

/// The nodes, their wait, their deadlines, and the buffers they share.
pub struct Fleet<D: Device> {
    nodes: Vec<Node<D>>,
    epoll: Epoll,
    watch: Watch,
    /// Each node's queued deadline as (microseconds, node); an entry whose node has since
    /// queued another deadline is stale and skipped when popped.
    deadlines: BinaryHeap<Reverse<(u64, usize)>>,
    /// The nodes with a socket ready in the last wait, once each.
    woken: Vec<usize>,
    /// Every received datagram.
    rx: Box<[u8; DATAGRAM_LEN]>,
    /// Every datagram built: replies and T->O data.
    tx: Box<[u8; DATAGRAM_LEN]>,
    clock: Clock,
}

impl<D: Device> Fleet<D> {
    /// The loop of `nodes`, their sockets registered, the netlink `watch` with them.
    pub fn new(mut nodes: Vec<Node<D>>, watch: Watch) -> std::io::Result<Self> {
        // Room for every descriptor: after a stall of the process, every socket that became
        // ready meanwhile is served before any deadline's work.
        let epoll = Epoll::new(nodes.len() * SLOTS as usize + 1)?;
        epoll.watch(watch.fd(), WATCH, true, false)?;
        for (base, node) in (0..).step_by(SLOTS as usize).zip(nodes.iter_mut()) {
            node.register(&epoll, base)?;
        }
        let count = nodes.len();
        Ok(Fleet {
            nodes,
            epoll,
            watch,
            deadlines: BinaryHeap::with_capacity(4 * count),
            woken: Vec::with_capacity(count),
            rx: Box::new([0; DATAGRAM_LEN]),
            tx: Box::new([0; DATAGRAM_LEN]),
            clock: Clock,
        })
    }

    /// Runs the nodes for ever; returns only the error of a failed wait.
    pub fn run(mut self) -> std::io::Error {
        let now = self.clock.now();
        for index in 0..self.nodes.len() {
            self.wake(index, now);
        }
        loop {
            let now = self.clock.now();
            self.wake_due(now);
            let timeout = self
                .deadlines
                .peek()
                .map(|Reverse((at, _))| until(now, Instant::from_micros(*at)));
            let (nodes, woken) = (&mut self.nodes, &mut self.woken);
            let mut watch_ready = false;
            let waited = self.epoll.wait(timeout, |ready| {
                if ready.key == WATCH {
                    watch_ready = true;
                    return;
                }
                let index = (ready.key / SLOTS) as usize;
                if let Some(node) = nodes.get_mut(index) {
                    if !node.woken {
                        node.woken = true;
                        woken.push(index);
                    }
                    node.mark(ready.key % SLOTS, ready.readable, ready.writable);
                }
            });
            if let Err(e) = waited {
                return e;
            }
            let now = self.clock.now();
            if watch_ready {
                self.interfaces_changed();
            }
            let mut woken = std::mem::take(&mut self.woken);
            for index in woken.drain(..) {
                self.wake(index, now);
            }
            self.woken = woken;
        }
    }

    /// Wakes every node whose queued deadline is at or before `now`.
    fn wake_due(&mut self, now: Instant) {
        // Bounded by the heap, which holds at most one live entry per node.
        while let Some(&Reverse((at, index))) = self.deadlines.peek() {
            if at > now.as_micros() {
                return;
            }
            self.deadlines.pop();
            let Some(node) = self.nodes.get_mut(index) else {
                continue;
            };
            if node.queued == Some(Instant::from_micros(at)) {
                node.queued = None;
                self.wake(index, now);
            }
        }
    }

    /// Wakes node `index`: what became ready, what is due; queues its next deadline unless
    /// the heap holds it already.
    fn wake(&mut self, index: usize, now: Instant) {
        let Some(node) = self.nodes.get_mut(index) else {
            return;
        };
        device_log::set_current(node.label);
        node.woken = false;
        let base = index as u64 * SLOTS;
        let next = node.wake(
            &self.epoll,
            base,
            now,
            self.rx.as_mut_slice(),
            self.tx.as_mut_slice(),
        );
        if next != node.queued {
            // The entry of the deadline it replaces, if any, goes stale.
            node.queued = next;
            if let Some(at) = next {
                self.deadlines.push(Reverse((at.as_micros(), index)));
            }
        }
        device_log::set_current(None);
    }

    /// After a netlink notification: every node reads its interface again.
    fn interfaces_changed(&mut self) {
        self.watch.drain(self.rx.as_mut_slice());
        for node in &mut self.nodes {
            device_log::set_current(node.label);
            node.refresh_interface();
        }
        device_log::set_current(None);
    }
}
