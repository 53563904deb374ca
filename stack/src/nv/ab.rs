//! [`AbStore`]: the records kept as whole copies in two flash sectors used in turn.
//!
//! A sector holds one copy: at offset 0 the commit word, at [`MAX_WRITE_SIZE`] the body:
//! sequence number (u32), records length (u16), format (u16), the records, and the CRC-32 of
//! all of these. Saving erases the sector that does not hold the current copy, programs the
//! body with the next sequence number, then the commit word: until that last program
//! completes, the other sector's copy stays the current one. At start the valid copy (commit
//! word present, CRC right) with the highest sequence number wins. In a batch
//! ([`NvStore::begin`]) changes stay in the RAM copy until the commit saves them as one copy.

use super::flash::{Flash, MAX_WRITE_SIZE};
use super::{crc32, records, NvError, NvStore};

/// Bytes of one copy in RAM and in flash (body with header and CRC), a multiple of
/// [`MAX_WRITE_SIZE`]; a sector must hold [`MAX_WRITE_SIZE`] more. Room for the stack's
/// records and the largest shipped profile's (the Ametek program, 1 818 bytes): see
/// [`PROFILE_RECORD_ROOM`]. (2 048 until the LLDP, QoS and ACD records came; a copy's layout
/// does not depend on it, a file store's sector offsets do.)
/// With the `cip-security` feature a copy is 160 bytes larger, for the security
/// record: a store written by a build with it does not mount in one without, nor back.
pub const IMAGE_SIZE: usize = BASE_IMAGE_SIZE + SECURITY_ROOM;
/// [`IMAGE_SIZE`] without the `cip-security` feature: a store of that size holds the same
/// copies, its sectors only shorter (a host's store file can be carried over).
pub const BASE_IMAGE_SIZE: usize = 2080;
/// The room the CIP Security record takes in a copy, its header included (0 without the
/// feature).
#[cfg(feature = "cip-security")]
const SECURITY_ROOM: usize = 160;
#[cfg(not(feature = "cip-security"))]
const SECURITY_ROOM: usize = 0;
/// The room of the CIP Security record.
#[cfg(feature = "cip-security")]
pub const SECURITY_RECORD_ROOM: usize = SECURITY_ROOM - super::records::RECORD_HEADER;
/// The largest record a device profile can keep beside the TCP/IP settings: what a copy
/// holds once its header and CRC, the TCP/IP record and both record headers are counted.
pub const PROFILE_RECORD_ROOM: usize =
    IMAGE_SIZE - HEADER - CRC - 2 * super::records::RECORD_HEADER - STACK_RECORD_ROOM;
/// The room the stack's own records take in a copy: the TCP/IP object's settings
/// ([`TCP_IP_RECORD_ROOM`], the first record's header counted in [`PROFILE_RECORD_ROOM`])
/// and, each with its record header, the LLDP Management object's ([`LLDP_RECORD_ROOM`]), the
/// QoS object's ([`QOS_RECORD_ROOM`]) and Address Conflict Detection's ([`ACD_RECORD_ROOM`]);
/// each layout is checked against its room at compile time.
pub const STACK_RECORD_ROOM: usize = TCP_IP_RECORD_ROOM
    + 3 * super::records::RECORD_HEADER
    + LLDP_RECORD_ROOM
    + QOS_RECORD_ROOM
    + ACD_RECORD_ROOM
    + SECURITY_ROOM;
/// The room of the TCP/IP object's record (its settable attributes).
pub const TCP_IP_RECORD_ROOM: usize = 150;
/// The room of the LLDP Management object's record (attributes 1-3).
pub const LLDP_RECORD_ROOM: usize = 5;
/// The room of the QoS object's record (attribute 1 and the seven DSCP values).
pub const QOS_RECORD_ROOM: usize = 9;
/// The room of Address Conflict Detection's record (TCP/IP attributes 10 and 11).
pub const ACD_RECORD_ROOM: usize = 37;
/// The commit word: the copy in this sector is complete.
const MAGIC: u32 = 0x4E56_4331; // "NVC1"
/// Version of the body layout.
const FORMAT: u16 = 1;
/// Sequence number, records length and format.
const HEADER: usize = 8;
/// The CRC after the records.
const CRC: usize = 4;
/// Where the body starts in a sector.
const BODY: usize = MAX_WRITE_SIZE;

