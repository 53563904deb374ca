//! Electronic Data Sheets: the EDS file of any [`Device`], from its own description
//! (identity, assemblies with their roles and sizes, connection points) and the few choices
//! only its vendor can make ([`EdsInfo`]: names, catalog number, RPI limits, triggers).
//!
//! Written through [`core::fmt::Write`], so it needs no allocation: a host tool writes into a
//! `String`, a device could serve it from a buffer. The file declares every connection a
//! scanner can open: each output assembly with each input assembly (exclusive owner), and
//! each input-only and listen-only heartbeat point with each input assembly.
//!
//! A device's parameters ([`Param`]: the fields of its configuration assembly, the
//! attributes of its vendor classes) go to `[Params]` after the RPI (`Param1`), numbered
//! from `Param2` in the order of [`EdsInfo::params`]; an assembly's [`Layout`] refers to them
//! as its members, so a tool can show and edit configuration data field by field.
//!
//! ```
//! use enip_stack::cip::object::DataType;
//! use enip_stack::eds::{write_eds, EdsInfo, Layout, Member, Param};
//! # use enip_stack::cip::CipResult;
//! # use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};
//! # struct Analog;
//! # const ID: IdentityInfo = IdentityInfo { vendor_id: 0xFFFF, device_type: 0x0A,
//! #     product_code: 4, revision: (1, 1), serial_number: 1, product_name: "analog 4/2" };
//! # impl Device for Analog {
//! #     fn identity(&self) -> &IdentityInfo { &ID }
//! #     fn assemblies(&self) -> &[AssemblyInfo] { &[
//! #         AssemblyInfo { instance: 100, role: AssemblyRole::Input, size: 8, run_idle_header: false },
//! #         AssemblyInfo { instance: 150, role: AssemblyRole::Output, size: 4, run_idle_header: true },
//! #         AssemblyInfo { instance: 151, role: AssemblyRole::Config, size: 4, run_idle_header: false },
//! #     ] }
//! #     fn read_assembly(&mut self, _: u16, out: &mut [u8]) -> CipResult<usize> { Ok(out.len()) }
//! #     fn write_assembly(&mut self, _: u16, _: &[u8]) -> CipResult { Ok(()) }
//! # }
//!
//! /// Configuration 151: filter (USINT, ms), range (USINT), offset (INT); class 0x70
//! /// attribute 1 of each channel is its scale (INT).
//! pub const EDS: EdsInfo<'static> = EdsInfo {
//!     description: "4 analog inputs, 2 analog outputs",
//!     vendor_name: "Example Automation",
//!     catalog: "AN-42",
//!     assembly_names: &[(100, "Inputs"), (150, "Outputs"), (151, "Configuration")],
//!     member_bits: 16, // the inputs and outputs: 16-bit channels
//!     layouts: &[Layout {
//!         instance: 151,
//!         members: &[Member::Param(0), Member::Param(1), Member::Param(2)],
//!     }],
//!     params: &[
//!         Param::new("Input filter", DataType::Usint, 0, 100, 10).units("ms"),
//!         Param::new("Input range", DataType::Usint, 0, 2, 0).help("0: 0-10 V, 1: +-10 V, 2: 4-20 mA"),
//!         Param::new("Offset", DataType::Int, -1000, 1000, 0),
//!         Param::new("Channel 1 scale", DataType::Int, -32768, 32767, 1000).attribute(0x70, 1, 1),
//!     ],
//!     ..EdsInfo::DEFAULT
//! };
//!
//! let mut eds = String::new();
//! write_eds(&mut eds, &Analog, &EDS).unwrap();
//! assert!(eds.contains("Assem151 = \"Configuration\", \"20 04 24 97 30 03\", 4, 0x0000, , , 8, Param2, 8, Param3, 16, Param4;"));
//! assert!(eds.contains("Param5 = 0, 6, \"20 70 24 01 30 01\", 0x0000, 0xC3, 2, \"Channel 1 scale\""));
//! ```

use core::fmt::{self, Write};

use crate::device::{AssemblyInfo, AssemblyRole, Device};

mod params;

pub use params::{Layout, Member, Param};

