//! The Lenze (AC Tech) PositionServo drive, as its EtherNet/IP reference guide (P94ETH01D)
//! describes it, with a simulated drive behind it.
//!
//! - [`identity`]: the Identity object, "EnetIP 940" (7.1).
//! - [`params`]: the variable table and the RAM copy; [`storage`]: the EPM copy.
//! - [`classes`]: System940, class 0x64, a variable per instance, attributes 0-5 (7.2).
//! - [`assemblies`]: 103-109 (5.5) and the heartbeat points; [`datalinks`]: 5.4.
//! - [`device`]: the simulated drive, advanced by [`Device::poll`] every millisecond.
//! - [`eds`]: the EDS file's choices (`eds/position-servo.eds`).
//!
//! Connections (5.1, table 9): cyclic and application-triggered, exclusive owner, input only
//! and listen only; change-of-state is refused. An exclusive owner sets EXSTATUS bit 24
//! (0x1000000); when the last one goes, the bit clears and the drive disables, as the
//! application note of 8.4 has the drive's program do. Run/idle: the drive acts on output
//! data in Run only (the stack ignores idle data) and does nothing else on Idle. The
//! multicast TTL and address are variables 273/275 and TCP/IP attributes 8/9 at once.

pub mod assemblies;
pub mod classes;
pub mod datalinks;
pub mod device;
pub mod eds;
pub mod identity;
pub mod params;
pub mod storage;

#[cfg(test)]
mod tests;

use core::net::Ipv4Addr;

use enip_stack::cip::connection_status::TRANSPORT_NOT_SUPPORTED;
use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{Access, ClassDef};
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::MulticastConfig;
use enip_stack::device::Trigger;
use enip_stack::device::{AttributeRef, ConnectionEvent, InputChanges, Multicast, OpenRequest};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo, Instant};

use device::Servo;
use params::{id, Value, Variables, DEFAULT_MULTICAST};
use storage::EpmCopy;

/// The PositionServo: variables, their EPM copy, and the simulated drive.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PositionServo {
    servo: Servo,
    epm: EpmCopy,
    /// Input assemblies to produce now (application-triggered connections).
    changes: InputChanges,
}

impl PositionServo {
    /// A drive at power-up with an empty EPM (every variable at its default).
    pub fn new() -> Self {
        Self::with_storage(EpmCopy::new())
    }
}

impl Default for PositionServo {
    fn default() -> Self {
        Self::new()
    }
}

impl PositionServo {
    /// A drive at power-up whose variables start from the EPM copy in `epm`.
    pub fn with_storage(epm: EpmCopy) -> Self {
        PositionServo {
            servo: Servo::power_up(|id| epm.value(id)),
            epm,
            changes: InputChanges::new(),
        }
    }

    /// The RAM copy of the variables.
    pub fn variables(&self) -> &Variables {
        &self.servo.vars
    }

    /// The EPM storage.
    pub fn storage(&self) -> &EpmCopy {
        &self.epm
    }

    /// Writes `value` to variable `id`: the RAM copy, and with `epm` the EPM copy as well.
    /// Writes with an action (enable, moves) act at once; the drive's read-only variables
    /// are refreshed.
    pub fn write(&mut self, id: u16, value: Value, epm: bool) -> CipResult {
        self.servo.write(id, value, epm.then_some(&mut self.epm))
    }
}

impl Device for PositionServo {
    fn identity(&self) -> &IdentityInfo {
        &identity::IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &assemblies::INFOS
    }

    /// 7.3 lists Get_Attribute_All among the assembly instances' services.
    fn assembly_get_attributes_all(&self) -> bool {
        true
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        assemblies::read(&self.servo.vars, instance, out)
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        assemblies::write(&mut self.servo, instance, data)
    }

    fn classes(&self) -> &[ClassDef] {
        &[classes::CLASS_DEF]
    }

    /// A System940 instance is a variable of the table.
    fn has_instance(&self, _class: &ClassDef, instance: u32) -> bool {
        classes::variable(instance).is_some()
    }

    fn instance_count(&self, _class: &ClassDef) -> u32 {
        params::COUNT as u32
    }

    fn attribute_access(&self, at: &AttributeRef<'_>) -> Access {
        classes::access(at)
    }

    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        let var = classes::variable(at.instance).ok_or(General::ObjectDoesNotExist)?;
        classes::get(&self.servo.vars, var, at.attribute.id, w)
    }

    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        let var = classes::variable(at.instance).ok_or(General::ObjectDoesNotExist)?;
        let (value, epm) = classes::decode(var, at.attribute.id, value)?;
        self.write(var.id, value, epm)
    }

    /// 0 restarts from the EPM copy (a power cycle); 1 also erases the EPM (factory
    /// defaults).
    fn reset(&mut self, kind: u8) -> CipResult {
        if kind == 1 {
            self.epm
                .clear()
                .map_err(|_| General::StoreOperationFailure)?;
        }
        self.servo.restart(|id| self.epm.value(id));
        Ok(())
    }

    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::OwnershipGained => self.servo.drive.set_owned(true),
            ConnectionEvent::OwnershipLost(_) => {
                self.servo.drive.set_owned(false);
                self.servo.drive.disable();
            }
            _ => {}
        }
        self.servo.drive.publish(&mut self.servo.vars);
    }

    /// Every input assembly is made of variables (DataLinks can map any of them), so a
    /// change of any variable marks them all.
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        if self.servo.vars.take_changed() {
            let inputs = assemblies::INFOS
                .iter()
                .filter(|a| a.role == AssemblyRole::Input);
            inputs.for_each(|a| self.changes.mark(a.instance));
        }
        Some(&mut self.changes)
    }

    fn poll(&mut self, now: Instant) -> Option<Instant> {
        Some(self.servo.drive.poll(now, &mut self.servo.vars))
    }

    /// Variables 273 (TTL) and 275 (address); Num Mcast is always 1 (2.2.1). The address is
    /// "automatically generated" (alloc control 0) while it is the default 239.192.15.32.
    fn multicast(&self) -> Option<Multicast> {
        let start = self.servo.vars.raw(id::MULTICAST_ADDRESS);
        Some(Multicast {
            ttl: u8::try_from(self.servo.vars.raw(id::MULTICAST_TTL)).unwrap_or(1),
            config: MulticastConfig {
                alloc_control: u8::from(start != DEFAULT_MULTICAST),
                num_mcast: 1,
                start: Ipv4Addr::from(start),
            },
        })
    }

    /// TCP/IP attributes 8/9 write variables 273/275, RAM and EPM (the attributes are
    /// non-volatile). Alloc control 0 restores the default address; 1 needs Num Mcast 1.
    fn set_multicast(&mut self, m: Multicast) -> CipResult {
        let address = match m.config.alloc_control {
            0 => DEFAULT_MULTICAST,
            _ if m.config.num_mcast == 1 => u32::from(m.config.start),
            _ => return Err(General::InvalidAttributeValue.into()),
        };
        self.write(id::MULTICAST_TTL, Value::Integer(m.ttl.into()), true)?;
        self.write(id::MULTICAST_ADDRESS, Value::Integer(address), true)
    }

    /// Change-of-state connections are refused (5.1, table 9: cyclic and application
    /// triggered only) with 0x0103, transport class and trigger not supported.
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        if request.trigger == Trigger::ChangeOfState {
            return Err(CipError::connection(TRANSPORT_NOT_SUPPORTED));
        }
        Ok(())
    }
}