/// An [`NvStore`] over the two sectors of `F`, with the current copy cached in RAM.
pub struct AbStore<F: Flash> {
    flash: F,
    /// The current copy's body: header, records (then room for the CRC when saving).
    image: [u8; IMAGE_SIZE],
    /// Bytes of records in `image`.
    used: usize,
    /// Sequence number of the current copy.
    seq: u32,
    /// The sector holding the current copy.
    current: Option<u8>,
    /// Where a batch is: changes wait in `image` for [`NvStore::commit`].
    batch: Batch,
}

/// Whether changes are saved at once or wait for a commit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Batch {
    /// Every change is saved at once.
    None,
    /// In a batch, nothing changed yet.
    Clean,
    /// In a batch, with changes not saved.
    Dirty,
}

impl<F: Flash> AbStore<F> {
    /// Finds the current copy on `flash` (none: no records).
    pub fn mount(flash: F) -> Self {
        let mut store = AbStore {
            flash,
            image: [0xFF; IMAGE_SIZE],
            used: 0,
            seq: 0,
            current: None,
            batch: Batch::None,
        };
        store.reload();
        store
    }
    /// The flash, e.g. to look at what a test left in it.
    pub fn flash(&self) -> &F {
        &self.flash
    }
    /// Ends the store, giving the flash back.
    pub fn into_flash(self) -> F {
        self.flash
    }
    /// Sequence number of the current copy (0: none yet); one more at every save.
    pub fn sequence(&self) -> u32 {
        self.seq
    }

    /// Reads the current copy into RAM, forgetting any change not saved.
    fn reload(&mut self) {
        self.used = 0;
        self.seq = 0;
        self.current = None;
        let mut candidates = [(0u8, self.header(0)), (1u8, self.header(1))];
        // Newer first: sequence numbers compare modulo 2^32.
        if let [(_, Some((a, _))), (_, Some((b, _)))] = candidates {
            if (b.wrapping_sub(a) as i32) > 0 {
                candidates.swap(0, 1);
            }
        }
        for (sector, header) in candidates {
            if let Some((seq, len)) = header {
                if self.load_body(sector, len) {
                    self.used = len;
                    self.seq = seq;
                    self.current = Some(sector);
                    return;
                }
            }
        }
    }

    /// The sequence number and records length of `sector`'s copy, if it is committed.
    fn header(&mut self, sector: u8) -> Option<(u32, usize)> {
        let mut word = [0u8; 4];
        self.flash.read(sector, 0, &mut word).ok()?;
        if u32::from_le_bytes(word) != MAGIC {
            return None;
        }
        let mut head = [0u8; HEADER];
        self.flash.read(sector, BODY, &mut head).ok()?;
        let [s0, s1, s2, s3, l0, l1, f0, f1] = head;
        let len = usize::from(u16::from_le_bytes([l0, l1]));
        let fits = HEADER.saturating_add(len).saturating_add(CRC) <= IMAGE_SIZE;
        (u16::from_le_bytes([f0, f1]) == FORMAT && fits)
            .then_some((u32::from_le_bytes([s0, s1, s2, s3]), len))
    }

    /// Reads `sector`'s body into `image`; true if its CRC is right.
    fn load_body(&mut self, sector: u8, len: usize) -> bool {
        let end = HEADER.saturating_add(len);
        let Some(body) = self.image.get_mut(..end.saturating_add(CRC)) else {
            return false;
        };
        if self.flash.read(sector, BODY, body).is_err() {
            return false;
        }
        let (data, crc) = body.split_at(end);
        <[u8; CRC]>::try_from(crc).map(u32::from_le_bytes).ok() == Some(crc32(data))
    }

    /// The records of the current copy (changed in RAM by a write being saved).
    fn area(&self) -> &[u8] {
        self.image
            .get(HEADER..HEADER.saturating_add(self.used))
            .unwrap_or(&[])
    }

