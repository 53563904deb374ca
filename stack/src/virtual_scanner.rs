//! A scanner in virtual time, for a device's own tests: it drives an [`Adapter`] through its
//! entry points as a PLC would over the network (a registered session, explicit requests,
//! Forward_Open, Class 1 data both ways) with no socket and no clock, so a device's
//! admission rules, assemblies and connection behaviour are tested in `cargo test`.
//!
//! ```
//! # use enip_stack::virtual_scanner::VirtualScanner;
//! # fn check<D: enip_stack::Device>(device: D) {
//! let mut scanner = VirtualScanner::new(device);
//! // Identity attribute 1 (vendor ID): Get_Attribute_Single of class 1, instance 1.
//! let vendor = scanner.unconnected(&[0x0E, 3, 0x20, 0x01, 0x24, 0x01, 0x30, 0x01]);
//! assert_eq!(vendor.map(|(general, _, _)| general), Some(0));
//! # }
//! ```

use core::net::{Ipv4Addr, SocketAddrV4};

use crate::adapter::{Adapter, SocketId};
use crate::config::{IO_PORT, MAX_ENCAP_FRAME, MAX_SESSIONS};
use crate::device::Device;
use crate::io::consume::{Accepted, Discard};
use crate::net::NetworkConfig;
use crate::originator;
use crate::time::{Duration, Instant};
use crate::wire::forward_open::{ForwardOpenReplyRepr, ForwardOpenRepr};
use crate::wire::io_datagram::{Packet, SEQUENCE_LEN};
use crate::wire::Writer;

/// The adapter's address on its virtual network.
pub const ADAPTER_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
/// The scanner's address.
pub const SCANNER_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
/// The TCP port the scanner's session on socket 0 comes from (socket `n`: this plus `n`).
const SCANNER_TCP_PORT: u16 = 50_000;
/// Forward_Open, on the Connection Manager (class 6, instance 1).
const FORWARD_OPEN: [u8; 6] = [0x54, 0x02, 0x20, 0x06, 0x24, 0x01];
/// Longest wait [`VirtualScanner::advance`] takes in one step.
const MAX_STEP: Duration = Duration(1_000_000);
/// The most steps one [`VirtualScanner::advance`] takes (a bound, not an expected count).
const MAX_STEPS: u32 = 1_000_000;

/// The outcome of a Forward_Open.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Opened {
    /// General status (0: the connection is open).
    pub general: u8,
    /// The first extended status word, if any.
    pub extended: Option<u16>,
    /// The O->T connection ID the adapter chose (0 if refused).
    pub o_t_id: u32,
    /// The T->O connection ID (0 if refused).
    pub t_o_id: u32,
}

/// A scanner with registered sessions on an adapter (one to begin with), and the adapter's
/// virtual time.
pub struct VirtualScanner<D: Device> {
    adapter: Adapter<D>,
    /// The session handle on each TCP socket, if one is registered.
    sessions: [Option<u32>; MAX_SESSIONS],
    /// The socket requests go on.
    socket: u8,
    now: Instant,
    /// When the device last asked to run again ([`Device::poll`]).
    device_next: Option<Instant>,
    io_sequence: u32,
    frame: [u8; MAX_ENCAP_FRAME],
    reply: [u8; MAX_ENCAP_FRAME],
}

