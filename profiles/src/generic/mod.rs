//! The generic profile: the assemblies of the OpENer sample application under our identity.
//!
//! Output data written to assembly 150 is echoed into input assembly 100, so a scanner sees
//! its own outputs come back (an application-triggered connection produces it at once); 154
//! is a scratch assembly for explicit messaging.

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::InputChanges;
use enip_stack::eds::{EdsInfo, RpiRange, Triggers};
use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};

/// Identity of the generic profile: every value in one place.
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 1,
    // Communications adapter.
    device_type: 12,
    product_code: 65001,
    revision: (1, 0),
    serial_number: 0x5255_5354,
    product_name: "enip-rs generic",
};

/// The EDS choices of the generic profile (`eds/generic.eds`).
pub const EDS: EdsInfo<'static> = EdsInfo {
    description: "enip-rs generic adapter (OpENer sample application assemblies)",
    date: "12-01-2026",
    vendor_name: "enip-rs",
    product_type_name: "Communications Adapter",
    catalog: "ENIP-RS-GENERIC",
    rpi_us: RpiRange {
        min: enip_stack::config::MIN_RPI_US,
        max: enip_stack::config::MAX_RPI_US,
        default: 10_000,
    },
    triggers: Triggers::ALL,
    assembly_names: &[
        (INPUT, "Input (echo of the outputs)"),
        (OUTPUT, "Output"),
        (CONFIG, "Configuration"),
        (EXPLICIT, "Explicit messaging scratch"),
    ],
    member_bits: 0,
};

/// Input assembly (T->O data).
pub const INPUT: u16 = 100;
/// Output assembly (O->T data, with the run/idle header); echoed into [`INPUT`].
pub const OUTPUT: u16 = 150;
/// Configuration assembly.
pub const CONFIG: u16 = 151;
/// O->T connection point of input-only connections.
pub const INPUT_ONLY_HEARTBEAT: u16 = 152;
/// O->T connection point of listen-only connections.
pub const LISTEN_ONLY_HEARTBEAT: u16 = 153;
/// Assembly for explicit messaging only: reads back what was written.
pub const EXPLICIT: u16 = 154;

/// Size of the input, output and explicit assemblies in bytes.
pub const IO_SIZE: usize = 32;
/// Size of the configuration assembly in bytes.
pub const CONFIG_SIZE: usize = 10;

/// The assembly instances, as the stack sees them.
const ASSEMBLIES: [AssemblyInfo; 6] = [
    assembly(INPUT, AssemblyRole::Input, IO_SIZE, false),
    assembly(OUTPUT, AssemblyRole::Output, IO_SIZE, true),
    assembly(CONFIG, AssemblyRole::Config, CONFIG_SIZE, false),
    assembly(
        INPUT_ONLY_HEARTBEAT,
        AssemblyRole::InputOnlyHeartbeat,
        0,
        false,
    ),
    assembly(
        LISTEN_ONLY_HEARTBEAT,
        AssemblyRole::ListenOnlyHeartbeat,
        0,
        false,
    ),
    assembly(EXPLICIT, AssemblyRole::Explicit, IO_SIZE, false),
];

const fn assembly(
    instance: u16,
    role: AssemblyRole,
    size: usize,
    run_idle_header: bool,
) -> AssemblyInfo {
    AssemblyInfo {
        instance,
        role,
        size: size as u16,
        run_idle_header,
    }
}

/// The generic device: assembly data, all zero at power-up.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Generic {
    /// The outputs, which are also the inputs (the echo).
    output: [u8; IO_SIZE],
    config: [u8; CONFIG_SIZE],
    explicit: [u8; IO_SIZE],
    changed: InputChanges,
}

impl Generic {
    /// A device with every assembly zeroed.
    pub const fn new() -> Self {
        Generic {
            output: [0; IO_SIZE],
            config: [0; CONFIG_SIZE],
            explicit: [0; IO_SIZE],
            changed: InputChanges::new(),
        }
    }

    /// The data of assembly `instance`, if it exists.
    fn data(&self, instance: u16) -> Option<&[u8]> {
        match instance {
            INPUT | OUTPUT => Some(&self.output),
            CONFIG => Some(&self.config),
            INPUT_ONLY_HEARTBEAT | LISTEN_ONLY_HEARTBEAT => Some(&[]),
            EXPLICIT => Some(&self.explicit),
            _ => None,
        }
    }
}

impl Default for Generic {
    fn default() -> Self {
        Self::new()
    }
}

impl Device for Generic {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let data = self.data(instance).ok_or(unknown())?;
        let n = data.len().min(out.len());
        if let (Some(dst), Some(src)) = (out.get_mut(..n), data.get(..n)) {
            dst.copy_from_slice(src);
        }
        Ok(n)
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            OUTPUT => {
                if data != self.output {
                    copy_exact(&mut self.output, data)?;
                    self.changed.mark(INPUT);
                }
                Ok(())
            }
            CONFIG => copy_exact(&mut self.config, data),
            EXPLICIT => copy_exact(&mut self.explicit, data),
            INPUT_ONLY_HEARTBEAT | LISTEN_ONLY_HEARTBEAT => copy_exact(&mut [], data),
            INPUT => Err(General::AttributeNotSettable.into()),
            _ => Err(unknown()),
        }
    }

    /// The echo of new outputs into [`INPUT`].
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changed)
    }
}

