//! What the runtime needs from a board: the number of embassy-net sockets, and the socket
//! buffers (usually placed in a `static`).

use embassy_net::udp::PacketMetadata;
use embassy_net::StackResources;
use enip_stack::config::MAX_ENCAP_FRAME;

/// Sockets [`crate::run`] opens on the embassy-net stack: the UDP socket on 44818 (the
/// encapsulation TCP on 44818 and Class 1 I/O on 2222 need none: they are the link task's).
/// A board using DHCP adds one for the DHCP client.
pub const SOCKETS: usize = 1;

/// The embassy-net `StackResources` for `N` sockets, refusing fewer than [`SOCKETS`]: in a
/// `static` or `const` initializer the refusal is a compile error, otherwise a panic with
/// this message at start-up (rather than smoltcp's "adding a socket to a full SocketSet"
/// deep inside the runtime).
pub const fn stack_resources<const N: usize>() -> StackResources<N> {
    assert!(
        N >= SOCKETS,
        "embassy-net StackResources too small: the EtherNet/IP runtime needs enip_firmware::SOCKETS (1) socket, plus one for DHCP"
    );
    StackResources::new()
}

/// Datagrams the UDP 44818 socket can hold in each direction.
pub const UDP_PACKETS: usize = 4;
/// Payload bytes the UDP 44818 socket can hold in each direction.
pub const UDP_BUFFER_LEN: usize = 1536;

/// Buffers of the UDP 44818 socket, replies of up to `F` bytes.
pub(crate) struct UdpBuffers<const F: usize> {
    pub rx_meta: [PacketMetadata; UDP_PACKETS],
    pub rx: [u8; UDP_BUFFER_LEN],
    pub tx_meta: [PacketMetadata; UDP_PACKETS],
    pub tx: [u8; UDP_BUFFER_LEN],
    pub reply: [u8; F],
}

/// Every buffer [`crate::run`] uses, for an adapter of `FRAME`-byte frames (the same
/// capacity as its [`enip_stack::Adapter`]; the default is the stack's); create one with
/// [`Resources::new`] in a `static` cell. (The encapsulation TCP's buffers are the
/// [`crate::SharedAdapter`]'s.)
pub struct Resources<const FRAME: usize = { MAX_ENCAP_FRAME }> {
    pub(crate) udp: UdpBuffers<FRAME>,
}

impl<const FRAME: usize> Resources<FRAME> {
    /// Sockets [`crate::run`] opens for these resources ([`SOCKETS`]).
    pub const SOCKETS: usize = SOCKETS;

    /// Zeroed buffers (a `const fn`, so a board can place them in `.bss`).
    pub const fn new() -> Self {
        Resources {
            udp: UdpBuffers {
                rx_meta: [PacketMetadata::EMPTY; UDP_PACKETS],
                rx: [0; UDP_BUFFER_LEN],
                tx_meta: [PacketMetadata::EMPTY; UDP_PACKETS],
                tx: [0; UDP_BUFFER_LEN],
                reply: [0; FRAME],
            },
        }
    }

    /// The embassy-net `StackResources` for `N` sockets, refusing (at compile time) fewer
    /// than [`Self::SOCKETS`]; [`stack_resources`] for the default capacity.
    pub const fn stack_resources<const N: usize>() -> StackResources<N> {
        const {
            assert!(
                N >= Self::SOCKETS,
                "embassy-net StackResources too small: the runtime needs one socket for UDP, plus one for DHCP"
            )
        };
        StackResources::new()
    }
}

impl Default for Resources {
    fn default() -> Self {
        Self::new()
    }
}
