//! The Ethernet Link object's interface and media counters (attributes 4 and 5), and how a
//! frame counts in them.
//!
//! The runtime counts: it sees every frame the interface receives and sends (the link task
//! owns the driver), classifies each with [`LinkCounters::received`] and
//! [`LinkCounters::sent`], and hands what it counted to the adapter
//! ([`crate::Adapter::add_link_counters`]), which the object reads and Get_And_Clear clears.
//!
//! What counts where (RFC 2863 / RFC 3635, which the Ethernet Link object of CIP Vol 2 refers
//! to):
//! - octets: each frame as it is on the wire from destination address through FCS, padded
//!   to the 64-byte minimum (the FCS the MAC strips or adds is counted; the preamble not);
//! - in unicast / non-unicast: frames for this station delivered to a protocol it handles
//!   (IPv4, ARP, LLDP), by the group bit of the destination address; frames to another
//!   station's address are not counted at all (a MAC's address filter never passes them);
//! - in unknown protos: frames for this station with any other EtherType (IPv6, VLAN-tagged,
//!   802.2 LLC...), counted in octets but in neither packet count;
//! - in errors: frames too short to hold an Ethernet header (counted in nothing else), or
//!   longer than the largest frame (also media counter Frame Too Long);
//! - out unicast / non-unicast: every frame sent, by its destination's group bit.
//!
//! The MAC-level errors (FCS, alignment, collisions, carrier sense, MAC transmit/receive
//! errors), in/out discards and out errors are not reported through `embassy-net-driver`:
//! they stay 0.

/// The largest Ethernet frame without its FCS (1 500 bytes of payload and the header).
const MAX_FRAME: usize = 1514;
/// The smallest frame on the wire without its FCS (the MAC pads shorter ones).
const MIN_FRAME: usize = 60;
/// The frame check sequence the MAC appends and strips.
const FCS: u32 = 4;
/// EtherTypes this station handles: IPv4, ARP, LLDP.
const KNOWN_ETHERTYPES: [u16; 3] = [0x0800, 0x0806, 0x88CC];

/// Attribute 4, Interface Counters (RFC 2863's ifTable), in the attribute's order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InterfaceCounters {
    /// Octets received, framing included.
    pub in_octets: u32,
    /// Unicast packets received.
    pub in_ucast: u32,
    /// Broadcast and multicast packets received.
    pub in_nucast: u32,
    /// Inbound packets discarded without an error.
    pub in_discards: u32,
    /// Inbound packets with errors.
    pub in_errors: u32,
    /// Inbound packets of an unknown protocol.
    pub in_unknown_protos: u32,
    /// Octets sent, framing included.
    pub out_octets: u32,
    /// Unicast packets sent.
    pub out_ucast: u32,
    /// Broadcast and multicast packets sent.
    pub out_nucast: u32,
    /// Outbound packets discarded without an error.
    pub out_discards: u32,
    /// Outbound packets that failed.
    pub out_errors: u32,
}

impl InterfaceCounters {
    /// The values in the attribute's order.
    pub const fn values(&self) -> [u32; 11] {
        [
            self.in_octets,
            self.in_ucast,
            self.in_nucast,
            self.in_discards,
            self.in_errors,
            self.in_unknown_protos,
            self.out_octets,
            self.out_ucast,
            self.out_nucast,
            self.out_discards,
            self.out_errors,
        ]
    }
}

/// Attribute 5, Media Counters (RFC 3635's dot3StatsTable), in the attribute's order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MediaCounters {
    /// Frames received with an alignment error.
    pub alignment_errors: u32,
    /// Frames received with a bad FCS.
    pub fcs_errors: u32,
    /// Frames sent after exactly one collision.
    pub single_collisions: u32,
    /// Frames sent after more than one collision.
    pub multiple_collisions: u32,
    /// SQE test errors.
    pub sqe_test_errors: u32,
    /// Frames whose first transmission was deferred.
    pub deferred_transmissions: u32,
    /// Collisions later than 512 bit times.
    pub late_collisions: u32,
    /// Frames not sent after excessive collisions.
    pub excessive_collisions: u32,
    /// Frames not sent for an internal MAC error.
    pub mac_transmit_errors: u32,
    /// Times carrier sense was lost while sending.
    pub carrier_sense_errors: u32,
    /// Frames received longer than the largest frame.
    pub frame_too_long: u32,
    /// Frames not received for an internal MAC error.
    pub mac_receive_errors: u32,
}

