//! CIP general status codes and the error type every service returns.

/// CIP general status codes (Vol 1, appendix B).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum General {
    /// Success.
    Success = 0x00,
    /// Connection failure (extended status says why).
    ConnectionFailure = 0x01,
    /// Resource unavailable.
    ResourceUnavailable = 0x02,
    /// Invalid parameter value.
    InvalidParameterValue = 0x03,
    /// Path segment error.
    PathSegmentError = 0x04,
    /// Path destination unknown (class or instance).
    PathDestinationUnknown = 0x05,
    /// Partial transfer.
    PartialTransfer = 0x06,
    /// Connection lost.
    ConnectionLost = 0x07,
    /// Service not supported.
    ServiceNotSupported = 0x08,
    /// Invalid attribute value.
    InvalidAttributeValue = 0x09,
    /// Attribute list error.
    AttributeListError = 0x0A,
    /// Already in requested mode/state.
    AlreadyInRequestedMode = 0x0B,
    /// Object state conflict.
    ObjectStateConflict = 0x0C,
    /// Attribute not settable.
    AttributeNotSettable = 0x0E,
    /// Privilege violation.
    PrivilegeViolation = 0x0F,
    /// Device state conflict.
    DeviceStateConflict = 0x10,
    /// Reply data too large.
    ReplyDataTooLarge = 0x11,
    /// Not enough data.
    NotEnoughData = 0x13,
    /// Attribute not supported.
    AttributeNotSupported = 0x14,
    /// Too much data.
    TooMuchData = 0x15,
    /// Object does not exist.
    ObjectDoesNotExist = 0x16,
    /// Store operation failure: non-volatile storage could not be written.
    StoreOperationFailure = 0x19,
    /// Vendor specific error.
    VendorSpecific = 0x1F,
    /// Invalid parameter.
    InvalidParameter = 0x20,
    /// Embedded service error (Multiple_Service_Packet).
    EmbeddedServiceError = 0x1E,
    /// Routing failure, request packet too large.
    RequestTooLarge = 0x1A,
    /// Missing attribute list entry data.
    MissingAttributeListEntryData = 0x1C,
    /// Path size invalid: the request path's size does not fit the request.
    PathSizeInvalid = 0x26,
    /// Unexpected attribute in list.
    UnexpectedAttributeInList = 0x27,
    /// Attribute not gettable.
    AttributeNotGettable = 0x2C,
    /// Object already exists.
    ObjectAlreadyExists = 0x0D,
    /// Fragmentation of a primitive value.
    PrimitiveFragmentation = 0x12,
    /// Service fragmentation sequence not in progress.
    FragmentationNotInProgress = 0x17,
    /// No stored attribute data.
    NoStoredAttributeData = 0x18,
    /// Routing failure: response packet too large.
    ResponseTooLarge = 0x1B,
    /// Invalid attribute value list.
    InvalidAttributeValueList = 0x1D,
    /// Write-once value or medium already written.
    WriteOnceAlreadyWritten = 0x21,
    /// Invalid reply received.
    InvalidReplyReceived = 0x22,
    /// Buffer overflow.
    BufferOverflow = 0x23,
    /// Message format error.
    MessageFormatError = 0x24,
    /// Key failure in path (electronic key mismatch).
    KeyFailureInPath = 0x25,
    /// Invalid member ID.
    InvalidMemberId = 0x28,
    /// Member not settable.
    MemberNotSettable = 0x29,
    /// Group 2 only server general failure.
    Group2OnlyServerFailure = 0x2A,
    /// Unknown Modbus error.
    UnknownModbusError = 0x2B,
    /// Instance not deletable.
    InstanceNotDeletable = 0x2D,
    /// Service not supported for the specified path.
    ServiceNotSupportedForPath = 0x2E,
}

impl General {
    /// Every general status code CIP defines (Vol 1, table B-1.1), in code order.
    pub const ALL: [General; 47] = {
        use General::*;
        [
            Success,
            ConnectionFailure,
            ResourceUnavailable,
            InvalidParameterValue,
            PathSegmentError,
            PathDestinationUnknown,
            PartialTransfer,
            ConnectionLost,
            ServiceNotSupported,
            InvalidAttributeValue,
            AttributeListError,
            AlreadyInRequestedMode,
            ObjectStateConflict,
            ObjectAlreadyExists,
            AttributeNotSettable,
            PrivilegeViolation,
            DeviceStateConflict,
            ReplyDataTooLarge,
            PrimitiveFragmentation,
            NotEnoughData,
            AttributeNotSupported,
            TooMuchData,
            ObjectDoesNotExist,
            FragmentationNotInProgress,
            NoStoredAttributeData,
            StoreOperationFailure,
            RequestTooLarge,
            ResponseTooLarge,
            MissingAttributeListEntryData,
            InvalidAttributeValueList,
            EmbeddedServiceError,
            VendorSpecific,
            InvalidParameter,
            WriteOnceAlreadyWritten,
            InvalidReplyReceived,
            BufferOverflow,
            MessageFormatError,
            KeyFailureInPath,
            PathSizeInvalid,
            UnexpectedAttributeInList,
            InvalidMemberId,
            MemberNotSettable,
            Group2OnlyServerFailure,
            UnknownModbusError,
            AttributeNotGettable,
            InstanceNotDeletable,
            ServiceNotSupportedForPath,
        ]
    };
}

impl From<General> for u8 {
    fn from(g: General) -> u8 {
        g as u8
    }
}

impl From<General> for u16 {
    fn from(g: General) -> u16 {
        u16::from(g as u8)
    }
}

/// A general status byte CIP does not define (reserved, or object class specific).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UnknownGeneral(pub u8);

