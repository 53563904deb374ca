//! Class 1 I/O at the Ethernet frame level, past the TCP/IP stack.
//!
//! The board's Ethernet driver belongs to the link task ([`run`], spawned by the board next
//! to embassy-net's runner). It takes each received frame first: an O->T datagram for this
//! adapter (IPv4, UDP port 2222, unfragmented, checksums good) goes straight from the
//! driver's buffer to the adapter; every other frame goes on to embassy-net through
//! [`LinkFrames`] and the [`NetDriver`] the stack was built with. T->O datagrams are written
//! by the adapter straight into the driver's transmit buffer, behind Ethernet, IPv4 and UDP
//! headers the link task writes (built once per route and kept, `route.rs`); the next hop's
//! MAC address is the one the originator's own frames came from (asked for by ARP if none
//! came yet), or the IPv4 multicast group's.
//!
//! LLDP frames (ethertype 0x88CC) are the link task's too: received ones go to the adapter's
//! LLDP Data Table, and the adapter's own LLDPDUs go out when due (`link/lldp.rs`).
//! Every IPv4 packet carries the QoS object's DSCP: a T->O datagram its connection's, the
//! stack's TCP and UDP 44818 packets the explicit one, written on their way out (`dscp`).
//! The link task also runs Address Conflict Detection (`acd.rs`: RFC 5227 probes,
//! announcements and defence of the interface address) and holds back the network stack's
//! frames until the address has been probed.
//! During a flood the link task keeps work from the stack (`flood_guard.rs`): TCP SYNs to
//! port 44818 from a source that floods them, and ARP requests from hosts that do not talk
//! IPv4 to the adapter past a few a second (`arp_guard.rs`); and it waits only a
//! millisecond for a stack that is behind before it reads on, dropping the stack's frames so
//! that the O->T data behind them is not held up (`stack_hold.rs`).
//! Every frame the driver receives or sends is counted for the Ethernet Link object
//! (`counted`). On a board that asks for it, the link task verifies and fills the network
//! stack's checksums in its place (`stack_sums.rs`). A driver that reads its PHY over MDIO
//! for the link state is wrapped in [`PolledLink`], which reads it once a period, not at
//! every wake-up.
//!
//! The task sleeps until its next deadline through a [`LinkAlarm`]: embassy-time's queue
//! ([`TimeQueue`]), or a board's own slot for it.
//!
//! So a Class 1 cycle wakes one task and touches neither smoltcp nor the socket futures of
//! the explicit-messaging side, and the TCP/IP stack keeps ARP, ICMP, IGMP, DHCP, TCP and
//! UDP 44818 as before.

mod acd;
mod alarm;
mod arp_guard;
mod checksum;
mod counted;
mod dscp;
mod flood_guard;
mod frame;
mod frames;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
mod io_port;
mod kept_waker;
mod lldp;
mod neighbors;
mod net_driver;
mod polled_link;
mod pump;
mod route;
mod stack_hold;
mod stack_sums;
mod tcp_frames;
mod tcp_link;
#[cfg(test)]
mod test_frames;

pub use acd::AcdPort;
pub use alarm::{LinkAlarm, TimeQueue};
pub use frames::{LinkFrames, FRAME_LEN, RX_FRAMES, TX_FRAMES};
pub use io_port::IoPort;
pub use kept_waker::KeptWaker;
pub use lldp::{shutdown as lldp_shutdown, LldpPort};
pub use net_driver::{NetDriver, Received, Send};
pub use polled_link::{PolledLink, PHY_READ_PERIOD};
pub use pump::{run, run_with_link_checksums};
pub use stack_sums::LinkChecksums;
