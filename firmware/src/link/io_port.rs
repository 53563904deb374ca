//! [`IoPort`]: the adapter's Class 1 and encapsulation TCP calls the link task makes, without
//! naming the device type (the link task is one non-generic task of the board).

use core::net::SocketAddrV4;
use core::task::Waker;

use enip_stack::objects::LinkCounters;
use enip_stack::tcp::{Outgoing, Segment};
use enip_stack::{Instant, IoDue, NetworkConfig};

use super::lldp::LldpPort;
use super::AcdPort;

/// Class 1 I/O, the encapsulation TCP (and, through [`LldpPort`], LLDP) of an adapter shared with the other tasks
/// of the runtime, and what Address Conflict Detection reports to it ([`AcdPort`]);
/// implemented by [`crate::SharedAdapter`].
pub trait IoPort: LldpPort + AcdPort {
    /// The interface configuration now (`Adapter::network`): the addresses T->O datagrams
    /// go out with.
    fn interface(&self) -> NetworkConfig;
    /// Feeds one O->T datagram from `from` (`Adapter::io_receive`); returns the next
    /// production or watchdog expiry after it (`Adapter::io_deadline`, asked under the same
    /// lock: the data may have triggered a production).
    fn receive(&self, from: SocketAddrV4, data: &[u8], now: Instant) -> Option<Instant>;
    /// Closes expired connections, then names the most overdue T->O datagram
    /// (`Adapter::io_due`), or if none is due the next production or watchdog expiry
    /// (`Adapter::io_deadline`, asked under the same lock).
    fn due(&self, now: Instant) -> Result<IoDue, Option<Instant>>;
    /// Writes (or with `None` drops) the datagram `due` named (`Adapter::write_io`).
    fn write(&self, due: &IoDue, now: Instant, out: Option<&mut [u8]>) -> usize;
    /// The next production or watchdog expiry (`Adapter::io_deadline`).
    fn deadline(&self) -> Option<Instant>;
    /// Time to live of multicast T->O datagrams (TCP/IP attribute 8).
    fn multicast_ttl(&self) -> u8;
    /// The DSCP of explicit messaging, TCP and UDP 44818 (`Adapter::explicit_dscp`).
    fn explicit_dscp(&self) -> u8;
    /// True if the network stack serves EtherNet/IP over TLS (`Adapter::tls_port_open`): TCP
    /// segments to that port go to it.
    fn tls_port_open(&self) -> bool;
    /// Adds the frames the link task counted to the Ethernet Link object's counters
    /// (`Adapter::add_link_counters`).
    fn add_link_counters(&self, counted: &LinkCounters);
    /// Keeps `waker` (the link task's) to wake whenever another task brings the deadline
    /// forward; kept across wake-ups, so registered once.
    fn watch_deadline(&self, waker: &Waker);
    /// True (once) if another task brought the deadline forward since the last call.
    fn deadline_moved(&self) -> bool;
    /// Seeds the encapsulation TCP's initial sequence numbers (once, at the link task's
    /// start).
    fn tcp_seed(&self, seed: u64);
    /// A TCP segment for the encapsulation port (`TcpServer::process`, the adapter taking
    /// its data); what answers it if it belongs to no connection (a RST, or a SYN cookie's
    /// SYN-ACK).
    fn tcp_segment(&self, segment: &Segment<'_>, now: Instant) -> Option<Outgoing>;
    /// The encapsulation TCP's timers at `now` (`TcpServer::poll`).
    fn tcp_poll(&self, now: Instant);
    /// When [`Self::tcp_poll`] has something to do next.
    fn tcp_deadline(&self) -> Option<Instant>;
    /// True if the encapsulation TCP has a segment to send now.
    fn tcp_owes(&self) -> bool;
    /// Hands the next segment of the encapsulation TCP and its data to `send` (which sends
    /// it); false if there was none.
    fn tcp_transmit(&self, now: Instant, send: &mut dyn FnMut(&Outgoing, &[u8])) -> bool;
}
