//! What the runtime needs from a board: the number of embassy-net sockets, and the socket
//! buffers (usually placed in a `static`).

use embassy_net::udp::PacketMetadata;
use embassy_net::StackResources;
use enip_stack::config::{MAX_ENCAP_FRAME, MAX_SESSIONS};

/// Sockets [`crate::run`] opens on the embassy-net stack: a TCP socket per encapsulation
/// session on port 44818 (3), a UDP socket on 44818, and two UDP sockets on 2222
/// (point-to-point and multicast T->O). A board using DHCP adds one for the DHCP client.
pub const SOCKETS: usize = MAX_SESSIONS + 1 + 2;

/// The embassy-net `StackResources` for `N` sockets, refusing fewer than [`SOCKETS`]: in a
/// `static` or `const` initializer the refusal is a compile error, otherwise a panic with
/// this message at start-up (rather than smoltcp's "adding a socket to a full SocketSet"
/// deep inside the runtime).
pub const fn stack_resources<const N: usize>() -> StackResources<N> {
    assert!(
        N >= SOCKETS,
        "embassy-net StackResources too small: the EtherNet/IP runtime needs enip_firmware::SOCKETS (6) sockets, plus one for DHCP"
    );
    StackResources::new()
}

/// Receive window of each encapsulation TCP socket, in bytes.
pub const TCP_RX_LEN: usize = 2048;
/// Transmit buffer of each encapsulation TCP socket, in bytes.
pub const TCP_TX_LEN: usize = 2048;
/// Datagrams the UDP 44818 socket can hold in each direction.
pub const UDP_PACKETS: usize = 4;
/// Payload bytes the UDP 44818 socket can hold in each direction.
pub const UDP_BUFFER_LEN: usize = 1536;

/// Buffers of one encapsulation TCP socket.
pub(crate) struct TcpBuffers {
    pub rx: [u8; TCP_RX_LEN],
    pub tx: [u8; TCP_TX_LEN],
    pub reply: [u8; MAX_ENCAP_FRAME],
}

/// Buffers of the UDP 44818 socket.
pub(crate) struct UdpBuffers {
    pub rx_meta: [PacketMetadata; UDP_PACKETS],
    pub rx: [u8; UDP_BUFFER_LEN],
    pub tx_meta: [PacketMetadata; UDP_PACKETS],
    pub tx: [u8; UDP_BUFFER_LEN],
    pub reply: [u8; MAX_ENCAP_FRAME],
}

/// Datagrams each UDP 2222 socket can hold in each direction.
pub const IO_PACKETS: usize = 16;
/// Payload bytes each UDP 2222 socket can hold in each direction.
pub const IO_BUFFER_LEN: usize = 4096;
/// Largest T->O datagram: I/O header, sequence count and the largest assembly.
pub const IO_DATAGRAM_LEN: usize =
    enip_stack::wire::io_datagram::HEADER_LEN + 2 + enip_stack::config::MAX_ASSEMBLY_SIZE;

/// Buffers of one UDP 2222 socket.
pub(crate) struct IoSocketBuffers {
    pub rx_meta: [PacketMetadata; IO_PACKETS],
    pub rx: [u8; IO_BUFFER_LEN],
    pub tx_meta: [PacketMetadata; IO_PACKETS],
    pub tx: [u8; IO_BUFFER_LEN],
}

/// Buffers of Class 1 I/O: the point-to-point and multicast sockets, and the datagram being built.
pub(crate) struct IoBuffers {
    pub unicast: IoSocketBuffers,
    pub multicast: IoSocketBuffers,
    pub out: [u8; IO_DATAGRAM_LEN],
}

/// Every buffer [`crate::run`] uses; create one with [`Resources::new`] in a `static` cell.
pub struct Resources {
    pub(crate) tcp: [TcpBuffers; MAX_SESSIONS],
    pub(crate) udp: UdpBuffers,
    pub(crate) io: IoBuffers,
}

impl Resources {
    /// Zeroed buffers (a `const fn`, so a board can place them in `.bss`).
    pub const fn new() -> Self {
        const TCP: TcpBuffers = TcpBuffers {
            rx: [0; TCP_RX_LEN],
            tx: [0; TCP_TX_LEN],
            reply: [0; MAX_ENCAP_FRAME],
        };
        const IO: IoSocketBuffers = IoSocketBuffers {
            rx_meta: [PacketMetadata::EMPTY; IO_PACKETS],
            rx: [0; IO_BUFFER_LEN],
            tx_meta: [PacketMetadata::EMPTY; IO_PACKETS],
            tx: [0; IO_BUFFER_LEN],
        };
        Resources {
            tcp: [TCP; MAX_SESSIONS],
            udp: UdpBuffers {
                rx_meta: [PacketMetadata::EMPTY; UDP_PACKETS],
                rx: [0; UDP_BUFFER_LEN],
                tx_meta: [PacketMetadata::EMPTY; UDP_PACKETS],
                tx: [0; UDP_BUFFER_LEN],
                reply: [0; MAX_ENCAP_FRAME],
            },
            io: IoBuffers {
                unicast: IO,
                multicast: IO,
                out: [0; IO_DATAGRAM_LEN],
            },
        }
    }
}

impl Default for Resources {
    fn default() -> Self {
        Self::new()
    }
}