impl<D: Device> VirtualScanner<D> {
    /// An adapter for `device` at [`ADAPTER_IP`]/24 at time 0, with the scanner's session
    /// registered on it.
    pub fn new(device: D) -> Self {
        let net = NetworkConfig::new_static(
            ADAPTER_IP,
            Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 2],
        );
        let mut scanner = VirtualScanner {
            adapter: Adapter::new(device, net, 7),
            sessions: [None; MAX_SESSIONS],
            socket: 0,
            now: Instant(0),
            device_next: None,
            io_sequence: 0,
            frame: [0; MAX_ENCAP_FRAME],
            reply: [0; MAX_ENCAP_FRAME],
        };
        scanner.open_session(0);
        scanner
    }

    /// Opens a TCP connection on the adapter's socket `socket`, registers a session on it,
    /// and sends what follows there; the session handle.
    pub fn open_session(&mut self, socket: u8) -> Option<u32> {
        let port = SCANNER_TCP_PORT.saturating_add(u16::from(socket));
        let peer = SocketAddrV4::new(SCANNER_IP, port);
        self.adapter.tcp_accept(SocketId(socket), peer, self.now);
        self.socket = socket;
        let mut request = [0u8; 28];
        let n = originator::register_session(&mut request).ok()?;
        let handle = self
            .tcp(request.get(..n)?)
            .get(4..8)
            .and_then(|h| h.try_into().ok())
            .map(u32::from_le_bytes)?;
        *self.sessions.get_mut(usize::from(socket))? = Some(handle);
        Some(handle)
    }

    /// Sends what follows on the session already open on socket `socket`.
    pub fn select_session(&mut self, socket: u8) {
        self.socket = socket;
    }

    /// The adapter.
    pub fn adapter(&self) -> &Adapter<D> {
        &self.adapter
    }

    /// The adapter, mutably (e.g. to reach the device).
    pub fn adapter_mut(&mut self) -> &mut Adapter<D> {
        &mut self.adapter
    }

    /// The device, once the test is done with the adapter.
    pub fn into_device(self) -> D {
        self.adapter.into_device()
    }

    /// The current virtual time.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// The handle of the session requests go on (0 if none is registered).
    pub fn session(&self) -> u32 {
        self.sessions
            .get(usize::from(self.socket))
            .copied()
            .flatten()
            .unwrap_or(0)
    }

    /// Sends an encapsulation frame on the current session's TCP connection now; the reply
    /// frame.
    pub fn tcp(&mut self, frame: &[u8]) -> &[u8] {
        let socket = SocketId(self.socket);
        let out = self
            .adapter
            .tcp_receive(socket, frame, self.now, &mut self.reply);
        self.reply.get(..out.reply_len).unwrap_or(&[])
    }

    /// Sends a Message Router request (service, path size, path, data) unconnected in a
    /// SendRRData frame; the response's general status, first extended status word and data,
    /// or `None` if no response came back.
    pub fn unconnected(&mut self, request: &[u8]) -> Option<(u8, Option<u16>, &[u8])> {
        let session = self.session();
        let n =
            originator::send_rr_data(&mut self.frame, session, None, |w| w.bytes(request)).ok()?;
        self.exchange(n)
    }

    /// Sends a Message Router request on Class 3 connection `o_t_id` with sequence count
    /// `sequence` in a SendUnitData frame; like [`Self::unconnected`].
    pub fn connected(
        &mut self,
        o_t_id: u32,
        sequence: u16,
        request: &[u8],
    ) -> Option<(u8, Option<u16>, &[u8])> {
        let session = self.session();
        let n = originator::send_unit_data(&mut self.frame, session, o_t_id, sequence, |w| {
            w.bytes(request)
        })
        .ok()?;
        self.exchange(n)
    }

    /// Sends the first `n` bytes of the request frame; the parsed response.
    fn exchange(&mut self, n: usize) -> Option<(u8, Option<u16>, &[u8])> {
        let frame = self.frame.get(..n)?;
        let socket = SocketId(self.socket);
        let out = self
            .adapter
            .tcp_receive(socket, frame, self.now, &mut self.reply);
        let reply = originator::parse_reply(self.reply.get(..out.reply_len)?).ok()?;
        let r = reply.response?;
        Some((r.general_status, r.extended_status(), r.data))
    }

    /// Sends `fo` to the Connection Manager; what the adapter answered.
    pub fn forward_open(&mut self, fo: &ForwardOpenRepr<'_>) -> Opened {
        let mut request = [0u8; 256];
        let mut w = Writer::new(&mut request);
        let written = w.bytes(&FORWARD_OPEN).and_then(|()| fo.emit(&mut w));
        let len = w.len();
        let refused = Opened {
            general: 0xFF,
            extended: None,
            o_t_id: 0,
            t_o_id: 0,
        };
        if written.is_err() {
            return refused;
        }
        let Some((general, extended, data)) = self.unconnected(request.get(..len).unwrap_or(&[]))
        else {
            return refused;
        };
        let ids = ForwardOpenReplyRepr::parse(data)
            .ok()
            .filter(|_| general == 0)
            .map_or((0, 0), |r| (r.o_t_connection_id, r.t_o_connection_id));
        Opened {
            general,
            extended,
            o_t_id: ids.0,
            t_o_id: ids.1,
        }
    }

    /// Sends a Class 1 O->T datagram on connection `o_t_id` now, with the next sequence
    /// numbers and, if `run` is given, the run/idle header; what the adapter made of it.
    pub fn send_io(
        &mut self,
        o_t_id: u32,
        run: Option<bool>,
        data: &[u8],
    ) -> Result<Accepted, Discard> {
        self.io_sequence = self.io_sequence.wrapping_add(1);
        let n = originator::io_datagram(
            &mut self.frame,
            o_t_id,
            self.io_sequence,
            self.io_sequence as u16,
            run,
            data,
        )
        .map_err(|_| Discard::Malformed)?;
        let datagram = self.frame.get(..n).ok_or(Discard::Malformed)?;
        let from = SocketAddrV4::new(SCANNER_IP, IO_PORT);
        self.adapter.io_receive(from, datagram, self.now)
    }

    /// Moves virtual time `us` microseconds on, stopping now and at every later instant the
    /// adapter or the device has work (productions, watchdogs, [`Device::poll`]); hands each
    /// T->O datagram produced to `on_t_o` with its destination and its data after the
    /// sequence count. Returns how many were produced.
    pub fn advance(&mut self, us: u64, mut on_t_o: impl FnMut(SocketAddrV4, &[u8])) -> usize {
        let end = self.now.add(Duration(us));
        let mut produced = 0usize;
        for step in 0..MAX_STEPS {
            if step > 0 {
                // Time moves on by at least a microsecond, so a deadline that stays due
                // cannot hold it still.
                let soonest = self.now.add(Duration(1));
                self.now = [self.adapter.next_deadline(), self.device_next]
                    .into_iter()
                    .flatten()
                    .fold(end.min(self.now.add(MAX_STEP)), Instant::min)
                    .max(soonest)
                    .min(end);
            }
            self.device_next = self.adapter.poll_device(self.now);
            while let Some((to, n)) = self.adapter.poll_io(self.now, &mut self.reply) {
                produced = produced.saturating_add(1);
                let datagram = self.reply.get(..n).unwrap_or(&[]);
                if let Ok(p) = Packet::new_checked(datagram) {
                    on_t_o(to, p.connected_data().get(SEQUENCE_LEN..).unwrap_or(&[]));
                }
            }
            if self.now >= end {
                break;
            }
        }
        produced
    }
}