impl MediaCounters {
    /// The values in the attribute's order.
    pub const fn values(&self) -> [u32; 12] {
        [
            self.alignment_errors,
            self.fcs_errors,
            self.single_collisions,
            self.multiple_collisions,
            self.sqe_test_errors,
            self.deferred_transmissions,
            self.late_collisions,
            self.excessive_collisions,
            self.mac_transmit_errors,
            self.carrier_sense_errors,
            self.frame_too_long,
            self.mac_receive_errors,
        ]
    }
}

/// Both counter sets of one Ethernet Link instance.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinkCounters {
    /// Attribute 4.
    pub interface: InterfaceCounters,
    /// Attribute 5.
    pub media: MediaCounters,
}

impl LinkCounters {
    /// All zero.
    pub const fn new() -> Self {
        LinkCounters {
            interface: InterfaceCounters {
                in_octets: 0,
                in_ucast: 0,
                in_nucast: 0,
                in_discards: 0,
                in_errors: 0,
                in_unknown_protos: 0,
                out_octets: 0,
                out_ucast: 0,
                out_nucast: 0,
                out_discards: 0,
                out_errors: 0,
            },
            media: MediaCounters {
                alignment_errors: 0,
                fcs_errors: 0,
                single_collisions: 0,
                multiple_collisions: 0,
                sqe_test_errors: 0,
                deferred_transmissions: 0,
                late_collisions: 0,
                excessive_collisions: 0,
                mac_transmit_errors: 0,
                carrier_sense_errors: 0,
                frame_too_long: 0,
                mac_receive_errors: 0,
            },
        }
    }

    /// Counts `frame` (destination address first, no FCS) received by the station `mac`.
    pub fn received(&mut self, frame: &[u8], mac: &[u8; 6]) {
        let c = &mut self.interface;
        let Some((h, _)) = frame.split_first_chunk::<14>() else {
            // Not even a header: whose it was is unknown.
            c.in_errors = c.in_errors.wrapping_add(1);
            return;
        };
        let group = h[0] & 1 != 0;
        // Word compares: a byte array compare may become a call to `bcmp`.
        let mine = u32::from_ne_bytes([h[0], h[1], h[2], h[3]])
            == u32::from_ne_bytes([mac[0], mac[1], mac[2], mac[3]])
            && u16::from_ne_bytes([h[4], h[5]]) == u16::from_ne_bytes([mac[4], mac[5]]);
        if !group && !mine {
            return;
        }
        c.in_octets = c.in_octets.wrapping_add(wire_octets(frame.len()));
        let ethertype = u16::from_be_bytes([h[12], h[13]]);
        let counter = if frame.len() > MAX_FRAME {
            let m = &mut self.media;
            m.frame_too_long = m.frame_too_long.wrapping_add(1);
            &mut c.in_errors
        } else if !KNOWN_ETHERTYPES.contains(&ethertype) {
            &mut c.in_unknown_protos
        } else if group {
            &mut c.in_nucast
        } else {
            &mut c.in_ucast
        };
        *counter = counter.wrapping_add(1);
    }

    /// Counts `frame` (destination address first, no FCS) sent.
    pub fn sent(&mut self, frame: &[u8]) {
        let c = &mut self.interface;
        c.out_octets = c.out_octets.wrapping_add(wire_octets(frame.len()));
        let counter = match frame.first() {
            Some(d) if d & 1 != 0 => &mut c.out_nucast,
            _ => &mut c.out_ucast,
        };
        *counter = counter.wrapping_add(1);
    }

