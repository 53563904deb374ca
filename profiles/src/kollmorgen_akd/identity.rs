//! Identity object values: every value in one place, with where it comes from.
//!
//! The manual (December 2014, p.9) lists the Identity object among the supported objects but
//! gives none of its values, so the numbers below are this project's choices (\[R\] "Identity"
//! of the requirement digest), kept consistent with the EDS file.

use enip_stack::IdentityInfo;

/// Product name: contains "AKD" (\[R\] Identity); the drive family of the manual.
pub const PRODUCT_NAME: &str = "AKD EtherNet/IP servo drive";
/// Vendor ID 452: not in the manual; the CIP vendor table Wireshark's dissector carried
/// from ODVA's list (`packet-cip.h`, `VENDOR_ID_LIST`) names 452 "Danaher Motion/Kollmorgen",
/// the only public assignment to Kollmorgen found (Kollmorgen was Danaher Motion's brand
/// until 2008). A later copy of the same table shows 452 as "Reserved", and no AKD EDS was
/// retrievable to confirm it, so a keyed connection to a real AKD may need "Disable Keying"
/// (see the profile's README).
pub const VENDOR_ID: u16 = 452;
/// Device type 0x2B, "Generic Device (keyable)" (\[R\] Identity): the drive exposes the
/// Position Controller objects 0x24/0x25 but not the ODVA position controller assemblies,
/// so it does not claim device type 0x10.
pub const DEVICE_TYPE: u16 = 0x2B;
/// Product code: not in the manual; a project constant.
pub const PRODUCT_CODE: u16 = 0x0AD0;
/// Revision 1.13: the drive firmware of the manual's edition (Rev C, 2012, is "valid for
/// firmware 1.7", Rev F, December 2015, for 1.14; Rev E of December 2014 sits between).
pub const REVISION: (u8, u8) = (1, 13);
/// Serial number: a fixed value for the simulation (a real drive reads its own).
pub const SERIAL_NUMBER: u32 = 0x00AD_0001;

/// The Identity object of the profile.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: VENDOR_ID,
    device_type: DEVICE_TYPE,
    product_code: PRODUCT_CODE,
    revision: REVISION,
    serial_number: SERIAL_NUMBER,
    product_name: PRODUCT_NAME,
};
