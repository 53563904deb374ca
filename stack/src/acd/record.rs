//! TCP/IP attribute 11 (LastConflictDetected) and the non-volatile record that keeps it with
//! attribute 10 (SelectAcd) across restarts.

use super::arp::{Arp, ARP_PDU_LEN};
use crate::nv::{key, NvError, NvStore};

/// Bytes of attribute 11: activity, remote MAC, ARP PDU.
pub const LAST_CONFLICT_LEN: usize = 1 + 6 + ARP_PDU_LEN;
/// Layout version of the stored record.
const RECORD_VERSION: u8 = 1;
/// Bytes of the stored record: version, SelectAcd, attribute 11.
pub(crate) const RECORD_LEN: usize = 2 + LAST_CONFLICT_LEN;
const _: () = assert!(RECORD_LEN <= crate::nv::ACD_RECORD_ROOM);

/// What detection was doing when the last conflict came (attribute 11's AcdActivity).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Activity {
    /// No conflict since the attribute was last cleared (0).
    None = 0,
    /// While probing the address (1).
    Probe = 1,
    /// While using it: ongoing detection or the defence that followed (2).
    Ongoing = 2,
    /// While probing it semi-actively (3; not used by this stack).
    SemiActiveProbe = 3,
}

impl Activity {
    fn from_u8(v: u8) -> Option<Activity> {
        Some(match v {
            0 => Activity::None,
            1 => Activity::Probe,
            2 => Activity::Ongoing,
            3 => Activity::SemiActiveProbe,
            _ => return None,
        })
    }
}

/// TCP/IP attribute 11: the last conflict detected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LastConflict {
    /// What detection was doing.
    pub activity: Activity,
    /// The sender hardware address of the conflicting ARP PDU.
    pub remote_mac: [u8; 6],
    /// The conflicting ARP PDU as received.
    pub pdu: [u8; ARP_PDU_LEN],
}

impl LastConflict {
    /// No conflict: every byte zero.
    pub const NONE: LastConflict = LastConflict {
        activity: Activity::None,
        remote_mac: [0; 6],
        pdu: [0; ARP_PDU_LEN],
    };

    /// The conflict `arp` caused during `activity`.
    pub fn of(activity: Activity, arp: &Arp) -> Self {
        LastConflict {
            activity,
            remote_mac: arp.sender_mac,
            pdu: arp.raw,
        }
    }

    /// The attribute's bytes.
    pub fn to_bytes(&self) -> [u8; LAST_CONFLICT_LEN] {
        let mut out = [0u8; LAST_CONFLICT_LEN];
        let (head, pdu) = out.split_at_mut(7);
        let (activity, mac) = head.split_at_mut(1);
        activity.fill(self.activity as u8);
        mac.copy_from_slice(&self.remote_mac);
        pdu.copy_from_slice(&self.pdu);
        out
    }

    /// Reads the attribute's bytes; `None` if the length or the activity is wrong.
    pub fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let (&activity, rest) = bytes.split_first()?;
        if rest.len() != LAST_CONFLICT_LEN - 1 {
            return None;
        }
        let (mac, pdu) = rest.split_at(6);
        Some(LastConflict {
            activity: Activity::from_u8(activity)?,
            remote_mac: mac.try_into().ok()?,
            pdu: pdu.try_into().ok()?,
        })
    }
}

/// TCP/IP attributes 10 and 11 as stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AcdSettings {
    /// Attribute 10: detection selected (default on).
    pub select: bool,
    /// Attribute 11.
    pub last: LastConflict,
}

impl AcdSettings {
    /// Factory defaults: selected, no conflict.
    pub const DEFAULT: AcdSettings = AcdSettings {
        select: true,
        last: LastConflict::NONE,
    };

    /// The settings in `store`; `None` if there are none or they are unreadable.
    pub fn stored(store: &mut dyn NvStore) -> Result<Option<AcdSettings>, NvError> {
        crate::nv::read_decoded::<RECORD_LEN, _>(store, key::ACD, "ACD", Self::decode)
    }

    /// Stores them in `store`.
    pub fn save(&self, store: &mut dyn NvStore) -> Result<(), NvError> {
        let mut buf = [0u8; RECORD_LEN];
        let (head, last) = buf.split_at_mut(2);
        head.copy_from_slice(&[RECORD_VERSION, u8::from(self.select)]);
        last.copy_from_slice(&self.last.to_bytes());
        store.write(key::ACD, &buf)
    }

    fn decode(bytes: &[u8]) -> Option<AcdSettings> {
        let (&[version, select], last) = bytes.split_first_chunk::<2>()?;
        if version != RECORD_VERSION || select > 1 {
            return None;
        }
        Some(AcdSettings {
            select: select == 1,
            last: LastConflict::from_bytes(last)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::acd::arp::{ArpFrame, ARP_FRAME_LEN};
    use crate::nv::{AbStore, RamFlash, IMAGE_SIZE, MAX_WRITE_SIZE};

    #[test]
    fn settings_survive_a_restart() {
        let mut store = AbStore::mount(RamFlash::<{ MAX_WRITE_SIZE + IMAGE_SIZE }>::new());
        assert_eq!(AcdSettings::stored(&mut store), Ok(None));
        let mut frame = [0u8; ARP_FRAME_LEN];
        ArpFrame::Announcement.write([2, 9, 9, 9, 9, 9], [198, 18, 0, 2].into(), &mut frame);
        let arp = Arp::from_frame(&frame).unwrap();
        let settings = AcdSettings {
            select: false,
            last: LastConflict::of(Activity::Probe, &arp),
        };
        settings.save(&mut store).unwrap();
        let mut store = AbStore::mount(store.into_flash());
        assert_eq!(AcdSettings::stored(&mut store), Ok(Some(settings)));
        let bytes = settings.last.to_bytes();
        assert_eq!(bytes[0], 1);
        assert_eq!(bytes[1..7], [2, 9, 9, 9, 9, 9]);
        assert_eq!(bytes[7..], frame[14..]);
        store.write(key::ACD, &[RECORD_VERSION, 2]).unwrap();
        assert_eq!(AcdSettings::stored(&mut store), Ok(None));
        assert!(LastConflict::from_bytes(&[4; LAST_CONFLICT_LEN]).is_none());
        assert!(LastConflict::from_bytes(&[0; LAST_CONFLICT_LEN - 1]).is_none());
    }
}
