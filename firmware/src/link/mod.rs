//! Class 1 I/O at the Ethernet frame level, past the TCP/IP stack.
//!
//! The board's Ethernet driver belongs to the link task ([`run`], spawned by the board next
//! to embassy-net's runner). It takes each received frame first: an O->T datagram for this
//! adapter (IPv4, UDP port 2222, unfragmented, checksums good) goes straight from the
//! driver's buffer to the adapter; every other frame goes on to embassy-net through
//! [`LinkFrames`] and the [`NetDriver`] the stack was built with. T->O datagrams are written
//! by the adapter straight into the driver's transmit buffer, behind Ethernet, IPv4 and UDP
//! headers the link task writes; the next hop's MAC address is the one the originator's own
//! frames came from (asked for by ARP if none came yet), or the IPv4 multicast group's.
//!
//! Every frame the driver receives or sends is counted for the Ethernet Link object
//! (`counted`).
//!
//! So a Class 1 cycle wakes one task and touches neither smoltcp nor the socket futures of
//! the explicit-messaging side, and the TCP/IP stack keeps ARP, ICMP, IGMP, DHCP, TCP and
//! UDP 44818 as before.

mod checksum;
mod counted;
mod frame;
mod frames;
mod io_port;
mod neighbors;
mod net_driver;
mod pump;

pub use frames::{LinkFrames, FRAME_LEN, RX_FRAMES, TX_FRAMES};
pub use io_port::IoPort;
pub use net_driver::{NetDriver, Received, Send};
pub use pump::run;