    /// Adds `other`'s counts (each counter wraps, as the attribute's UDINTs do).
    pub fn add(&mut self, other: &LinkCounters) {
        macro_rules! add {
            ($set:ident: $($field:ident),*) => {
                $(self.$set.$field = self.$set.$field.wrapping_add(other.$set.$field);)*
            };
        }
        add!(interface: in_octets, in_ucast, in_nucast, in_discards, in_errors,
            in_unknown_protos, out_octets, out_ucast, out_nucast, out_discards, out_errors);
        add!(media: alignment_errors, fcs_errors, single_collisions, multiple_collisions,
            sqe_test_errors, deferred_transmissions, late_collisions, excessive_collisions,
            mac_transmit_errors, carrier_sense_errors, frame_too_long, mac_receive_errors);
    }
}

/// The octets a frame of `len` bytes (no FCS) takes on the wire, FCS included.
fn wire_octets(len: usize) -> u32 {
    // A frame is far shorter than 4 GiB: the cast keeps its length.
    (len.max(MIN_FRAME) as u32).wrapping_add(FCS)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ME: [u8; 6] = [2, 0, 0, 0, 0, 7];

    fn frame(dst: [u8; 6], ethertype: u16) -> [u8; 1600] {
        let mut f = [0u8; 1600];
        f[..6].copy_from_slice(&dst);
        f[12..14].copy_from_slice(&ethertype.to_be_bytes());
        f
    }

    #[test]
    fn received_frames_count_by_address_and_type() {
        let mut c = LinkCounters::new();
        c.received(&frame(ME, 0x0800)[..100], &ME);
        c.received(&frame([0xFF; 6], 0x0806)[..42], &ME);
        c.received(&frame([0x01, 0x80, 0xC2, 0, 0, 0x0E], 0x88CC)[..80], &ME);
        c.received(&frame(ME, 0x86DD)[..90], &ME);
        // Another station's unicast: a MAC's filter never passes it.
        c.received(&frame([2, 0, 0, 0, 0, 9], 0x0800)[..100], &ME);
        c.received(&frame(ME, 0x0800)[..10], &ME);
        c.received(&frame(ME, 0x0800)[..1600], &ME);
        c.received(&[2, 0], &ME);
        let i = c.interface;
        assert_eq!((i.in_ucast, i.in_nucast, i.in_unknown_protos), (1, 2, 1));
        assert_eq!(i.in_errors, 3);
        assert_eq!(c.media.frame_too_long, 1);
        // 100 + 64 (42 padded) + 80 + 90 + 1600, each with its FCS; the runts none.
        assert_eq!(i.in_octets, 104 + 64 + 84 + 94 + 1604);
    }

    #[test]
    fn sent_frames_count_by_address() {
        let mut c = LinkCounters::new();
        c.sent(&frame([2, 0, 0, 0, 0, 9], 0x0800)[..200]);
        c.sent(&frame([0x01, 0, 0x5E, 0, 0, 1], 0x0800)[..60]);
        c.sent(&frame([0xFF; 6], 0x0806)[..42]);
        let i = c.interface;
        assert_eq!(
            (i.out_ucast, i.out_nucast, i.out_octets),
            (1, 2, 204 + 64 + 64)
        );
    }

    #[test]
    fn add_wraps_each_counter() {
        let mut a = LinkCounters::new();
        a.interface.in_octets = u32::MAX;
        a.media.frame_too_long = 2;
        let mut b = LinkCounters::new();
        b.interface.in_octets = 3;
        b.interface.out_errors = 5;
        b.media.frame_too_long = 1;
        a.add(&b);
        assert_eq!(a.interface.in_octets, 2);
        assert_eq!(a.interface.out_errors, 5);
        assert_eq!(a.media.frame_too_long, 3);
        assert_eq!(a.interface.values()[10], 5);
        assert_eq!(a.media.values()[10], 3);
    }
}
