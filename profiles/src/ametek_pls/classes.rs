//! The two vendor classes of §2.2 as [`ClassDef`]s the stack serves: 0xC0 PLS Status
//! (attributes 1-3, Get only) and 0xC1 PLS Configuration (attributes 1-38, Get/Set), one
//! instance each ("the instance number is always set to 1", §3.2).
//!
//! Every attribute is a structure of UINT/INT words with the manual's size; the stack
//! answers the length (0x13/0x15), unknown attribute (0x14), unknown instance (0x05/0x16),
//! Set of a Get-only attribute (0x0E) and unsupported services (0x08; Get_Attributes_All
//! is not offered) itself. The values come from [`super::AmetekPls`].

use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};

/// Class code of the PLS Status class.
pub const STATUS: u16 = 0xC0;
/// Class code of the PLS Configuration class.
pub const CONFIG: u16 = 0xC1;

/// Status attribute 1: system information (2 words).
pub const SYSTEM_INFORMATION: u16 = 1;
/// Status attribute 2: input status information (16 x 3 words).
pub const INPUT_STATUS: u16 = 2;
/// Status attribute 3: offset information (24 words).
pub const OFFSET_INFORMATION: u16 = 3;

/// Class 0xC0 (§2.11-2.13).
pub const STATUS_CLASS: ClassDef = ClassDef {
    id: STATUS,
    name: "PLS Status",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get(1, DataType::Bytes(4), "System Information"),
        AttributeDef::get(2, DataType::Bytes(96), "Input Status Information"),
        AttributeDef::get(3, DataType::Bytes(48), "Offset Information"),
    ],
    get_all: &[],
    optional_attributes: &[],
};

/// Class 0xC1 (§2.3-2.10). 36 (offset) and 37 (program control) are commands: a Get returns
/// the last accepted data (\[R\] AM-EX-3). 38 is settable in the class but refused by the
/// resolver version (\[R\] 12).
pub const CONFIG_CLASS: ClassDef = ClassDef {
    id: CONFIG,
    name: "PLS Configuration",
    revision: 1,
    max_instance: 1,
    attributes: &[
        AttributeDef::get_set(1, DataType::Bytes(96), "PLS Object"),
        AttributeDef::get_set(2, DataType::Bytes(52), "High Speed Output 1"),
        AttributeDef::get_set(3, DataType::Bytes(52), "High Speed Output 2"),
        AttributeDef::get_set(4, DataType::Bytes(52), "High Speed Output 3"),
        AttributeDef::get_set(5, DataType::Bytes(52), "High Speed Output 4"),
        AttributeDef::get_set(6, DataType::Bytes(52), "High Speed Output 5"),
        AttributeDef::get_set(7, DataType::Bytes(52), "High Speed Output 6"),
        AttributeDef::get_set(8, DataType::Bytes(52), "High Speed Output 7"),
        AttributeDef::get_set(9, DataType::Bytes(52), "High Speed Output 8"),
        AttributeDef::get_set(10, DataType::Bytes(52), "High Speed Output 9"),
        AttributeDef::get_set(11, DataType::Bytes(52), "High Speed Output 10"),
        AttributeDef::get_set(12, DataType::Bytes(52), "High Speed Output 11"),
        AttributeDef::get_set(13, DataType::Bytes(52), "High Speed Output 12"),
        AttributeDef::get_set(14, DataType::Bytes(52), "High Speed Output 13"),
        AttributeDef::get_set(15, DataType::Bytes(52), "High Speed Output 14"),
        AttributeDef::get_set(16, DataType::Bytes(52), "High Speed Output 15"),
        AttributeDef::get_set(17, DataType::Bytes(52), "High Speed Output 16"),
        AttributeDef::get_set(18, DataType::Bytes(40), "Low Speed Output 17"),
        AttributeDef::get_set(19, DataType::Bytes(40), "Low Speed Output 18"),
        AttributeDef::get_set(20, DataType::Bytes(40), "Low Speed Output 19"),
        AttributeDef::get_set(21, DataType::Bytes(40), "Low Speed Output 20"),
        AttributeDef::get_set(22, DataType::Bytes(40), "Low Speed Output 21"),
        AttributeDef::get_set(23, DataType::Bytes(40), "Low Speed Output 22"),
        AttributeDef::get_set(24, DataType::Bytes(40), "Low Speed Output 23"),
        AttributeDef::get_set(25, DataType::Bytes(40), "Low Speed Output 24"),
        AttributeDef::get_set(26, DataType::Bytes(40), "Low Speed Output 25"),
        AttributeDef::get_set(27, DataType::Bytes(40), "Low Speed Output 26"),
        AttributeDef::get_set(28, DataType::Bytes(40), "Low Speed Output 27"),
        AttributeDef::get_set(29, DataType::Bytes(40), "Low Speed Output 28"),
        AttributeDef::get_set(30, DataType::Bytes(40), "Low Speed Output 29"),
        AttributeDef::get_set(31, DataType::Bytes(40), "Low Speed Output 30"),
        AttributeDef::get_set(32, DataType::Bytes(40), "Low Speed Output 31"),
        AttributeDef::get_set(33, DataType::Bytes(40), "Low Speed Output 32"),
        AttributeDef::get_set(34, DataType::Bytes(224), "Input Configuration"),
        AttributeDef::get_set(35, DataType::Bytes(6), "Add-On Test Configuration"),
        AttributeDef::get_set(36, DataType::Bytes(18), "Offset Configuration"),
        AttributeDef::get_set(37, DataType::Bytes(4), "Program Control"),
        AttributeDef::get_set(38, DataType::Bytes(4), "Encoder"),
    ],
    get_all: &[],
    optional_attributes: &[],
};

/// Both classes, as [`enip_stack::Device::classes`] lists them.
pub const CLASSES: [ClassDef; 2] = [STATUS_CLASS, CONFIG_CLASS];
