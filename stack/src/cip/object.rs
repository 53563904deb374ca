//! Declarative CIP objects: a class, its attributes and their access rules as `const` data.
//!
//! A [`ClassDef`] says what a class is (id, revision, instances, attributes with access and
//! data type, the Get_Attributes_All order); the stack serves every attribute service and
//! every status rule from it, for its own objects and for a device's vendor classes alike.
//! Only the values come from code: the built-in objects read them from the stack's state, a
//! device from [`crate::Device::get_attribute`] and [`crate::Device::set_attribute`].

use super::status::{CipError, CipResult, General};

/// Who may read and write an attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Access {
    /// Read-only: a Set answers 0x0E (attribute not settable).
    Get,
    /// Write-only: a Get answers 0x2C (attribute not gettable).
    Set,
    /// Read and written.
    GetSet,
}

impl Access {
    /// True if Get services may read the attribute.
    pub const fn gettable(self) -> bool {
        matches!(self, Access::Get | Access::GetSet)
    }
    /// True if Set services may write the attribute.
    pub const fn settable(self) -> bool {
        matches!(self, Access::Set | Access::GetSet)
    }
}

/// The CIP data type of an attribute value, which also tells the stack how many bytes a
/// value takes in a Set request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DataType {
    /// BOOL, one byte.
    Bool,
    /// SINT.
    Sint,
    /// INT.
    Int,
    /// DINT.
    Dint,
    /// LINT.
    Lint,
    /// USINT.
    Usint,
    /// UINT.
    Uint,
    /// UDINT.
    Udint,
    /// ULINT.
    Ulint,
    /// REAL.
    Real,
    /// LREAL.
    Lreal,
    /// BYTE.
    Byte,
    /// WORD.
    Word,
    /// DWORD.
    Dword,
    /// LWORD.
    Lword,
    /// SHORT_STRING: a length byte, then at most `max` characters.
    ShortString {
        /// Most characters.
        max: u8,
    },
    /// STRING: a 16-bit length, then at most `max` characters.
    String {
        /// Most characters.
        max: u16,
    },
    /// STRING padded to an even length (the TCP/IP object's host and domain names).
    PaddedString {
        /// Most characters.
        max: u16,
    },
    /// A UDINT byte count, then at most `max` bytes (e.g. a value as text).
    CountedBytes {
        /// Most bytes after the count.
        max: u16,
    },
    /// A structure or array of exactly this many bytes.
    Bytes(u16),
    /// A structure of `bytes` fixed bytes, then a STRING padded to an even length of at
    /// most `max` characters (the TCP/IP object's interface configuration).
    BytesThenPaddedString {
        /// Bytes before the STRING.
        bytes: u16,
        /// Most characters of the STRING.
        max: u16,
    },
    /// A size the object knows only at run time (the Assembly data attribute; for a vendor
    /// class, [`crate::Device::attribute_size`]).
    RunTime,
    /// A value whose length only its handler can tell: a Set takes the rest of the request,
    /// so in Set_Attribute_List it must come last.
    Unsized,
}

impl DataType {
    /// The encoded size of a fixed-size type.
    pub const fn fixed_size(self) -> Option<usize> {
        Some(match self {
            DataType::Bool | DataType::Sint | DataType::Usint | DataType::Byte => 1,
            DataType::Int | DataType::Uint | DataType::Word => 2,
            DataType::Dint | DataType::Udint | DataType::Dword | DataType::Real => 4,
            DataType::Lint | DataType::Ulint | DataType::Lword | DataType::Lreal => 8,
            DataType::Bytes(n) => n as usize,
            _ => return None,
        })
    }

    /// The CIP elementary data type code (Vol 1, C-6.1), for EDS files and tools; `None`
    /// for structures and sizes known at run time.
    pub const fn code(self) -> Option<u8> {
        Some(match self {
            DataType::Bool => 0xC1,
            DataType::Sint => 0xC2,
            DataType::Int => 0xC3,
            DataType::Dint => 0xC4,
            DataType::Lint => 0xC5,
            DataType::Usint => 0xC6,
            DataType::Uint => 0xC7,
            DataType::Udint => 0xC8,
            DataType::Ulint => 0xC9,
            DataType::Real => 0xCA,
            DataType::Lreal => 0xCB,
            DataType::Byte => 0xD1,
            DataType::Word => 0xD2,
            DataType::Dword => 0xD3,
            DataType::Lword => 0xD4,
            DataType::ShortString { .. } => 0xDA,
            DataType::String { .. } | DataType::PaddedString { .. } => 0xD0,
            _ => return None,
        })
    }

    /// The length of the value at the front of `data` in a Set request: 0x13 if `data` is
    /// shorter, 0x09 if a counted value is longer than the type allows. `run_time` is the
    /// size of a [`DataType::RunTime`] value.
    pub(crate) fn value_len(self, data: &[u8], run_time: Option<usize>) -> CipResult<usize> {
        let counted = |prefix: usize, max: usize, pad: bool| -> CipResult<usize> {
            let head = data.get(..prefix).ok_or(not_enough())?;
            let n = head
                .iter()
                .rev()
                .fold(0usize, |acc, &b| (acc << 8) | usize::from(b));
            if n > max {
                return Err(General::InvalidAttributeValue.into());
            }
            // n <= max, a u16: no overflow.
            Ok(prefix
                .saturating_add(n)
                .saturating_add(usize::from(pad && n % 2 == 1)))
        };
        let len = match self {
            DataType::ShortString { max } => counted(1, usize::from(max), false)?,
            DataType::String { max } => counted(2, usize::from(max), false)?,
            DataType::PaddedString { max } => counted(2, usize::from(max), true)?,
            DataType::CountedBytes { max } => counted(4, usize::from(max), false)?,
            DataType::BytesThenPaddedString { bytes, max } => {
                let fixed = usize::from(bytes);
                let rest = data.get(fixed..).ok_or(not_enough())?;
                fixed.saturating_add(DataType::PaddedString { max }.value_len(rest, None)?)
            }
            DataType::RunTime => run_time.ok_or(CipError::new(General::AttributeNotSupported))?,
            DataType::Unsized => data.len(),
            fixed => fixed.fixed_size().unwrap_or(0),
        };
        if data.len() < len {
            return Err(not_enough());
        }
        Ok(len)
    }
}