    /// Changes record `key` and saves the new copy (in a batch, at the commit); on failure the
    /// old one stays current.
    fn change(&mut self, key: u16, value: Option<&[u8]>) -> Result<(), NvError> {
        let room = self
            .image
            .get_mut(HEADER..IMAGE_SIZE - CRC)
            .ok_or(NvError::NoSpace)?;
        self.used = records::replace(room, self.used, key, value)?;
        if self.batch != Batch::None {
            self.batch = Batch::Dirty;
            return Ok(());
        }
        self.save_or_reload()
    }

    /// Saves the RAM copy; if that fails, reads the current one back.
    fn save_or_reload(&mut self) -> Result<(), NvError> {
        let saved = self.save();
        if saved.is_err() {
            self.reload();
        }
        saved
    }

    /// Programs the RAM copy into the other sector, then commits it.
    fn save(&mut self) -> Result<(), NvError> {
        if F::WRITE_SIZE > MAX_WRITE_SIZE
            || !F::WRITE_SIZE.is_power_of_two()
            || F::SECTOR_SIZE < BODY + IMAGE_SIZE
        {
            return Err(NvError::Flash);
        }
        let target = match self.current {
            Some(0) => 1,
            _ => 0,
        };
        let seq = self.seq.wrapping_add(1);
        let len = self.used as u16;
        // `used` is at most the image size: no overflow.
        let end = HEADER.saturating_add(self.used);
        let padded = end.saturating_add(CRC).next_multiple_of(F::WRITE_SIZE);
        let mut head = [0u8; HEADER];
        for (dst, src) in head.iter_mut().zip(
            seq.to_le_bytes()
                .into_iter()
                .chain(len.to_le_bytes())
                .chain(FORMAT.to_le_bytes()),
        ) {
            *dst = src;
        }
        let image = &mut self.image;
        image
            .get_mut(..HEADER)
            .ok_or(NvError::NoSpace)?
            .copy_from_slice(&head);
        let crc = crc32(image.get(..end).ok_or(NvError::NoSpace)?);
        let tail = image.get_mut(end..padded).ok_or(NvError::NoSpace)?;
        tail.fill(0xFF);
        tail.get_mut(..CRC)
            .ok_or(NvError::NoSpace)?
            .copy_from_slice(&crc.to_le_bytes());
        let body = image.get(..padded).ok_or(NvError::NoSpace)?;
        self.flash.erase(target)?;
        self.flash.program(target, BODY, body)?;
        let mut commit = [0xFFu8; MAX_WRITE_SIZE];
        let commit_len = F::WRITE_SIZE.max(4);
        commit
            .get_mut(..4)
            .ok_or(NvError::Flash)?
            .copy_from_slice(&MAGIC.to_le_bytes());
        self.flash
            .program(target, 0, commit.get(..commit_len).ok_or(NvError::Flash)?)?;
        self.seq = seq;
        self.current = Some(target);
        Ok(())
    }
}

impl<F: Flash> NvStore for AbStore<F> {
    fn read(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, NvError> {
        let Some(value) = records::find(self.area(), key) else {
            return Ok(None);
        };
        buf.get_mut(..value.len())
            .ok_or(NvError::BufferTooSmall)?
            .copy_from_slice(value);
        Ok(Some(value.len()))
    }
    fn write(&mut self, key: u16, value: &[u8]) -> Result<(), NvError> {
        self.change(key, Some(value))
    }
    fn remove(&mut self, key: u16) -> Result<(), NvError> {
        if records::find(self.area(), key).is_none() {
            return Ok(());
        }
        self.change(key, None)
    }
    fn begin(&mut self) -> Result<(), NvError> {
        if self.batch == Batch::None {
            self.batch = Batch::Clean;
        }
        Ok(())
    }
    fn commit(&mut self) -> Result<(), NvError> {
        let dirty = self.batch == Batch::Dirty;
        self.batch = Batch::None;
        if dirty {
            self.save_or_reload()
        } else {
            Ok(())
        }
    }
    fn abandon(&mut self) {
        if core::mem::replace(&mut self.batch, Batch::None) == Batch::Dirty {
            self.reload();
        }
    }
}