/// The vendor's choices an EDS needs beyond the device itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EdsInfo<'a> {
    /// `[File] DescText`.
    pub description: &'a str,
    /// `CreateDate` and `ModDate`, `MM-DD-YYYY`.
    pub date: &'a str,
    /// `[Device] VendName`.
    pub vendor_name: &'a str,
    /// `[Device] ProdTypeStr`, the device type in words (e.g. "Generic Device").
    pub product_type_name: &'a str,
    /// `[Device] Catalog`.
    pub catalog: &'a str,
    /// RPI range and default, microseconds.
    pub rpi_us: RpiRange,
    /// The production triggers the device accepts.
    pub triggers: Triggers,
    /// Names of assembly instances (others are named by their role).
    pub assembly_names: &'a [(u16, &'a str)],
    /// Bits of each member an assembly without a [`Layout`] lists (e.g. 32 for a drive's
    /// 32-bit words); 0 lists the whole assembly as one member.
    pub member_bits: u16,
    /// Assemblies laid out member by member (e.g. a configuration assembly's fields as
    /// parameters). A layout whose sizes do not add up to the assembly's current size is
    /// not used (the assembly is then listed by [`Self::member_bits`]).
    pub layouts: &'a [Layout<'a>],
    /// The device's parameters, `Param2` onwards.
    pub params: &'a [Param<'a>],
}

impl EdsInfo<'static> {
    /// Neutral choices, to complete with `..EdsInfo::DEFAULT`: no names, date 01-01-2026,
    /// "Generic Device", RPI 1 ms to 10 s (default 10 ms), every trigger, each assembly
    /// one member, no parameters.
    pub const DEFAULT: EdsInfo<'static> = EdsInfo {
        description: "",
        date: "01-01-2026",
        vendor_name: "",
        product_type_name: "Generic Device",
        catalog: "",
        rpi_us: RpiRange {
            min: 1_000,
            max: 10_000_000,
            default: 10_000,
        },
        triggers: Triggers::ALL,
        assembly_names: &[],
        member_bits: 0,
        layouts: &[],
        params: &[],
    };
}

impl Default for EdsInfo<'static> {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The RPI a scanner may choose, microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RpiRange {
    /// Smallest.
    pub min: u32,
    /// Largest.
    pub max: u32,
    /// Default.
    pub default: u32,
}

/// Production triggers the device accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Triggers {
    /// Cyclic.
    pub cyclic: bool,
    /// Change of state.
    pub change_of_state: bool,
    /// Application triggered.
    pub application: bool,
}

impl Triggers {
    /// Every trigger the stack implements.
    pub const ALL: Triggers = Triggers {
        cyclic: true,
        change_of_state: true,
        application: true,
    };

    /// Bits 16-18 of the EDS trigger and transport word.
    const fn bits(self) -> u32 {
        (self.cyclic as u32) << 16
            | (self.change_of_state as u32) << 17
            | (self.application as u32) << 18
    }
}

/// Transport class 1, server (bit 1).
const CLASS1: u32 = 0x0000_0002;
/// Connection kinds (trigger and transport word, bits 24-26).
const EXCLUSIVE_OWNER: u32 = 1 << 26;
const INPUT_ONLY: u32 = 1 << 25;
const LISTEN_ONLY: u32 = 1 << 24;
/// Connection parameters: fixed sizes both ways (bits 0 and 2), O->T point-to-point (bit
/// 18), scheduled priority both ways (bits 26 and 30).
const FIXED_P2P_SCHEDULED: u32 = 0x4404_0005;
/// T->O point-to-point and multicast (bits 21-22).
const T_O_P2P_OR_MULTICAST: u32 = 0x0060_0000;
/// T->O multicast only (bit 21).
const T_O_MULTICAST: u32 = 0x0020_0000;
/// O->T real-time format (bits 8-11): modeless, heartbeat, 32-bit run/idle header.
const O_T_MODELESS: u32 = 0x0000;
const O_T_HEARTBEAT: u32 = 0x0300;
const O_T_RUN_IDLE: u32 = 0x0400;