/// Error for an assembly instance the device does not have.
const fn unknown() -> CipError {
    CipError::new(General::PathDestinationUnknown)
}

/// Replaces `dst` with `src`, which must have exactly its length.
fn copy_exact(dst: &mut [u8], src: &[u8]) -> CipResult {
    match src.len().cmp(&dst.len()) {
        core::cmp::Ordering::Less => Err(General::NotEnoughData.into()),
        core::cmp::Ordering::Greater => Err(General::TooMuchData.into()),
        core::cmp::Ordering::Equal => {
            dst.copy_from_slice(src);
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(dev: &mut Generic, instance: u16) -> CipResult<([u8; 64], usize)> {
        let mut buf = [0u8; 64];
        let size = dev
            .assemblies()
            .iter()
            .find(|a| a.instance == instance)
            .map_or(64, |a| usize::from(a.size));
        let n = dev.read_assembly(instance, &mut buf[..size])?;
        Ok((buf, n))
    }

    #[test]
    fn declares_the_opener_sample_assemblies() {
        let dev = Generic::new();
        let list: [(u16, AssemblyRole, u16, bool); 6] = [
            (100, AssemblyRole::Input, 32, false),
            (150, AssemblyRole::Output, 32, true),
            (151, AssemblyRole::Config, 10, false),
            (152, AssemblyRole::InputOnlyHeartbeat, 0, false),
            (153, AssemblyRole::ListenOnlyHeartbeat, 0, false),
            (154, AssemblyRole::Explicit, 32, false),
        ];
        assert_eq!(dev.assemblies().len(), list.len());
        for (a, (instance, role, size, header)) in dev.assemblies().iter().zip(list) {
            assert_eq!(
                (a.instance, a.role, a.size, a.run_idle_header),
                (instance, role, size, header)
            );
        }
    }

    #[test]
    fn output_is_echoed_into_input() {
        let mut dev = Generic::new();
        let data: [u8; 32] = core::array::from_fn(|i| i as u8 + 1);
        dev.write_assembly(OUTPUT, &data).unwrap();
        let (buf, n) = read(&mut dev, INPUT).unwrap();
        assert_eq!(&buf[..n], &data);
        let (buf, n) = read(&mut dev, OUTPUT).unwrap();
        assert_eq!(&buf[..n], &data);
    }

    #[test]
    fn explicit_and_config_read_back_what_was_written() {
        let mut dev = Generic::new();
        dev.write_assembly(EXPLICIT, &[0xA5; 32]).unwrap();
        dev.write_assembly(CONFIG, &[7; 10]).unwrap();
        let (buf, n) = read(&mut dev, EXPLICIT).unwrap();
        assert_eq!(&buf[..n], &[0xA5; 32]);
        let (buf, n) = read(&mut dev, CONFIG).unwrap();
        assert_eq!(&buf[..n], &[7; 10]);
        // Neither touches the input data.
        let (buf, n) = read(&mut dev, INPUT).unwrap();
        assert_eq!(&buf[..n], &[0; 32]);
    }

    #[test]
    fn heartbeats_are_empty() {
        let mut dev = Generic::new();
        for hb in [INPUT_ONLY_HEARTBEAT, LISTEN_ONLY_HEARTBEAT] {
            assert_eq!(read(&mut dev, hb).unwrap().1, 0);
            assert_eq!(dev.write_assembly(hb, &[]), Ok(()));
            assert_eq!(
                dev.write_assembly(hb, &[1]),
                Err(General::TooMuchData.into())
            );
        }
    }

    #[test]
    fn wrong_sizes_and_instances_are_refused() {
        let mut dev = Generic::new();
        assert_eq!(
            dev.write_assembly(OUTPUT, &[1; 31]),
            Err(General::NotEnoughData.into())
        );
        assert_eq!(
            dev.write_assembly(OUTPUT, &[1; 33]),
            Err(General::TooMuchData.into())
        );
        assert_eq!(
            dev.write_assembly(INPUT, &[1; 32]),
            Err(General::AttributeNotSettable.into())
        );
        assert_eq!(dev.write_assembly(99, &[]), Err(unknown()));
        assert_eq!(read(&mut dev, 99).map(|r| r.1), Err(unknown()));
        // A refused write leaves the data alone.
        assert_eq!(read(&mut dev, INPUT).unwrap().0[..32], [0; 32]);
    }

    #[test]
    fn identity_matches_the_constants() {
        let dev = Generic::new();
        let id = dev.identity();
        assert_eq!(
            (id.vendor_id, id.device_type, id.product_code),
            (1, 12, 65001)
        );
        assert_eq!(id.revision, (1, 0));
        assert_eq!(id.serial_number, 0x5255_5354);
        assert_eq!(id.product_name, "enip-rs generic");
    }
}