impl TryFrom<u8> for General {
    type Error = UnknownGeneral;
    fn try_from(code: u8) -> Result<Self, UnknownGeneral> {
        // Codes 0x00-0x2E are all defined, in order.
        General::ALL
            .get(usize::from(code))
            .copied()
            .ok_or(UnknownGeneral(code))
    }
}

/// Most additional status words an error carries.
pub const MAX_ADDITIONAL: usize = 6;

/// A failed service: general status plus up to [`MAX_ADDITIONAL`] additional status words.
/// Shown (`Display`, and `defmt::Format` alike) as `general status 0x01, extended 0x0100`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CipError {
    /// General status code.
    pub general: General,
    additional: [u16; MAX_ADDITIONAL],
    additional_len: u8,
    keep_data: bool,
}

impl CipError {
    /// An error with a general status only.
    pub const fn new(general: General) -> Self {
        CipError {
            general,
            additional: [0; MAX_ADDITIONAL],
            additional_len: 0,
            keep_data: false,
        }
    }
    /// Adds an extended status word.
    pub const fn with_extended(mut self, ext: u16) -> Self {
        self.additional[0] = ext;
        self.additional_len = 1;
        self
    }
    /// Adds an extended status word and a second additional word (e.g. the allowed size).
    pub const fn with_additional(mut self, ext: u16, second: u16) -> Self {
        self.additional[0] = ext;
        self.additional[1] = second;
        self.additional_len = 2;
        self
    }
    /// Sets all additional status words (at most [`MAX_ADDITIONAL`]; extra ones are dropped).
    pub fn with_words(mut self, words: &[u16]) -> Self {
        let n = words.len().min(MAX_ADDITIONAL);
        for (dst, src) in self.additional.iter_mut().zip(words) {
            *dst = *src;
        }
        self.additional_len = n as u8;
        self
    }
    /// Marks the error as one whose reply still carries the data written so far
    /// (attribute lists, Multiple_Service_Packet, vendor services).
    pub const fn keeping_data(mut self) -> Self {
        self.keep_data = true;
        self
    }
    /// True if the reply keeps the data written before the error.
    pub const fn keeps_data(&self) -> bool {
        self.keep_data
    }
    /// Connection failure (0x01) with extended status `ext`.
    pub const fn connection(ext: u16) -> Self {
        Self::new(General::ConnectionFailure).with_extended(ext)
    }
    /// The additional status words.
    pub fn additional(&self) -> &[u16] {
        self.additional
            .get(..usize::from(self.additional_len))
            .unwrap_or(&[])
    }
    /// The extended (first additional) status, if any.
    pub fn extended(&self) -> Option<u16> {
        self.additional().first().copied()
    }
}

impl core::fmt::Display for CipError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        // Every number through `u32`'s formatter: one hex routine in a logging image.
        write!(f, "general status {:#04x}", u32::from(self.general as u8))?;
        let mut words = self.additional().iter();
        if let Some(ext) = words.next() {
            write!(f, ", extended {:#06x}", u32::from(*ext))?;
        }
        for word in words {
            write!(f, ", {:#06x}", u32::from(*word))?;
        }
        Ok(())
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for CipError {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "general status {=u8:#04x}", self.general as u8);
        let mut words = self.additional().iter();
        if let Some(ext) = words.next() {
            defmt::write!(f, ", extended {=u16:#06x}", ext);
        }
        for word in words {
            defmt::write!(f, ", {=u16:#06x}", word);
        }
    }
}

impl From<General> for CipError {
    fn from(g: General) -> Self {
        CipError::new(g)
    }
}

impl From<crate::wire::Error> for CipError {
    /// Output exhaustion means the reply is too large; anything else is missing request data.
    fn from(e: crate::wire::Error) -> Self {
        match e {
            crate::wire::Error::Exhausted => CipError::new(General::ReplyDataTooLarge),
            crate::wire::Error::Truncated => CipError::new(General::NotEnoughData),
            crate::wire::Error::Malformed => CipError::new(General::InvalidParameter),
        }
    }
}

/// Result of a CIP service.
pub type CipResult<T = ()> = core::result::Result<T, CipError>;

#[cfg(test)]
mod tests {
    use super::{General, UnknownGeneral};

    #[test]
    fn every_defined_code_reads_back_and_the_rest_are_unknown() {
        for code in 0..=u8::MAX {
            match General::try_from(code) {
                Ok(g) => assert_eq!(u8::from(g), code),
                Err(e) => assert!(code > 0x2E && e == UnknownGeneral(code), "{code:#04x}"),
            }
        }
    }

    #[test]
    fn shows_the_general_and_additional_status() {
        extern crate std;
        use super::CipError;
        use std::string::ToString;
        assert_eq!(
            CipError::new(General::PathDestinationUnknown).to_string(),
            "general status 0x05"
        );
        assert_eq!(
            CipError::connection(0x0109).to_string(),
            "general status 0x01, extended 0x0109"
        );
        assert_eq!(
            CipError::connection(0x0127)
                .with_words(&[0x0127, 6])
                .to_string(),
            "general status 0x01, extended 0x0127, 0x0006"
        );
    }

    /// The codes whose numbers are easy to mix up, against Vol 1 appendix B.
    #[test]
    fn codes_match_the_specification() {
        assert_eq!(General::StoreOperationFailure as u8, 0x19);
        assert_eq!(General::RequestTooLarge as u8, 0x1A);
        assert_eq!(General::MissingAttributeListEntryData as u8, 0x1C);
        assert_eq!(General::EmbeddedServiceError as u8, 0x1E);
        assert_eq!(General::PathSizeInvalid as u8, 0x26);
        assert_eq!(General::UnexpectedAttributeInList as u8, 0x27);
        assert_eq!(General::AttributeNotGettable as u8, 0x2C);
    }
}