/// Writes the EDS file of `device` to `w`.
pub fn write_eds<W: Write>(w: &mut W, device: &impl Device, info: &EdsInfo<'_>) -> fmt::Result {
    let id = device.identity();
    let assemblies = device.assemblies();
    writeln!(
        w,
        "$ EDS of \"{}\" (enip-rs), generated from the device's own description.",
        id.product_name
    )?;
    writeln!(w, "$ Regenerate it rather than edit it.\n")?;
    writeln!(w, "[File]")?;
    writeln!(w, "        DescText = \"{}\";", info.description)?;
    writeln!(
        w,
        "        CreateDate = {};\n        CreateTime = 12:00:00;",
        info.date
    )?;
    writeln!(
        w,
        "        ModDate = {};\n        ModTime = 12:00:00;",
        info.date
    )?;
    writeln!(w, "        Revision = 1.0;\n")?;
    writeln!(w, "[Device]")?;
    writeln!(w, "        VendCode = {};", id.vendor_id)?;
    writeln!(w, "        VendName = \"{}\";", info.vendor_name)?;
    writeln!(w, "        ProdType = {};", id.device_type)?;
    writeln!(w, "        ProdTypeStr = \"{}\";", info.product_type_name)?;
    writeln!(w, "        ProdCode = {};", id.product_code)?;
    writeln!(w, "        MajRev = {};", id.revision.0)?;
    writeln!(w, "        MinRev = {};", id.revision.1)?;
    writeln!(w, "        ProdName = \"{}\";", id.product_name)?;
    writeln!(w, "        Catalog = \"{}\";\n", info.catalog)?;
    writeln!(w, "[Device Classification]\n        Class1 = EtherNetIP;\n")?;
    let rpi = info.rpi_us;
    writeln!(w, "[Params]")?;
    writeln!(
        w,
        "        Param1 = 0, , , 0x0000, 0xC8, 4, \"RPI\", \"microsecond\", \
         \"Requested packet interval\", {}, {}, {}, , , , , , , , , ;",
        rpi.min, rpi.max, rpi.default
    )?;
    for (i, param) in info.params.iter().enumerate() {
        param.write(w, params::number(i))?;
    }
    writeln!(w)?;
    writeln!(w, "[Assembly]\n        Object_Name = \"Assembly Object\";")?;
    writeln!(w, "        Object_Class_Code = 0x04;")?;
    for a in assemblies {
        let n = a.instance;
        write!(
            w,
            "        Assem{n} = \"{}\", \"20 04 {} 30 03\", {}, 0x0000, , ",
            Name(info, a),
            Point(0x24, n),
            a.size
        )?;
        write_members(w, info, a)?;
        writeln!(w, ";")?;
    }
    writeln!(w, "\n[Connection Manager]")?;
    writeln!(w, "        Object_Name = \"Connection Manager Object\";")?;
    writeln!(w, "        Object_Class_Code = 0x06;")?;
    let config = assemblies.iter().find(|a| a.role == AssemblyRole::Config);
    let kinds = [
        (
            AssemblyRole::Output,
            EXCLUSIVE_OWNER,
            T_O_P2P_OR_MULTICAST,
            "Exclusive owner",
        ),
        (
            AssemblyRole::InputOnlyHeartbeat,
            INPUT_ONLY,
            T_O_P2P_OR_MULTICAST,
            "Input only",
        ),
        (
            AssemblyRole::ListenOnlyHeartbeat,
            LISTEN_ONLY,
            T_O_MULTICAST,
            "Listen only",
        ),
    ];
    let mut k = 0u32;
    for (role, kind, t_o, label) in kinds {
        for o in assemblies.iter().filter(|a| a.role == role) {
            for t in assemblies.iter().filter(|a| a.role == AssemblyRole::Input) {
                k = k.saturating_add(1);
                let format = match (o.size, o.run_idle_header) {
                    (0, _) => O_T_HEARTBEAT,
                    (_, true) => O_T_RUN_IDLE,
                    (_, false) => O_T_MODELESS,
                };
                let params = FIXED_P2P_SCHEDULED | t_o | format;
                write!(
                    w,
                    "        Connection{k} = 0x{:08X}, 0x{params:08X}, Param1, {}, Assem{}, \
                     Param1, {}, Assem{}, ",
                    kind | info.triggers.bits() | CLASS1,
                    o.size,
                    o.instance,
                    t.size,
                    t.instance,
                )?;
                // Config #1: the configuration assembly's data, when it has any.
                match config.filter(|c| c.size > 0) {
                    Some(c) => write!(w, "{}, Assem{}, ", c.size, c.instance)?,
                    None => write!(w, ", , ")?,
                }
                write!(
                    w,
                    ", , \"{label} {}/{}\", \"\", \"20 04 ",
                    o.instance, t.instance
                )?;
                if let Some(c) = config {
                    write!(w, "{} ", Point(0x24, c.instance))?;
                }
                writeln!(
                    w,
                    "{} {}\";",
                    Point(0x2C, o.instance),
                    Point(0x2C, t.instance)
                )?;
            }
        }
    }
    Ok(())
}

