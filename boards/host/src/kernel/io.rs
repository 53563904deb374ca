//! Class 1 implicit I/O on UDP 2222: O->T datagrams into the adapter, T->O production at the
//! adapter's deadlines, multicast group membership on the bound interface and the TCP/IP
//! object's TTL.
//!
//! One socket, bound to the adapter's address, does all of it: the kernel applies the
//! multicast TTL to multicast destinations only, and `IP_MULTICAST_IF` sends the group's
//! datagrams out of the bound interface. Each datagram carries its connection's DSCP: the
//! socket's `IP_TOS` is changed only when a datagram's DSCP differs from the last one's.

use std::cell::Cell;
use std::io;
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, UdpSocket};

use enip_stack::config::{IO_PORT, MAX_CONNECTIONS};
use enip_stack::{Adapter, Device, Instant};
use socket2::SockRef;

use super::socket::{set_dscp, udp_socket};

/// The Class 1 socket and the multicast state it is in.
pub struct Io {
    /// Bound to port 2222 of the adapter's address.
    pub socket: UdpSocket,
    /// The adapter's address (the interface multicast is joined and sent on).
    ip: Ipv4Addr,
    /// The group joined, if any.
    joined: Option<Ipv4Addr>,
    /// The multicast TTL set on the socket.
    ttl: u8,
    /// The DSCP set on the socket (the last T->O datagram's).
    dscp: Cell<u8>,
}

impl Io {
    /// Binds UDP 2222 on `ip`, sending multicast out of that address's interface.
    pub fn open(ip: Ipv4Addr) -> io::Result<Self> {
        let socket = udp_socket(SocketAddrV4::new(ip, IO_PORT))?;
        let s = SockRef::from(&socket);
        s.set_multicast_if_v4(&ip)?;
        // The adapter's own T->O data is of no use to itself.
        s.set_multicast_loop_v4(false)?;
        s.set_multicast_ttl_v4(1)?;
        Ok(Io {
            socket,
            ip,
            joined: None,
            ttl: 1,
            dscp: Cell::new(0),
        })
    }

    /// Hands one waiting O->T datagram to the adapter, if any; false if none was waiting
    /// (or the socket failed).
    pub fn consume<D: Device>(
        &self,
        adapter: &mut Adapter<D>,
        now: Instant,
        rx: &mut [u8],
    ) -> bool {
        match self.socket.recv_from(rx) {
            Ok((len, SocketAddr::V4(from))) => {
                // A discarded datagram is counted by the adapter; nothing to answer.
                let _ = adapter.io_receive(from, rx.get(..len).unwrap_or(&[]), now);
                true
            }
            Ok(_) => true,
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => false,
            Err(e) => {
                log::warn!("udp {IO_PORT} receive: {e}");
                false
            }
        }
    }

    /// Sends every T->O datagram due at `now`, built in `tx`.
    pub fn produce<D: Device>(&self, adapter: &mut Adapter<D>, now: Instant, tx: &mut [u8]) {
        // Bounded: each call either produces or returns None, and each producer is due once.
        for _ in 0..MAX_CONNECTIONS * 2 {
            let Some(due) = adapter.io_due(now) else {
                return;
            };
            let (to, len) = (due.to, adapter.write_io(due, now, Some(&mut *tx)));
            if len == 0 {
                // `tx` too short for it: nothing changed, and nothing more can be sent.
                return;
            }
            if due.dscp != self.dscp.get() {
                match set_dscp(&self.socket, due.dscp) {
                    Ok(()) => self.dscp.set(due.dscp),
                    Err(e) => log::warn!("io dscp {}: {e}", due.dscp),
                }
            }
            if let Err(e) = self.socket.send_to(tx.get(..len).unwrap_or(&[]), to) {
                log::warn!("io to {to}: {e}");
            }
        }
    }

    /// Joins the T->O multicast group while multicast connections exist, leaves it after,
    /// and keeps the socket's multicast TTL at the TCP/IP object's while it sends multicast.
    pub fn track_multicast<D: Device>(&mut self, adapter: &Adapter<D>) {
        let want = adapter.multicast_group();
        if want.is_none() && self.joined.is_none() {
            // No multicast datagram goes out: the TTL is set once one will.
            return;
        }
        let s = SockRef::from(&self.socket);
        let ttl = adapter.multicast_ttl();
        if ttl != self.ttl {
            match s.set_multicast_ttl_v4(u32::from(ttl)) {
                Ok(()) => self.ttl = ttl,
                Err(e) => log::warn!("multicast ttl {ttl}: {e}"),
            }
        }
        if want == self.joined {
            return;
        }
        if let Some(old) = self.joined.take() {
            if let Err(e) = s.leave_multicast_v4(&old, &self.ip) {
                log::warn!("leave {old}: {e}");
            }
        }
        if let Some(new) = want {
            match s.join_multicast_v4(&new, &self.ip) {
                Ok(()) => self.joined = Some(new),
                Err(e) => log::warn!("join {new}: {e}"),
            }
        }
    }
}
