//! [`Renamed`]: a device with its identity's serial number and product name replaced, so
//! that the devices of a fleet running the same profile tell themselves apart.

use enip_stack::device::Front;
use enip_stack::{Device, IdentityInfo};

/// Longest product name the Identity object holds (attribute 7).
pub const MAX_PRODUCT_NAME: usize = 32;

/// `D` with another identity; every other method is `D`'s.
#[derive(Debug)]
pub struct Renamed<D> {
    inner: D,
    identity: IdentityInfo,
}

impl<D: Device> Renamed<D> {
    /// `device` with `serial_number` and `product_name` where given (a name of at most
    /// [`MAX_PRODUCT_NAME`] ASCII bytes, else an error).
    pub fn new(
        device: D,
        serial_number: Option<u32>,
        product_name: Option<&str>,
    ) -> Result<Self, String> {
        let mut identity = *device.identity();
        if let Some(serial) = serial_number {
            identity.serial_number = serial;
        }
        if let Some(name) = product_name {
            if name.len() > MAX_PRODUCT_NAME || !name.is_ascii() {
                return Err(format!(
                    "product name {name:?}: at most {MAX_PRODUCT_NAME} ASCII characters"
                ));
            }
            identity.product_name = Box::leak(name.to_owned().into_boxed_str());
        }
        Ok(Renamed {
            inner: device,
            identity,
        })
    }
}

impl<D: Device> Front for Renamed<D> {
    type Inner = D;
    fn inner(&self) -> &D {
        &self.inner
    }
    fn inner_mut(&mut self) -> &mut D {
        &mut self.inner
    }
    fn front_identity(&self) -> &IdentityInfo {
        &self.identity
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use enip_stack::cip::status::CipResult;
    use enip_stack::{AssemblyInfo, AssemblyRole};

    /// A device with one assembly, recording the calls forwarded to it.
    struct Probe(u32);

    const IDENTITY: IdentityInfo = IdentityInfo {
        vendor_id: 1,
        device_type: 0x2B,
        product_code: 7,
        revision: (1, 2),
        serial_number: 42,
        product_name: "probe",
    };
    const ASSEMBLIES: [AssemblyInfo; 1] = [AssemblyInfo {
        instance: 100,
        role: AssemblyRole::Input,
        size: 4,
        run_idle_header: false,
    }];

    impl Device for Probe {
        fn identity(&self) -> &IdentityInfo {
            &IDENTITY
        }
        fn assemblies(&self) -> &[AssemblyInfo] {
            &ASSEMBLIES
        }
        fn read_assembly(&mut self, _instance: u16, out: &mut [u8]) -> CipResult<usize> {
            self.0 += 1;
            out.get_mut(..4).map_or(Ok(0), |o| {
                o.copy_from_slice(&self.0.to_le_bytes());
                Ok(4)
            })
        }
        fn write_assembly(&mut self, _instance: u16, _data: &[u8]) -> CipResult {
            Ok(())
        }
        fn status_bits(&self) -> u16 {
            0x0100
        }
    }

    #[test]
    fn replaces_the_identity_and_forwards_the_rest() {
        let mut d = Renamed::new(Probe(0), Some(0x1234_5678), Some("press 1")).unwrap();
        assert_eq!(d.identity().serial_number, 0x1234_5678);
        assert_eq!(d.identity().product_name, "press 1");
        assert_eq!(d.identity().product_code, 7);
        assert_eq!(d.status_bits(), 0x0100);
        let mut out = [0; 4];
        assert_eq!(d.read_assembly(100, &mut out), Ok(4));
        assert_eq!(out, 1u32.to_le_bytes());
        let same = Renamed::new(Probe(0), None, None).unwrap();
        assert_eq!(*same.identity(), IDENTITY);
        assert!(Renamed::new(Probe(0), None, Some(&"x".repeat(33))).is_err());
    }
}
