//! UDP port 44818: ListIdentity and friends, answered at once or, for a broadcast, after the
//! delay the stack chooses.
//!
//! Two sockets share the port: `unicast`, bound to the adapter's address, receives what is
//! sent to it and sends every reply (so replies come from that address); `broadcast`, bound to
//! the wildcard address, receives the broadcasts a socket bound to a unicast address never
//! sees, with `IP_PKTINFO` telling their destination (which the stack needs to tell a
//! broadcast) and arrival interface (datagrams from other interfaces are ignored).

use std::io;
use std::mem::{size_of, zeroed};
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, UdpSocket};
use std::os::fd::AsRawFd;

use enip_stack::config::ENCAP_PORT;
use enip_stack::{Adapter, Device, Instant};

use super::socket::{set_dscp, udp_socket};

/// The sockets of UDP port 44818.
pub struct Udp {
    /// Bound to the adapter's address: unicast requests, and every reply.
    pub unicast: UdpSocket,
    /// Bound to the wildcard address: broadcasts.
    pub broadcast: UdpSocket,
    /// The adapter's address.
    ip: Ipv4Addr,
    /// The interface broadcasts must arrive on.
    if_index: u32,
}

impl Udp {
    /// Binds both sockets to port 44818 for the address `ip` on interface `if_index`.
    pub fn open(ip: Ipv4Addr, if_index: u32) -> io::Result<Self> {
        let unicast = udp_socket(SocketAddrV4::new(ip, ENCAP_PORT))?;
        let broadcast = udp_socket(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, ENCAP_PORT))?;
        let on: libc::c_int = 1;
        // SAFETY: setsockopt with a valid int option value of the size given.
        let r = unsafe {
            libc::setsockopt(
                broadcast.as_raw_fd(),
                libc::IPPROTO_IP,
                libc::IP_PKTINFO,
                (&on as *const libc::c_int).cast(),
                size_of::<libc::c_int>() as libc::socklen_t,
            )
        };
        if r != 0 {
            return Err(io::Error::last_os_error());
        }
        Ok(Udp {
            unicast,
            broadcast,
            ip,
            if_index,
        })
    }

    /// Marks the replies (all sent from the unicast socket) with `dscp`.
    pub fn set_dscp(&self, dscp: u8) -> io::Result<()> {
        set_dscp(&self.unicast, dscp)
    }

    /// Answers one datagram waiting on the unicast socket, if any.
    pub fn serve_unicast<D: Device>(
        &self,
        adapter: &mut Adapter<D>,
        now: Instant,
        rx: &mut [u8],
        tx: &mut [u8],
    ) {
        let (len, from, to) = match self.unicast.recv_from(rx) {
            Ok((len, SocketAddr::V4(from))) => (len, from, self.ip),
            Ok(_) => return,
            Err(e) => return log_error("udp 44818 receive", &e),
        };
        self.answer(adapter, now, rx.get(..len).unwrap_or(&[]), from, to, tx);
    }

    /// Answers one broadcast waiting on the wildcard socket, if any (ignored unless it came
    /// in on the adapter's interface).
    pub fn serve_broadcast<D: Device>(
        &self,
        adapter: &mut Adapter<D>,
        now: Instant,
        rx: &mut [u8],
        tx: &mut [u8],
    ) {
        match recv_with_destination(&self.broadcast, rx) {
            Ok(Some((len, from, to, index))) if index == self.if_index => {
                self.answer(adapter, now, rx.get(..len).unwrap_or(&[]), from, to, tx)
            }
            Ok(_) => {}
            Err(e) => log_error("udp 44818 broadcast receive", &e),
        }
    }

    /// Sends every delayed reply that is due at `now`.
    pub fn send_due<D: Device>(&self, adapter: &mut Adapter<D>, now: Instant, tx: &mut [u8]) {
        // Bounded by the stack's queue of delayed replies.
        for _ in 0..enip_stack::config::MAX_PENDING_LIST_IDENTITY {
            let Some((to, len)) = adapter.poll_udp(now, tx) else {
                return;
            };
            self.send(tx.get(..len).unwrap_or(&[]), to);
        }
    }

    fn answer<D: Device>(
        &self,
        adapter: &mut Adapter<D>,
        now: Instant,
        data: &[u8],
        from: SocketAddrV4,
        to: Ipv4Addr,
        tx: &mut [u8],
    ) {
        let len = adapter.udp_receive(from, to, data, now, tx);
        if len > 0 {
            self.send(tx.get(..len).unwrap_or(&[]), from);
        }
    }

    fn send(&self, data: &[u8], to: SocketAddrV4) {
        if let Err(e) = self.unicast.send_to(data, to) {
            log::warn!("udp reply to {to}: {e}");
        }
    }
}

/// Logs a receive error other than "nothing waiting".
fn log_error(what: &str, e: &io::Error) {
    if e.kind() != io::ErrorKind::WouldBlock {
        log::warn!("{what}: {e}");
    }
}

/// Receives one datagram with its destination address and arrival interface
/// (`IP_PKTINFO`); `None` for one without that information or not from IPv4.
fn recv_with_destination(
    socket: &UdpSocket,
    buf: &mut [u8],
) -> io::Result<Option<(usize, SocketAddrV4, Ipv4Addr, u32)>> {
    // Room for one in_pktinfo control message, aligned for cmsghdr.
    let mut control = [0u64; 8];
    // SAFETY: all-zero sockaddr_in and msghdr are valid; the pointers set below stay valid
    // for the recvmsg call.
    let mut from: libc::sockaddr_in = unsafe { zeroed() };
    let mut iov = libc::iovec {
        iov_base: buf.as_mut_ptr().cast(),
        iov_len: buf.len(),
    };
    let mut msg: libc::msghdr = unsafe { zeroed() };
    msg.msg_name = (&mut from as *mut libc::sockaddr_in).cast();
    msg.msg_namelen = size_of::<libc::sockaddr_in>() as libc::socklen_t;
    msg.msg_iov = &mut iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control.as_mut_ptr().cast();
    msg.msg_controllen = size_of::<[u64; 8]>() as _;
    // SAFETY: `msg` describes valid buffers (name, one iovec over `buf`, control) owned by
    // this frame.
    let n = unsafe { libc::recvmsg(socket.as_raw_fd(), &mut msg, libc::MSG_DONTWAIT) };
    if n < 0 {
        return Err(io::Error::last_os_error());
    }
    if i32::from(from.sin_family) != libc::AF_INET {
        return Ok(None);
    }
    let source = SocketAddrV4::new(
        Ipv4Addr::from(u32::from_be(from.sin_addr.s_addr)),
        u16::from_be(from.sin_port),
    );
    // SAFETY: CMSG_FIRSTHDR/CMSG_NXTHDR walk the control buffer the kernel filled, within
    // `msg_controllen`; an IP_PKTINFO message carries an in_pktinfo, read unaligned.
    let mut cmsg = unsafe { libc::CMSG_FIRSTHDR(&msg) };
    while let Some(c) = unsafe { cmsg.as_ref() } {
        if c.cmsg_level == libc::IPPROTO_IP && c.cmsg_type == libc::IP_PKTINFO {
            let info: libc::in_pktinfo =
                unsafe { std::ptr::read_unaligned(libc::CMSG_DATA(c).cast()) };
            let to = Ipv4Addr::from(u32::from_be(info.ipi_addr.s_addr));
            let index = u32::try_from(info.ipi_ifindex).unwrap_or(0);
            return Ok(Some((n as usize, source, to, index)));
        }
        cmsg = unsafe { libc::CMSG_NXTHDR(&msg, c) };
    }
    Ok(None)
}
