//! Electronic key matching (key format 4, logical segment 0x34): the one check that both a
//! Forward_Open's connection path and every explicit request path go through, and the
//! status each of them answers a mismatch with.
//!
//! The rules (CIP Vol 1, C-1.4.2 and its Key Format Table; the extended status of each part
//! as Vol 1 table 3-5.33 names it):
//! - Compatibility bit clear: a key field of zero matches anything, any other value must be
//!   the device's own. A major revision of zero leaves the revision unchecked (the minor
//!   revision only means something within a major one); a minor revision of zero accepts
//!   any minor revision of the given major.
//! - Compatibility bit set: the key names a device the target is asked to emulate, so zero
//!   is not a valid value of any field. This stack emulates no other product: vendor ID,
//!   product code, device type and major revision must be the device's own, and the minor
//!   revision between 1 and the device's (a newer device emulates an older minor revision).
//!
//! The parts are checked in the order vendor ID / product code (0x0114), device type
//! (0x0115), revision (0x0116), and the first that fails is reported.

use super::IdentityInfo;
use crate::cip::connection_status as ext;
use crate::cip::status::{CipError, General};
use crate::wire::epath::ElectronicKey;

/// The part of an electronic key the device does not match.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum KeyMismatch {
    /// Vendor ID or product code (extended status 0x0114).
    VendorProduct,
    /// Device type (extended status 0x0115).
    DeviceType,
    /// Major or minor revision (extended status 0x0116).
    Revision,
}

impl KeyMismatch {
    /// The extended status that says which part failed.
    pub const fn extended_status(self) -> u16 {
        match self {
            KeyMismatch::VendorProduct => ext::KEY_VENDOR_PRODUCT,
            KeyMismatch::DeviceType => ext::KEY_DEVICE_TYPE,
            KeyMismatch::Revision => ext::KEY_REVISION,
        }
    }
    /// The Forward_Open answer: connection failure (0x01) with the extended status.
    pub const fn connection_failure(self) -> CipError {
        CipError::connection(self.extended_status())
    }
    /// The answer to an explicit request whose path starts with the key: key failure in
    /// path (0x25) with the extended status.
    pub const fn path_failure(self) -> CipError {
        CipError::new(General::KeyFailureInPath).with_extended(self.extended_status())
    }
}