fn not_enough() -> CipError {
    CipError::new(General::NotEnoughData)
}

/// One instance attribute of a class.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttributeDef {
    /// Attribute ID.
    pub id: u16,
    /// Access rule.
    pub access: Access,
    /// Data type and size.
    pub data_type: DataType,
    /// Name, for documentation and EDS files.
    pub name: &'static str,
}

impl AttributeDef {
    /// A read-only attribute.
    pub const fn get(id: u16, data_type: DataType, name: &'static str) -> Self {
        AttributeDef {
            id,
            access: Access::Get,
            data_type,
            name,
        }
    }
    /// A read-write attribute.
    pub const fn get_set(id: u16, data_type: DataType, name: &'static str) -> Self {
        AttributeDef {
            id,
            access: Access::GetSet,
            data_type,
            name,
        }
    }
    /// A write-only attribute.
    pub const fn set(id: u16, data_type: DataType, name: &'static str) -> Self {
        AttributeDef {
            id,
            access: Access::Set,
            data_type,
            name,
        }
    }
}

/// A CIP class as data: the stack serves Get/Set_Attribute_Single, Get/Set_Attribute_List,
/// Get_Attributes_All and the class attributes 1-7 (instance 0) from it.
///
/// ```
/// use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
///
/// /// A vendor class with two instances: a read-only counter and a settable limit each.
/// const COUNTERS: ClassDef = ClassDef {
///     id: 0x70,
///     name: "Counters",
///     revision: 1,
///     max_instance: 2,
///     attributes: &[
///         AttributeDef::get(1, DataType::Udint, "Count"),
///         AttributeDef::get_set(2, DataType::Udint, "Limit"),
///     ],
///     get_all: &[1, 2],
///     optional_attributes: &[],
/// };
/// assert_eq!(COUNTERS.attribute(2).map(|a| a.name), Some("Limit"));
/// assert_eq!(COUNTERS.max_attribute(), 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClassDef {
    /// Class ID.
    pub id: u16,
    /// Name, for logs, documentation and EDS files.
    pub name: &'static str,
    /// Class attribute 1: object revision.
    pub revision: u16,
    /// Class attribute 2: highest instance number. Instances `1..=max_instance` exist
    /// unless the owner says otherwise (a device: [`crate::Device::has_instance`]).
    pub max_instance: u32,
    /// The instance attributes, sorted by ID.
    pub attributes: &'static [AttributeDef],
    /// The attributes Get_Attributes_All returns, in order; empty if the class does not
    /// support the service (0x08).
    pub get_all: &'static [u16],
    /// Class attribute 4: the optional instance attributes implemented.
    pub optional_attributes: &'static [u16],
}

impl ClassDef {
    /// The definition of instance attribute `id`.
    pub fn attribute(&self, id: u16) -> Option<&'static AttributeDef> {
        self.attributes.iter().find(|a| a.id == id)
    }
    /// Class attribute 7: the highest instance attribute ID.
    pub fn max_attribute(&self) -> u16 {
        self.attributes.iter().map(|a| a.id).max().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_lengths() {
        let len = |t: DataType, d: &[u8]| t.value_len(d, Some(3)).map_err(|e| e.general as u8);
        assert_eq!(len(DataType::Uint, &[1, 2, 3]), Ok(2));
        assert_eq!(len(DataType::Udint, &[1, 2, 3]), Err(0x13));
        assert_eq!(
            len(DataType::ShortString { max: 4 }, &[2, b'a', b'b', 9]),
            Ok(3)
        );
        assert_eq!(
            len(DataType::ShortString { max: 1 }, &[2, b'a', b'b']),
            Err(0x09)
        );
        assert_eq!(len(DataType::String { max: 8 }, &[3, 0, b'a']), Err(0x13));
        assert_eq!(
            len(DataType::PaddedString { max: 8 }, &[1, 0, b'a', 0]),
            Ok(4)
        );
        assert_eq!(
            len(DataType::CountedBytes { max: 8 }, &[1, 0, 0, 0, b'7']),
            Ok(5)
        );
        assert_eq!(len(DataType::RunTime, &[0; 5]), Ok(3));
        assert_eq!(len(DataType::Unsized, &[0; 5]), Ok(5));
        assert_eq!(len(DataType::Bytes(6), &[0; 6]), Ok(6));
        let iface = DataType::BytesThenPaddedString { bytes: 4, max: 4 };
        assert_eq!(len(iface, &[0, 0, 0, 0, 1, 0, b'a', 0, 9]), Ok(8));
        assert_eq!(len(iface, &[0, 0, 0, 0, 0, 0]), Ok(6));
        assert_eq!(len(iface, &[0, 0, 0, 0, 1, 0, b'a']), Err(0x13));
        assert_eq!(len(iface, &[0, 0, 0]), Err(0x13));
        assert_eq!(len(iface, &[0, 0, 0, 0, 5, 0]), Err(0x09));
    }

    #[test]
    fn type_codes() {
        assert_eq!(DataType::Uint.code(), Some(0xC7));
        assert_eq!(DataType::ShortString { max: 32 }.code(), Some(0xDA));
        assert_eq!(DataType::Bytes(4).code(), None);
    }
}
