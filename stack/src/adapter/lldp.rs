//! LLDP (IEEE 802.1AB) for the runtime's link layer: received LLDPDUs go into the LLDP Data
//! Table object, and the adapter's LLDPDUs (see [`crate::objects::LldpState`] for when) are
//! written from the Identity, TCP/IP and Ethernet Link objects. The runtime owns the Ethernet
//! header: ethertype [`crate::wire::lldp::ETHERTYPE`], destination
//! [`crate::wire::lldp::MULTICAST_MAC`], its own MAC as source.

use super::Adapter;
use crate::device::Device;
use crate::objects::LldpDue;
use crate::time::Instant;
use crate::wire::lldp::{CipIdentification, LldpduRepr, LocalSystem};
use crate::wire::Writer;

/// The Port ID sent: the Ethernet Link object's interface label.
const PORT_ID: &[u8] = b"Port 1";
/// ifIndex of the one interface (the Ethernet Link instance).
const IF_INDEX: u32 = 1;
/// Room for the largest LLDPDU the adapter sends: mandatory TLVs, a 64-character System
/// Name, a 32-character System Description, capabilities, address, the ODVA TLVs, End.
pub const MAX_LLDPDU: usize = 9 + 9 + 4 + 66 + 34 + 6 + 14 + 18 + 12 + 2;

/// The System Description: the product name, at most 32 characters as Identity allows.
fn description(name: &[u8]) -> &[u8] {
    name.get(..32).unwrap_or(name)
}

impl<
        D: Device,
        const SESSIONS: usize,
        const CONNECTIONS: usize,
        const FRAME: usize,
        const LIST_IDENTITY: usize,
    > Adapter<D, SESSIONS, CONNECTIONS, FRAME, LIST_IDENTITY>
{
    /// Takes in an LLDPDU (the payload of an LLDP frame) received at `now`; ignored while
    /// LLDP is off globally (LLDP Enable bit 0), counted as discarded if malformed.
    pub fn lldp_receive(&mut self, lldpdu: &[u8], now: Instant) {
        let lldp = &mut self.inner.objects.lldp;
        if !lldp.config.receives() {
            return;
        }
        match LldpduRepr::parse(lldpdu) {
            Ok(pdu) => lldp.neighbors.receive(&pdu, lldpdu, now),
            Err(_) => {
                lldp.discarded = lldp.discarded.wrapping_add(1);
                let counted = &mut self.inner.objects.link.counters.interface.in_discards;
                *counted = counted.wrapping_add(1);
            }
        }
    }

    /// Writes the LLDPDU due at `now` into `out` (at least [`MAX_LLDPDU`] bytes) and returns
    /// its length; 0 if none is due (or `out` is too short: then it is dropped).
    pub fn lldp_transmit(&mut self, now: Instant, out: &mut [u8]) -> usize {
        match self.inner.objects.lldp.take_due(now) {
            Some(due) => self.write_lldpdu(due, out),
            None => 0,
        }
    }

    /// Writes the shutdown LLDPDU (TTL 0) into `out` now, whatever the schedule, for a
    /// runtime that is about to stop: the neighbours forget the adapter at once. Its length,
    /// 0 if LLDP does not transmit (or `out` is too short).
    pub fn lldp_shutdown(&self, out: &mut [u8]) -> usize {
        if !self.inner.objects.lldp.config.transmits() {
            return 0;
        }
        self.write_lldpdu(LldpDue::Shutdown, out)
    }

    /// Writes the LLDPDU `due` from the Identity, TCP/IP and Ethernet Link objects; its
    /// length, 0 if `out` is too short.
    fn write_lldpdu(&self, due: LldpDue, out: &mut [u8]) -> usize {
        let inner = &self.inner;
        let id = inner.device.identity();
        let local = LocalSystem {
            mac: inner.net.mac,
            port_id: PORT_ID,
            ttl: inner.objects.lldp.config.ttl(),
            system_name: &inner.objects.tcpip.host_name,
            system_description: description(id.product_name.as_bytes()),
            ip: inner.net.ip,
            if_index: IF_INDEX,
            identity: CipIdentification {
                vendor_id: id.vendor_id,
                device_type: id.device_type,
                product_code: id.product_code,
                major_revision: id.revision.0,
                minor_revision: id.revision.1,
                serial_number: id.serial_number,
            },
        };
        let mut w = Writer::new(out);
        let written = match due {
            LldpDue::Update => local.emit(&mut w),
            LldpDue::Shutdown => local.emit_shutdown(&mut w),
        };
        match written {
            Ok(()) => w.len(),
            Err(_) => 0,
        }
    }

    /// When [`Self::lldp_transmit`] next has an LLDPDU to send (`None`: LLDP is off).
    pub fn lldp_deadline(&self) -> Option<Instant> {
        self.inner.objects.lldp.deadline()
    }

    /// The link came up: the neighbours hear from the adapter soon (802.1AB 9.2.7.7.4).
    pub fn lldp_link_up(&mut self) {
        self.inner.objects.lldp.local_changed();
    }
}
