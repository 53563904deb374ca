//! What the runtime needs from a board: the number of embassy-net sockets, and the socket
//! buffers (usually placed in a `static`).

use embassy_net::udp::PacketMetadata;
use embassy_net::StackResources;
use enip_stack::config::{MAX_ENCAP_FRAME, MAX_SESSIONS};

/// Sockets [`crate::run`] opens on the embassy-net stack: a TCP socket per encapsulation
/// session on port 44818 (3) and a UDP socket on 44818 (Class 1 I/O on 2222 needs none: it
/// is the link task's). A board using DHCP adds one for the DHCP client.
pub const SOCKETS: usize = MAX_SESSIONS + 1;

/// The embassy-net `StackResources` for `N` sockets, refusing fewer than [`SOCKETS`]: in a
/// `static` or `const` initializer the refusal is a compile error, otherwise a panic with
/// this message at start-up (rather than smoltcp's "adding a socket to a full SocketSet"
/// deep inside the runtime).
pub const fn stack_resources<const N: usize>() -> StackResources<N> {
    assert!(
        N >= SOCKETS,
        "embassy-net StackResources too small: the EtherNet/IP runtime needs enip_firmware::SOCKETS (4) sockets, plus one for DHCP"
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

/// Every buffer [`crate::run`] uses; create one with [`Resources::new`] in a `static` cell.
pub struct Resources {
    pub(crate) tcp: [TcpBuffers; MAX_SESSIONS],
    pub(crate) udp: UdpBuffers,
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
        }
    }
}

impl Default for Resources {
    fn default() -> Self {
        Self::new()
    }
}
