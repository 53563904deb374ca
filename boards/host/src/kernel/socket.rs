//! Creating the runtime's kernel sockets: non-blocking, close-on-exec, and bound with
//! `SO_REUSEADDR` (the wildcard and the unicast UDP 44818 sockets share a port, and the TCP
//! listener is bound again while earlier connections linger).

use std::io;
use std::net::{SocketAddrV4, TcpListener, UdpSocket};

use socket2::{Domain, Protocol, Socket, Type};

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
