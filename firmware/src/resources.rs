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

/// Buffers of one encapsulation TCP socket, replies of up to `F` bytes.
pub(crate) struct TcpBuffers<const F: usize> {
    pub rx: Aligned<TCP_RX_LEN>,
    pub tx: Aligned<TCP_TX_LEN>,
    pub reply: Aligned<F>,
}

/// `N` bytes starting 2 bytes past a multiple of 4, as a TCP payload does in a frame that
/// starts word-aligned (behind 14 + 20 + 20 bytes of Ethernet, IPv4 and TCP headers): the
/// copies between frames and the socket buffers (smoltcp's), and from the reply into the
/// transmit buffer, then run a word at a time rather than shifting every word (a request
/// whose length is a multiple of 4 keeps the receive buffer's next one in step too).
#[repr(C, align(4))]
pub(crate) struct Aligned<const N: usize> {
    _lead: [u8; 2],
    /// The bytes.
    pub bytes: [u8; N],
}

impl<const N: usize> Aligned<N> {
    /// Zeroed bytes.
    const fn new() -> Self {
        Aligned {
            _lead: [0; 2],
            bytes: [0; N],
        }
    }
}

/// Buffers of the UDP 44818 socket, replies of up to `F` bytes.
pub(crate) struct UdpBuffers<const F: usize> {
    pub rx_meta: [PacketMetadata; UDP_PACKETS],
    pub rx: [u8; UDP_BUFFER_LEN],
    pub tx_meta: [PacketMetadata; UDP_PACKETS],
    pub tx: [u8; UDP_BUFFER_LEN],
    pub reply: [u8; F],
}

/// Every buffer [`crate::run`] uses, for an adapter of `SESSIONS` sessions and `FRAME`-byte
/// frames (the same capacities as its [`enip_stack::Adapter`]; the defaults are the stack's);
/// create one with [`Resources::new`] in a `static` cell.
pub struct Resources<
    const SESSIONS: usize = { MAX_SESSIONS },
    const FRAME: usize = { MAX_ENCAP_FRAME },
> {
    pub(crate) tcp: [TcpBuffers<FRAME>; SESSIONS],
    pub(crate) udp: UdpBuffers<FRAME>,
}

impl<const SESSIONS: usize, const FRAME: usize> Resources<SESSIONS, FRAME> {
    /// Sockets [`crate::run`] opens for these resources: one TCP socket per session and the
    /// UDP socket ([`SOCKETS`] for the default).
    pub const SOCKETS: usize = SESSIONS + 1;

    /// Zeroed buffers (a `const fn`, so a board can place them in `.bss`).
    pub const fn new() -> Self {
        const {
            assert!(
                FRAME <= TCP_TX_LEN,
                "FRAME: a whole reply must fit a TCP socket's transmit buffer (TCP_TX_LEN)"
            );
        };
        Resources {
            tcp: [const {
                TcpBuffers {
                    rx: Aligned::new(),
                    tx: Aligned::new(),
                    reply: Aligned::new(),
                }
            }; SESSIONS],
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
    /// than [`Self::SOCKETS`]; [`stack_resources`] for the default capacities.
    pub const fn stack_resources<const N: usize>() -> StackResources<N> {
        const {
            assert!(
                N >= Self::SOCKETS,
                "embassy-net StackResources too small: the runtime needs a socket per session and one for UDP, plus one for DHCP"
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
