//! The Identity object of the generic profile: every value in one place.

use enip_stack::IdentityInfo;

/// Identity of the generic profile: every value in one place.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 1,
    // Communications adapter.
    device_type: 12,
    product_code: 65001,
    revision: (1, 1),
    serial_number: 0x5255_5354,
    product_name: "enip-rs generic",
};
