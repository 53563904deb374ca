//! Identity object values (7.1): every value in one place, with where it comes from.
//!
//! The manual fixes only the product name ("EnetIP 940"); section 7.1 lists vendor ID,
//! device type, product code and revision without values. The numbers below are therefore
//! this project's choices, made so that a scanner's electronic key and the EDS file agree.

use enip_stack::IdentityInfo;

/// Product name (7.1).
pub const PRODUCT_NAME: &str = "EnetIP 940";
/// Vendor ID: not in the manual. 0xFFFF is a placeholder; a real product reports the ID
/// ODVA assigned to its vendor.
pub const VENDOR_ID: u16 = 0xFFFF;
/// Device type: not in the manual. 0x2B, "Generic Device (keyable)": the drive implements
/// no standard drive profile objects (its parameters are the vendor class 0x64).
pub const DEVICE_TYPE: u16 = 0x2B;
/// Product code: not in the manual; 940 after the product name ("EnetIP 940", E94P).
pub const PRODUCT_CODE: u16 = 940;
/// Revision: the drive firmware revision the manual's examples require (8.1: "firmware
/// revision 3.4 or later").
pub const REVISION: (u8, u8) = (3, 4);
/// Serial number: a fixed value for the simulation (a real drive reads its own).
pub const SERIAL_NUMBER: u32 = 0x0094_0001;

/// The Identity object of the profile.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: VENDOR_ID,
    device_type: DEVICE_TYPE,
    product_code: PRODUCT_CODE,
    revision: REVISION,
    serial_number: SERIAL_NUMBER,
    product_name: PRODUCT_NAME,
};