/// Checks `key` against the device's identity `id` by the rules of the module comment.
pub fn check(key: &ElectronicKey, id: &IdentityInfo) -> Result<(), KeyMismatch> {
    let emulate = key.compatibility;
    let field_matches = |want: u16, have: u16| {
        if emulate {
            want != 0 && want == have
        } else {
            want == 0 || want == have
        }
    };
    if !field_matches(key.vendor_id, id.vendor_id)
        || !field_matches(key.product_code, id.product_code)
    {
        return Err(KeyMismatch::VendorProduct);
    }
    if !field_matches(key.device_type, id.device_type) {
        return Err(KeyMismatch::DeviceType);
    }
    let (major, minor) = id.revision;
    let (want_major, want_minor) = (key.major_revision, key.minor_revision);
    let revision_ok = if emulate {
        want_major != 0 && want_major == major && want_minor != 0 && want_minor <= minor
    } else {
        want_major == 0 || (want_major == major && (want_minor == 0 || want_minor == minor))
    };
    if !revision_ok {
        return Err(KeyMismatch::Revision);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vendor 1, device type 12, product 65001, revision 3.4.
    const ID: IdentityInfo = IdentityInfo {
        vendor_id: 1,
        device_type: 12,
        product_code: 65001,
        revision: (3, 4),
        serial_number: 7,
        product_name: "key test",
    };

    /// The device's exact key, compatibility bit clear.
    const EXACT: ElectronicKey = ElectronicKey {
        vendor_id: 1,
        device_type: 12,
        product_code: 65001,
        major_revision: 3,
        compatibility: false,
        minor_revision: 4,
    };

    const ZERO: ElectronicKey = ElectronicKey {
        vendor_id: 0,
        device_type: 0,
        product_code: 0,
        major_revision: 0,
        compatibility: false,
        minor_revision: 0,
    };

    fn compatible(key: ElectronicKey) -> ElectronicKey {
        ElectronicKey {
            compatibility: true,
            ..key
        }
    }

    #[test]
    fn the_exact_key_matches() {
        assert_eq!(check(&EXACT, &ID), Ok(()));
        assert_eq!(check(&compatible(EXACT), &ID), Ok(()));
    }

    #[test]
    fn an_all_zero_key_matches_anything() {
        assert_eq!(check(&ZERO, &ID), Ok(()));
    }

    #[test]
    fn each_zero_field_is_a_wildcard_without_the_compatibility_bit() {
        // Only the zeroed field is wrong in each case: it must not count.
        assert_eq!(
            check(
                &ElectronicKey {
                    vendor_id: 0,
                    ..EXACT
                },
                &ID
            ),
            Ok(())
        );
        assert_eq!(
            check(
                &ElectronicKey {
                    product_code: 0,
                    ..EXACT
                },
                &ID
            ),
            Ok(())
        );
        assert_eq!(
            check(
                &ElectronicKey {
                    device_type: 0,
                    ..EXACT
                },
                &ID
            ),
            Ok(())
        );
        assert_eq!(
            check(
                &ElectronicKey {
                    minor_revision: 0,
                    ..EXACT
                },
                &ID
            ),
            Ok(())
        );
        // Major revision 0: the revision is not checked at all, whatever the minor says.
        let any_revision = ElectronicKey {
            major_revision: 0,
            minor_revision: 9,
            ..EXACT
        };
        assert_eq!(check(&any_revision, &ID), Ok(()));
    }

    #[test]
    fn a_wrong_vendor_or_product_code_is_0x0114() {
        let vendor = ElectronicKey {
            vendor_id: 2,
            ..EXACT
        };
        let product = ElectronicKey {
            product_code: 1,
            ..EXACT
        };
        assert_eq!(check(&vendor, &ID), Err(KeyMismatch::VendorProduct));
        assert_eq!(check(&product, &ID), Err(KeyMismatch::VendorProduct));
        assert_eq!(KeyMismatch::VendorProduct.extended_status(), 0x0114);
    }

    #[test]
    fn a_wrong_device_type_is_0x0115() {
        let key = ElectronicKey {
            device_type: 13,
            ..EXACT
        };
        assert_eq!(check(&key, &ID), Err(KeyMismatch::DeviceType));
        assert_eq!(KeyMismatch::DeviceType.extended_status(), 0x0115);
    }

    #[test]
    fn a_wrong_major_or_minor_revision_is_0x0116() {
        for (major, minor) in [(2, 4), (4, 4), (3, 3), (3, 5)] {
            let key = ElectronicKey {
                major_revision: major,
                minor_revision: minor,
                ..EXACT
            };
            assert_eq!(
                check(&key, &ID),
                Err(KeyMismatch::Revision),
                "{major}.{minor}"
            );
        }
        assert_eq!(KeyMismatch::Revision.extended_status(), 0x0116);
    }

    #[test]
    fn vendor_and_product_are_checked_before_device_type_and_revision() {
        let all_wrong = ElectronicKey {
            vendor_id: 2,
            device_type: 13,
            product_code: 65001,
            major_revision: 9,
            compatibility: false,
            minor_revision: 9,
        };
        assert_eq!(check(&all_wrong, &ID), Err(KeyMismatch::VendorProduct));
        let type_and_revision = ElectronicKey {
            vendor_id: 1,
            ..all_wrong
        };
        assert_eq!(check(&type_and_revision, &ID), Err(KeyMismatch::DeviceType));
    }

    #[test]
    fn the_compatibility_bit_accepts_an_older_minor_revision_of_the_same_major() {
        for minor in 1..=4 {
            let key = compatible(ElectronicKey {
                minor_revision: minor,
                ..EXACT
            });
            assert_eq!(check(&key, &ID), Ok(()), "3.{minor}");
        }
    }

    #[test]
    fn the_compatibility_bit_refuses_a_newer_minor_or_another_major() {
        for (major, minor) in [(3, 5), (3, 255), (2, 1), (4, 1)] {
            let key = compatible(ElectronicKey {
                major_revision: major,
                minor_revision: minor,
                ..EXACT
            });
            assert_eq!(
                check(&key, &ID),
                Err(KeyMismatch::Revision),
                "{major}.{minor}"
            );
        }
    }

    #[test]
    fn with_the_compatibility_bit_a_zero_field_is_refused_with_its_part() {
        let c = compatible(EXACT);
        let cases = [
            (
                ElectronicKey { vendor_id: 0, ..c },
                KeyMismatch::VendorProduct,
            ),
            (
                ElectronicKey {
                    product_code: 0,
                    ..c
                },
                KeyMismatch::VendorProduct,
            ),
            (
                ElectronicKey {
                    device_type: 0,
                    ..c
                },
                KeyMismatch::DeviceType,
            ),
            (
                ElectronicKey {
                    major_revision: 0,
                    ..c
                },
                KeyMismatch::Revision,
            ),
            (
                ElectronicKey {
                    minor_revision: 0,
                    ..c
                },
                KeyMismatch::Revision,
            ),
            (compatible(ZERO), KeyMismatch::VendorProduct),
        ];
        for (i, (key, want)) in cases.iter().enumerate() {
            assert_eq!(check(key, &ID), Err(*want), "case {i}");
        }
    }

    #[test]
    fn the_two_answers_carry_the_part_in_their_extended_status() {
        let fo = KeyMismatch::DeviceType.connection_failure();
        assert_eq!(
            (fo.general, fo.extended()),
            (General::ConnectionFailure, Some(0x0115))
        );
        let explicit = KeyMismatch::Revision.path_failure();
        assert_eq!(
            (explicit.general as u8, explicit.additional()),
            (0x25, &[0x0116u16][..])
        );
    }
}
