//! Forward_Open admission: the request as the stack validated it, handed to
//! [`crate::Device::admit`] before the connection exists, and helpers to refuse it.

use core::net::Ipv4Addr;

use super::{Kind, Trigger};
use crate::cip::connection_status as ext;
use crate::cip::status::{CipError, CipResult};
use crate::time::Duration;
use crate::wire::epath::ElectronicKey;
use crate::wire::forward_open::{NetworkParams, Triad};

use super::events::ConnectionPoints;

/// One direction of a requested connection.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Direction {
    /// Requested packet interval, microseconds.
    pub rpi_us: u32,
    /// The network connection parameters: type (null, point-to-point, multicast), fixed or
    /// variable, and the size in bytes as the Forward_Open gives it (Class 1: the data plus
    /// the 2-byte sequence count, plus 4 for a run/idle header where used).
    pub params: NetworkParams,
}

/// A Forward_Open whose request passed every check of the stack (format, paths, sizes, RPI
/// range, electronic key, network parameters). The device accepts it with `Ok(())`, or
/// refuses it with a connection failure that goes out exactly as given, e.g.
/// `CipError::connection(0x0103)` or [`OpenRequest::refuse_rpi`]. What the connection table
/// holds is judged after the device accepts: outputs already owned (0x0106), no free slot
/// (0x0113).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OpenRequest<'a> {
    /// Exclusive owner, input only, listen only, or Class 3 explicit.
    pub kind: Kind,
    /// Transport class: 1 (implicit I/O) or 3 (explicit).
    pub transport_class: u8,
    /// Production trigger: cyclic, change of state or application.
    pub trigger: Trigger,
    /// Production inhibit time (zero if none was given).
    pub inhibit: Duration,
    /// The configuration, consumed and produced assemblies of the path.
    pub points: ConnectionPoints,
    /// Originator to target.
    pub o_t: Direction,
    /// Target to originator.
    pub t_o: Direction,
    /// Connection timeout multiplier code (0-7: x4 to x512).
    pub timeout_multiplier: u8,
    /// The originator's IP address.
    pub originator: Ipv4Addr,
    /// Vendor ID, originator serial number and connection serial number.
    pub triad: Triad,
    /// The electronic key of the path, if it had one (already matched to the identity).
    pub key: Option<ElectronicKey>,
    /// Configuration data from the path's data segment (already the configuration
    /// assembly's size). If the device accepts, the stack writes it with
    /// [`crate::Device::write_assembly`] when the connection may configure the device.
    pub config_data: Option<&'a [u8]>,
}

/// RPI type in the 0x0112 additional status: acceptable, minimum, maximum, required to
/// correct a mismatch (with an existing multicast production).
const RPI_OK: u8 = 0;
const RPI_MIN: u8 = 2;
const RPI_MAX: u8 = 3;
const RPI_REQUIRED: u8 = 4;

impl OpenRequest<'_> {
    /// True for the Class 1 kinds (exclusive owner, input only, listen only).
    pub fn is_class1(&self) -> bool {
        self.kind != Kind::Explicit
    }

    /// Refuses an O->T or T->O RPI outside `min_us..=max_us` with 0x01/0x0112 and the
    /// acceptable values, as the stack does for its own range; `Ok` if both are inside.
    pub fn refuse_rpi(&self, min_us: u32, max_us: u32) -> CipResult {
        rpi_check(
            [
                (self.o_t.rpi_us, used(&self.o_t)),
                (self.t_o.rpi_us, used(&self.t_o)),
            ],
            min_us,
            max_us,
        )
    }
}

fn used(d: &Direction) -> bool {
    d.params.connection_type != crate::wire::forward_open::ConnectionType::Null
}

/// 0x0112 with the acceptable values (O->T type, T->O type, O->T value, T->O value) if an
/// RPI in use lies outside `min..=max`.
pub(crate) fn rpi_check(rpis: [(u32, bool); 2], min: u32, max: u32) -> CipResult {
    let verdict = |(rpi, in_use): (u32, bool)| match rpi {
        _ if !in_use => (RPI_OK, rpi),
        r if r < min => (RPI_MIN, min),
        r if r > max => (RPI_MAX, max),
        r => (RPI_OK, r),
    };
    let [(ot, otv), (to, tov)] = rpis.map(verdict);
    if ot == RPI_OK && to == RPI_OK {
        return Ok(());
    }
    Err(rpi_refusal([(ot, otv), (to, tov)]))
}

/// 0x0112 for a T->O RPI other than `required`, the RPI of the multicast production the
/// connection would join (type 4, "required RPI to correct mismatch"); the O->T RPI `o_t`
/// is acceptable.
pub(crate) fn rpi_mismatch(o_t: u32, required: u32) -> CipError {
    rpi_refusal([(RPI_OK, o_t), (RPI_REQUIRED, required)])
}

/// 0x0112 with the (type, value) of the O->T and the T->O RPI.
fn rpi_refusal([(ot, otv), (to, tov)]: [(u8, u32); 2]) -> CipError {
    CipError::connection(ext::RPI_NOT_ACCEPTABLE).with_words(&[
        ext::RPI_NOT_ACCEPTABLE,
        u16::from_le_bytes([ot, to]),
        otv as u16,
        (otv >> 16) as u16,
        tov as u16,
        (tov >> 16) as u16,
    ])
}
