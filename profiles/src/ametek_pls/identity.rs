//! Identity object values: every value in one place, with where it comes from.
//!
//! The manual (7500.MOR 4/05) gives no identity values; the numbers are this project's
//! choices (digest AM-ID-2), made so that a scanner's electronic key and the EDS agree.

use enip_stack::IdentityInfo;

/// Product name: contains "7500", the manual's product (AM-ID-2 proposal).
pub const PRODUCT_NAME: &str = "7500 PLS";
/// Vendor ID: not in the manual; 0xFFFF is a placeholder (a real product reports the ID
/// ODVA assigned to its vendor).
pub const VENDOR_ID: u16 = 0xFFFF;
/// Device type 0x2B, "Generic Device (keyable)": the PLS implements no ODVA device profile.
pub const DEVICE_TYPE: u16 = 0x2B;
/// Product code: not in the manual; 7500 after the product.
pub const PRODUCT_CODE: u16 = 7500;
/// Software version reported by class 0xC0 attribute 1 (major, minor) and as the Identity
/// revision (AM-ID-2: the two are equal). The manual gives no version number.
pub const SOFTWARE_VERSION: (u8, u8) = (1, 1);
/// Serial number: a fixed value for the simulation (a real module reads its own).
pub const SERIAL_NUMBER: u32 = 0x7500_0001;

/// The Identity object of the profile.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: VENDOR_ID,
    device_type: DEVICE_TYPE,
    product_code: PRODUCT_CODE,
    revision: SOFTWARE_VERSION,
    serial_number: SERIAL_NUMBER,
    product_name: PRODUCT_NAME,
};
