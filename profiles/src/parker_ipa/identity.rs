//! Identity object values: every value in one place, with where it comes from.
//!
//! The manual (88-032525-01 A) gives no identity values at all; each one below is the
//! resolution of the requirement digest (`shared/specs/parker-ipa.md` section 2, A20).

use enip_stack::IdentityInfo;

/// Product name: "IPA Controller", the product name of Table 1 (p.1).
pub const PRODUCT_NAME: &str = "IPA Controller";
/// Vendor ID 620 (0x026C), "Parker Hannifin/Compumotor Division" in the ODVA vendor list
/// (Wireshark's `cip_vendor_vals`); the manual's support address (Rohnert Park) is the
/// former Compumotor site. Digest section 2 \[R\].
pub const VENDOR_ID: u16 = 620;
/// Device type 0x2B, Generic Device (keyable): "there is no such profile for the IPA
/// controllers" (p.2).
pub const DEVICE_TYPE: u16 = 0x2B;
/// Product code: invented by this project (the manual has none). Digest section 2 \[R\].
pub const PRODUCT_CODE: u16 = 0x0001;
/// Revision 4.40: the minimum IPA firmware for the adapter function (Table 1, p.1).
pub const REVISION: (u8, u8) = (4, 40);
/// Serial number: a fixed value for the simulation (a real controller reports its own).
pub const SERIAL_NUMBER: u32 = 0x0440_0001;

/// The Identity object of the profile.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: VENDOR_ID,
    device_type: DEVICE_TYPE,
    product_code: PRODUCT_CODE,
    revision: REVISION,
    serial_number: SERIAL_NUMBER,
    product_name: PRODUCT_NAME,
};
