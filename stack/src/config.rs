//! Every compile-time capacity of the stack, in one place: the protocol's fixed limits, and
//! the defaults of the capacities a device maker chooses in the [`crate::Adapter`]'s type
//! (sessions, connections, frame size, delayed ListIdentity replies).

/// Default simultaneous encapsulation sessions: one per TCP socket on port 44818.
pub const MAX_SESSIONS: usize = 3;
/// Default slots in the CIP connection table (Class 1 and Class 3 share it).
pub const MAX_CONNECTIONS: usize = 10;
/// Default largest encapsulation data part accepted or produced (after the 24-byte header).
pub const MAX_ENCAP_DATA: usize = 1024;
/// Default largest whole encapsulation frame: header plus data (the reply buffer's size).
pub const MAX_ENCAP_FRAME: usize = crate::wire::encap::HEADER_LEN + MAX_ENCAP_DATA;
/// Default delayed ListIdentity replies (broadcast requests) that can wait at once.
pub const MAX_PENDING_LIST_IDENTITY: usize = 4;
/// Bytes of ListIdentity replies over UDP the adapter sends per second at most (encapsulation
/// bytes, unicast and broadcast requests alike; a full second's worth may go out at once).
/// Past it requests go unanswered, so a storm of spoofed requests cannot turn the device
/// into an amplifier: about 40 replies of the generic profile's 100 bytes a second.
pub const LIST_IDENTITY_UDP_BYTES_PER_SECOND: u32 = 4096;
/// Services inside one Multiple_Service_Packet request.
pub const MAX_MULTIPLE_SERVICES: usize = 32;
/// Longest host name (TCP/IP attribute 6).
pub const MAX_HOST_NAME: usize = 64;
/// Longest domain name (TCP/IP attribute 5), as CIP allows.
pub const MAX_DOMAIN_NAME: usize = 48;
/// LLDP neighbours kept in the LLDP Data Table object (0x10A).
pub const MAX_LLDP_NEIGHBORS: usize = 8;
/// TCP and UDP port of the encapsulation protocol (defined by the codec).
pub use crate::wire::encap::ENCAP_PORT;
/// The TCP port of EtherNet/IP over TLS (CIP Security).
pub const TLS_PORT: u16 = 2221;
/// UDP port of Class 0/1 implicit I/O (defined by the codec).
pub use crate::wire::io_datagram::IO_PORT;
/// Smallest requested packet interval accepted, in microseconds.
pub const MIN_RPI_US: u32 = 1_000;
/// Largest requested packet interval accepted, in microseconds.
pub const MAX_RPI_US: u32 = 10_000_000;
/// Largest Class 3 (connected explicit) message and cached reply, in bytes.
pub const MAX_EXPLICIT_CONNECTED: usize = 504;
/// The consumer's first packet may take this long even if the watchdog is shorter.
pub const FIRST_PACKET_GRACE_US: u64 = 10_000_000;
/// Input assemblies a device can mark one by one in [`crate::device::InputChanges`]; more
/// count as "every input changed".
pub const MAX_CHANGED_INPUTS: usize = 8;
