//! What the runtime needs from a board: the number of embassy-net sockets, and the socket
//! buffers (usually placed in a `static`).

use embassy_net::udp::PacketMetadata;
use embassy_net::StackResources;
use enip_stack::config::{MAX_ASSEMBLY_SIZE, MAX_CONNECTIONS, MAX_ENCAP_FRAME, MAX_SESSIONS};
use enip_stack::wire::io_datagram::HEADER_LEN;

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

/// Datagrams each UDP 2222 buffer can hold: one per connection.
pub const IO_PACKETS: usize = MAX_CONNECTIONS;
/// Payload bytes of each UDP 2222 buffer: a datagram per connection with assemblies of up to
/// 180 bytes, or two datagrams with the largest assembly. (A full transmit buffer makes the
/// I/O future wait for the network runner to send, not drop data.)
pub const IO_BUFFER_LEN: usize = 2048;
/// The largest Class 1 datagram: I/O header, sequence count, run/idle header, assembly.
const LARGEST_IO_DATAGRAM: usize = HEADER_LEN + 2 + 4 + MAX_ASSEMBLY_SIZE;
const _: () = assert!(IO_BUFFER_LEN >= 2 * LARGEST_IO_DATAGRAM);

/// Buffers of one UDP 2222 socket: receive side `RX_PACKETS` datagrams in `RX_LEN` bytes,
/// transmit side [`IO_PACKETS`] in [`IO_BUFFER_LEN`].
pub(crate) struct IoSocketBuffers<const RX_PACKETS: usize, const RX_LEN: usize> {
    pub rx_meta: [PacketMetadata; RX_PACKETS],
    pub rx: [u8; RX_LEN],
    pub tx_meta: [PacketMetadata; IO_PACKETS],
    pub tx: [u8; IO_BUFFER_LEN],
}

impl<const RX_PACKETS: usize, const RX_LEN: usize> IoSocketBuffers<RX_PACKETS, RX_LEN> {
    /// Empty buffers, built field by field (a `const` item would be a flash image of them).
    const fn new() -> Self {
        IoSocketBuffers {
            rx_meta: [PacketMetadata::EMPTY; RX_PACKETS],
            rx: [0; RX_LEN],
            tx_meta: [PacketMetadata::EMPTY; IO_PACKETS],
            tx: [0; IO_BUFFER_LEN],
        }
    }
}

/// Buffers of Class 1 I/O: the point-to-point and multicast sockets (T->O datagrams are
/// built straight into their transmit buffers). smoltcp hands a received datagram to the
/// first socket bound to its port, the point-to-point one (opened first): the multicast
/// socket only sends, and its receive side is one empty slot.
pub(crate) struct IoBuffers {
    pub unicast: IoSocketBuffers<IO_PACKETS, IO_BUFFER_LEN>,
    pub multicast: IoSocketBuffers<1, 0>,
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
                unicast: IoSocketBuffers::new(),
                multicast: IoSocketBuffers::new(),
            },
        }
    }
}

impl Default for Resources {
    fn default() -> Self {
        Self::new()
    }
}
