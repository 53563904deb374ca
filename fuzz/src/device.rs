//! A small device profile for fuzzing: three assemblies and one declared vendor class with
//! a settable number, a settable name and an echo service.

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::device::{AttributeRef, InputChanges};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};

/// Input assembly (T->O), 32 bytes.
pub const INPUT: u16 = 100;
/// Output assembly (O->T), 32 bytes.
pub const OUTPUT: u16 = 150;
/// Configuration assembly, 10 bytes.
pub const CONFIG: u16 = 151;
/// A vendor class whose instances 1 and 2 echo the request data of service 0x4B (so does
/// any symbolic path), with attributes 1 (UDINT, below 1000) and 2 (SHORT_STRING).
pub const ECHO_CLASS: u16 = 0x64;

/// The echo class as the stack serves it.
const ECHO: ClassDef = ClassDef {
    id: ECHO_CLASS,
    name: "Echo",
    revision: 1,
    max_instance: 2,
    attributes: &[
        AttributeDef::get_set(1, DataType::Udint, "Number"),
        AttributeDef::get_set(2, DataType::ShortString { max: 16 }, "Name"),
        AttributeDef::get(3, DataType::Usint, "Constant"),
    ],
    get_all: &[1, 2, 3],
    optional_attributes: &[],
};

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
    numbers: [u32; 2],
    names: [Vec<u8>; 2],
    changed: InputChanges,
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
            numbers: [0; 2],
            names: [Vec::new(), Vec::new()],
            changed: InputChanges::new(),
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

    fn classes(&self) -> &[ClassDef] {
        &[ECHO]
    }

    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        let i = (at.instance as usize).saturating_sub(1);
        match at.attribute.id {
            1 => w.u32(self.numbers.get(i).copied().unwrap_or(0))?,
            2 => {
                let name = self.names.get(i).map_or(&[][..], |n| n.as_slice());
                w.u8(name.len() as u8)?;
                w.bytes(name)?;
            }
            _ => w.u8(7)?,
        }
        Ok(())
    }

    /// Number 1 also becomes the first input byte, and the inputs are marked changed.
    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        let i = (at.instance as usize).saturating_sub(1);
        match at.attribute.id {
            1 => {
                let bytes = <[u8; 4]>::try_from(value).map_err(|_| General::NotEnoughData)?;
                let n = u32::from_le_bytes(bytes);
                if n >= 1000 {
                    return Err(General::InvalidAttributeValue.into());
                }
                if let Some(slot) = self.numbers.get_mut(i) {
                    *slot = n;
                }
                self.input[0] = n as u8;
                self.changed.mark(INPUT);
            }
            _ => {
                // The stack checked the length against the type's 16 characters.
                if let Some(slot) = self.names.get_mut(i) {
                    *slot = value.get(1..).unwrap_or(&[]).to_vec();
                }
            }
        }
        Ok(())
    }

    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changed)
    }

    fn handle_request(
        &mut self,
        _cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        if let Some(symbol) = req.path.symbol {
            return Some(match req.service {
                0x4B => reply
                    .bytes(symbol)
                    .and_then(|()| reply.bytes(req.data))
                    .map_err(|_| CipError::new(General::ReplyDataTooLarge)),
                _ => Err(CipError::new(General::ServiceNotSupported)),
            });
        }
        // Reached only for an existing instance of the declared echo class.
        (req.service == 0x4B).then(|| {
            reply
                .bytes(req.data)
                .map_err(|_| CipError::new(General::ReplyDataTooLarge))
        })
    }
}
