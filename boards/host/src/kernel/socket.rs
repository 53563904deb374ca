//! Creating the runtime's kernel sockets: non-blocking, close-on-exec, and bound with
//! `SO_REUSEADDR` (the wildcard and the unicast UDP 44818 sockets share a port, and the TCP
//! listener is bound again while earlier connections linger); and the DSCP (QoS object) the
//! kernel marks a socket's packets with.

use std::io;
use std::net::{SocketAddrV4, TcpListener, UdpSocket};

use socket2::{Domain, Protocol, SockRef, Socket, Type};

/// Connections the kernel may hold before the runtime accepts them.
pub const BACKLOG: usize = 8;

/// A non-blocking UDP socket bound to `addr`.
pub fn udp_socket(addr: SocketAddrV4) -> io::Result<UdpSocket> {
    let s = Socket::new(Domain::IPV4, Type::DGRAM, Some(Protocol::UDP))?;
    s.set_reuse_address(true)?;
    s.set_nonblocking(true)?;
    s.bind(&addr.into())?;
    Ok(s.into())
}

/// A non-blocking TCP listener on `addr`.
pub fn tcp_listener(addr: SocketAddrV4) -> io::Result<TcpListener> {
    let s = Socket::new(Domain::IPV4, Type::STREAM, Some(Protocol::TCP))?;
    s.set_reuse_address(true)?;
    s.set_nonblocking(true)?;
    s.bind(&addr.into())?;
    s.listen(BACKLOG as i32)?;
    Ok(s.into())
}

/// Has the kernel mark the IPv4 packets of `socket` with `dscp` (`IP_TOS`: the DSCP in the
/// upper six bits of the DS field, ECN left to the kernel). A TCP listener's accepted
/// connections inherit it.
pub fn set_dscp<'s>(socket: impl Into<SockRef<'s>>, dscp: u8) -> io::Result<()> {
    socket.into().set_tos_v4(u32::from(dscp & 0x3F) << 2)
}
