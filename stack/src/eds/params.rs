//! The `[Params]` of an EDS beyond the RPI: a device's parameters ([`Param`]: a field of the
//! configuration assembly, or an attribute of a vendor class) and the member layout of an
//! assembly that refers to them ([`Member`]).

use core::fmt::{self, Write};

use super::Point;
use crate::cip::object::DataType;

/// One `ParamN` entry: a value a configuration tool shows and edits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param<'a> {
    /// Parameter name.
    pub name: &'a str,
    /// Engineering units (e.g. "ms"), empty for none.
    pub units: &'a str,
    /// Help string, empty for none.
    pub help: &'a str,
    /// Data type: a fixed-size elementary type (an other type fails the write).
    pub data_type: DataType,
    /// Smallest value.
    pub min: i64,
    /// Largest value.
    pub max: i64,
    /// Default value.
    pub default: i64,
    /// The vendor-class attribute it is, as (class, instance, attribute): the EDS link
    /// path a tool reads and writes it through; `None` for a field an assembly carries.
    pub attribute: Option<(u16, u16, u16)>,
    /// Read only (descriptor bit 4).
    pub read_only: bool,
}

impl<'a> Param<'a> {
    /// A parameter `name` of `data_type`, from `min` to `max`, `default` at first; no
    /// units, help or link (set those fields, or use the builder methods).
    pub const fn new(name: &'a str, data_type: DataType, min: i64, max: i64, default: i64) -> Self {
        Param {
            name,
            units: "",
            help: "",
            data_type,
            min,
            max,
            default,
            attribute: None,
            read_only: false,
        }
    }
    /// With engineering units.
    pub const fn units(mut self, units: &'a str) -> Self {
        self.units = units;
        self
    }
    /// With a help string.
    pub const fn help(mut self, help: &'a str) -> Self {
        self.help = help;
        self
    }
    /// As attribute `attribute` of instance `instance` of vendor class `class`.
    pub const fn attribute(mut self, class: u16, instance: u16, attribute: u16) -> Self {
        self.attribute = Some((class, instance, attribute));
        self
    }
    /// Read only.
    pub const fn read_only(mut self) -> Self {
        self.read_only = true;
        self
    }
    /// Its size in bits, if its type has a fixed size.
    pub(super) fn bits(&self) -> Option<u32> {
        self.data_type
            .fixed_size()
            .and_then(|n| u32::try_from(n).ok())
            .and_then(|n| n.checked_mul(8))
    }

    /// Writes it as `Param{number}`.
    pub(super) fn write<W: Write>(&self, w: &mut W, number: usize) -> fmt::Result {
        let (Some(code), Some(bytes)) = (self.data_type.code(), self.data_type.fixed_size()) else {
            return Err(fmt::Error);
        };
        write!(w, "        Param{number} = 0, ")?;
        match self.attribute {
            Some((class, instance, attribute)) => {
                let segments = [
                    Point(0x20, class),
                    Point(0x24, instance),
                    Point(0x30, attribute),
                ];
                let len: usize = segments.iter().map(Point::len).sum();
                let [a, b, c] = segments;
                write!(w, "{len}, \"{a} {b} {c}\", ")?
            }
            None => write!(w, ", , ")?,
        }
        let descriptor: u16 = if self.read_only { 0x0010 } else { 0 };
        writeln!(
            w,
            "0x{descriptor:04X}, 0x{code:02X}, {bytes}, \"{}\", \"{}\", \"{}\", {}, {}, {}, \
             , , , , , , , , ;",
            self.name, self.units, self.help, self.min, self.max, self.default
        )
    }
}

/// One member of an assembly's layout in the EDS.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Member {
    /// `n` bits that no parameter describes (data, or reserved padding).
    Bits(u16),
    /// The parameter at this index of [`super::EdsInfo::params`], its type's size.
    Param(usize),
}

/// The layout of one assembly: its instance and its members in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout<'a> {
    /// Assembly instance.
    pub instance: u16,
    /// Members, first byte first; their sizes add up to the assembly's size.
    pub members: &'a [Member],
}

/// The number of the `ParamN` entry of parameter `index` (`Param1` is the RPI).
pub(super) const fn number(index: usize) -> usize {
    index.saturating_add(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(p: &Param<'_>) -> Result<heapless::String<256>, fmt::Error> {
        let mut s = heapless::String::new();
        p.write(&mut s, 7).map(|()| s)
    }

    #[test]
    fn a_vendor_attribute_links_by_its_path() {
        let p = Param::new("Gain", DataType::Int, -5, 5, 1)
            .attribute(0x0300, 2, 9)
            .read_only();
        assert_eq!(
            line(&p).unwrap(),
            "        Param7 = 0, 8, \"21 00 00 03 24 02 30 09\", 0x0010, 0xC3, 2, \"Gain\", \"\", \
             \"\", -5, 5, 1, , , , , , , , , ;\n"
        );
    }

    #[test]
    fn a_type_without_a_fixed_size_is_refused() {
        let p = Param::new("Name", DataType::ShortString { max: 8 }, 0, 0, 0);
        assert_eq!(line(&p), Err(fmt::Error));
        assert_eq!(p.bits(), None);
    }
}
