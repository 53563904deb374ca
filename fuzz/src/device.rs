//! A small device profile for fuzzing: three assemblies and one echo vendor class.

use stack::cip::{CipError, CipResult, General, Request};
use stack::wire::Writer;
use stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};

/// Input assembly (T->O), 32 bytes.
pub const INPUT: u16 = 100;
/// Output assembly (O->T), 32 bytes.
pub const OUTPUT: u16 = 150;
/// Configuration assembly, 10 bytes.
pub const CONFIG: u16 = 151;
/// A vendor class whose instance 1 echoes the request data of service 0x4B (so does any
/// symbolic path).
pub const ECHO_CLASS: u16 = 0x64;

const ASSEMBLIES: [AssemblyInfo; 3] = [
    AssemblyInfo {
        instance: INPUT,
        role: AssemblyRole::Input,
        size: 32,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: OUTPUT,
        role: AssemblyRole::Output,
        size: 32,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 10,
        run_idle_header: false,
    },
];

const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 0xFFFE,
    device_type: 0x0C,
    product_code: 1,
    revision: (1, 1),
    serial_number: 0x0BAD_F00D,
    product_name: "enip fuzz device",
};

/// The fuzzing device: assembly data lives in plain arrays.
#[derive(Debug, Clone)]
pub struct TestDevice {
    input: [u8; 32],
    output: [u8; 32],
    config: [u8; 10],
}

impl Default for TestDevice {
    fn default() -> Self {
        Self::new()
    }
}

impl TestDevice {
    /// A device with a recognisable input pattern and zeroed output and configuration.
    pub fn new() -> Self {
        let mut input = [0u8; 32];
        for (i, b) in input.iter_mut().enumerate() {
            *b = i as u8;
        }
        TestDevice {
            input,
            output: [0; 32],
            config: [0; 10],
        }
    }

    fn data_mut(&mut self, instance: u16) -> Option<&mut [u8]> {
        match instance {
            INPUT => Some(&mut self.input),
            OUTPUT => Some(&mut self.output),
            CONFIG => Some(&mut self.config),
            _ => None,
        }
    }
}

impl Device for TestDevice {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let data = self
            .data_mut(instance)
            .ok_or(CipError::new(General::ObjectDoesNotExist))?;
        let n = data.len().min(out.len());
        out[..n].copy_from_slice(&data[..n]);
        Ok(n)
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        let slot = self
            .data_mut(instance)
            .ok_or(CipError::new(General::ObjectDoesNotExist))?;
        if slot.len() != data.len() {
            return Err(CipError::new(General::InvalidAttributeValue));
        }
        slot.copy_from_slice(data);
        Ok(())
    }

    fn vendor_classes(&self) -> &[u16] {
        &[ECHO_CLASS]
    }

    fn handle_request(&mut self, req: &Request<'_>, reply: &mut Writer<'_>) -> Option<CipResult> {
        if let Some(symbol) = req.path.symbol {
            return Some(match req.service {
                0x4B => reply
                    .bytes(symbol)
                    .and_then(|()| reply.bytes(req.data))
                    .map_err(|_| CipError::new(General::ReplyDataTooLarge)),
                _ => Err(CipError::new(General::ServiceNotSupported)),
            });
        }
        if req.path.class != Some(u32::from(ECHO_CLASS)) {
            return None;
        }
        Some(match (req.path.instance, req.service) {
            (Some(1), 0x4B) => reply
                .bytes(req.data)
                .map_err(|_| CipError::new(General::ReplyDataTooLarge)),
            (Some(1), _) => Err(CipError::new(General::ServiceNotSupported)),
            _ => Err(CipError::new(General::ObjectDoesNotExist)),
        })
    }
}