/// Writes the members of assembly `a`: its [`Layout`] if one adds up to its size, else
/// [`EdsInfo::member_bits`] each.
fn write_members<W: Write>(w: &mut W, info: &EdsInfo<'_>, a: &AssemblyInfo) -> fmt::Result {
    let bits = u32::from(a.size) * 8;
    let member_bits = |m: &Member| match *m {
        Member::Bits(n) => Some(u32::from(n)),
        Member::Param(i) => info.params.get(i).and_then(Param::bits),
    };
    let layout = info.layouts.iter().find(|l| l.instance == a.instance);
    if let Some(layout) = layout.filter(|l| {
        let sum = l
            .members
            .iter()
            .map(member_bits)
            .try_fold(0u32, |sum, m| sum.checked_add(m?));
        sum == Some(bits)
    }) {
        for m in layout.members {
            match (*m, member_bits(m)) {
                (Member::Param(i), Some(n)) => write!(w, ", {n}, Param{}", params::number(i))?,
                (_, n) => write!(w, ", {}, ", n.unwrap_or(0))?,
            }
        }
        return Ok(());
    }
    let member = match u32::from(info.member_bits) {
        m if bits.checked_rem(m).is_none_or(|r| r != 0) => bits,
        m => m,
    };
    for _ in 0..bits.checked_div(member).unwrap_or(0) {
        write!(w, ", {member}, ")?;
    }
    Ok(())
}

/// An assembly's name: the vendor's, else its role and instance.
struct Name<'a>(&'a EdsInfo<'a>, &'a AssemblyInfo);

impl fmt::Display for Name<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Name(info, a) = *self;
        if let Some((_, name)) = info.assembly_names.iter().find(|(n, _)| *n == a.instance) {
            return f.write_str(name);
        }
        let role = match a.role {
            AssemblyRole::Input => "Input",
            AssemblyRole::Output => "Output",
            AssemblyRole::Config => "Configuration",
            AssemblyRole::InputOnlyHeartbeat => "Input only heartbeat",
            AssemblyRole::ListenOnlyHeartbeat => "Listen only heartbeat",
            AssemblyRole::Explicit => "Explicit",
        };
        write!(f, "{role} {}", a.instance)
    }
}

/// A logical segment as EDS path bytes: `format` 0x20 (class), 0x24 (instance), 0x2C
/// (connection point) or 0x30 (attribute), 8- or 16-bit.
struct Point(u8, u16);

impl Point {
    /// Its length in bytes.
    fn len(&self) -> usize {
        if self.1 > 0xFF {
            4
        } else {
            2
        }
    }
}

impl fmt::Display for Point {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Point(format, n) = *self;
        match u8::try_from(n) {
            Ok(n) => write!(f, "{format:02X} {n:02X}"),
            Err(_) => {
                let [lo, hi] = n.to_le_bytes();
                write!(f, "{:02X} 00 {lo:02X} {hi:02X}", format | 1)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One configuration assembly of `size` bytes.
    struct Config(AssemblyInfo);

    impl Device for Config {
        fn identity(&self) -> &crate::IdentityInfo {
            &crate::IdentityInfo {
                vendor_id: 1,
                device_type: 0,
                product_code: 1,
                revision: (1, 1),
                serial_number: 1,
                product_name: "c",
            }
        }
        fn assemblies(&self) -> &[AssemblyInfo] {
            core::slice::from_ref(&self.0)
        }
        fn read_assembly(&mut self, _: u16, out: &mut [u8]) -> crate::cip::CipResult<usize> {
            Ok(out.len())
        }
        fn write_assembly(&mut self, _: u16, _: &[u8]) -> crate::cip::CipResult {
            Ok(())
        }
    }

    /// The `Assem` line of a configuration assembly of `size` bytes, laid out as one
    /// USINT parameter and 8 bits.
    fn assem(size: u16) -> heapless::String<128> {
        const PARAMS: [Param<'static>; 1] = [Param::new(
            "a",
            crate::cip::object::DataType::Usint,
            0,
            1,
            0,
        )];
        let info = EdsInfo {
            member_bits: 8,
            layouts: &[Layout {
                instance: 151,
                members: &[Member::Param(0), Member::Bits(8)],
            }],
            params: &PARAMS,
            ..EdsInfo::DEFAULT
        };
        let device = Config(AssemblyInfo {
            instance: 151,
            role: AssemblyRole::Config,
            size,
            run_idle_header: false,
        });
        let mut s = heapless::String::<2048>::new();
        write_eds(&mut s, &device, &info).unwrap();
        let line = s.lines().find(|l| l.contains("Assem151 =")).unwrap_or("");
        heapless::String::try_from(line).unwrap()
    }

    #[test]
    fn a_layout_is_used_only_when_it_fits_the_current_size() {
        assert!(assem(2).ends_with("2, 0x0000, , , 8, Param2, 8, ;"));
        // Three bytes now: the layout describes two, so the default applies.
        assert!(assem(3).ends_with("3, 0x0000, , , 8, , 8, , 8, ;"));
    }

    #[test]
    fn points_are_8_or_16_bit() {
        let mut s = heapless::String::<32>::new();
        write!(s, "{} {}", Point(0x24, 0x97), Point(0x2C, 0x1234)).unwrap();
        assert_eq!(s, "24 97 2D 00 34 12");
    }
}
