//! The Kollmorgen AKD servo drive with its EtherNet/IP option, as the AKD EtherNet/IP
//! Communication manual (December 2014) describes it, with a simulated drive behind it.
//!
//! - [`identity`]: the Identity object values (project choices, documented).
//! - [`assemblies`]: 100 (configuration, 0 bytes), 101 (command, 64 bytes with run/idle),
//!   102 (response, 64 bytes) and their layouts.
//! - [`handshake`]: the control word and the Load/Start handshake; [`response`]: the
//!   response assembly's encoder.
//! - [`params`]: the parameter table; [`classes`]: class 0x25 (Position Controller), class
//!   0x24 (Position Controller Supervisor) and class 0x0F (Parameter), with [`maps`]
//!   (EIP.CMDMAP, EIP.RSPMAP) for [`dynamic_map`], map type 2.
//! - [`device`]: the simulated drive, advanced by [`Device::poll`] every millisecond;
//!   [`motion_tasks`]: its task table; [`state`]: the drive with the Position Controller
//!   settings, the parameters' values and the unit conversions; [`storage`]: DRV.NVSAVE's
//!   copy.
//!
//! Connections (p.10-11): exclusive owner, cyclic ("transmitted on a timer"), RPI 10 ms or
//! more, multicast or point-to-point T->O. Other triggers are refused with 0x0103, shorter
//! RPIs with 0x0112. When the owner goes (timeout or close), the drive makes a controlled
//! stop at DRV.DECSTOP and disables at rest; when the PLC goes to Program mode (O->T
//! run/idle header Idle), it makes the same stop and stays enabled. Explicit requests to a
//! class the drive does not have answer 0x16, "Class Not Supported" (p.10).

pub mod assemblies;
pub mod classes;
pub mod device;
pub mod dynamic_map;
pub mod eds;
pub mod handshake;
pub mod identity;
pub mod maps;
pub mod motion_tasks;
pub mod params;
pub mod response;
pub mod state;
pub mod storage;

use classes::{parameter, position_controller, supervisor};

#[cfg(test)]
mod tests;

use enip_stack::cip::connection_status::TRANSPORT_NOT_SUPPORTED;
use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{Access, ClassDef};
use enip_stack::cip::request::Request;
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::{AttributeRef, ConnectionEvent, OpenRequest};
use enip_stack::device::{Kind, Trigger};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, Device, IdentityInfo, Instant};

use handshake::Handshake;
use params::{id, Rule, View};
use state::State;
use storage::{NvCopy, Parameters};

/// Shortest RPI, microseconds: "10 ms or greater" (p.11; 20 ms with Workbench connected).
pub const MIN_RPI_US: u32 = 10_000;
/// Longest RPI, microseconds: the stack's own limit (the manual gives none).
pub const MAX_RPI_US: u32 = enip_stack::config::MAX_RPI_US;

/// The AKD: its state, the I/O handshake and the non-volatile parameter copy.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KollmorgenAkd {
    state: State,
    io: Handshake,
    nv: NvCopy,
}

impl KollmorgenAkd {
    /// A drive at power-up with empty non-volatile storage.
    pub fn new() -> Self {
        Self::with_storage(NvCopy::new())
    }
}

impl Default for KollmorgenAkd {
    fn default() -> Self {
        Self::new()
    }
}

impl KollmorgenAkd {
    /// A drive at power-up whose parameters start from the saved copy in `nv`.
    pub fn with_storage(nv: NvCopy) -> Self {
        let mut akd = KollmorgenAkd {
            state: State::new(),
            io: Handshake::new(),
            nv,
        };
        akd.restore();
        akd
    }

    /// The drive's state.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The non-volatile storage.
    pub fn storage(&self) -> &NvCopy {
        &self.nv
    }

    /// Writes `value` to a parameter: commands execute (on any value), read-write ones are
    /// stored, read-only ones answer 0x0E.
    pub fn write_parameter(&mut self, view: &View, value: i64) -> CipResult {
        parameter::write(&mut self.state, &mut self.nv, view, value)
    }

    /// Power-up: factory values, then the saved copy (unit parameters first, so the
    /// others scale with them).
    fn restore(&mut self) {
        self.state = State::new();
        self.io = Handshake::new();
        let Some(&Parameters(image)) = self.nv.load() else {
            return;
        };
        let units = |p: &params::Param| matches!(p.instance, id::EIP_POSUNIT | id::EIP_PROFUNIT);
        for pass in [true, false] {
            for (p, value) in params::TABLE.iter().zip(image.iter()) {
                if p.rule == Rule::ReadWrite && units(p) == pass {
                    // A value the table refuses keeps its factory value.
                    let _ = self.state.set_param(p, *value);
                }
            }
        }
    }
}

impl Device for KollmorgenAkd {
    fn identity(&self) -> &IdentityInfo {
        &identity::IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &assemblies::INFOS
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        match instance {
            assemblies::RESPONSE => Ok(response::encode(&self.state, &self.io, out)),
            assemblies::COMMAND => {
                let cmd = self.io.command();
                let n = out.len().min(cmd.len());
                for (o, c) in out.iter_mut().zip(cmd) {
                    *o = *c;
                }
                Ok(n)
            }
            assemblies::CONFIG => Ok(0),
            _ => Err(General::PathDestinationUnknown.into()),
        }
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            assemblies::COMMAND => {
                handshake::consume(&mut self.io, &mut self.state, &mut self.nv, data);
                Ok(())
            }
            // The configuration assembly has no data.
            assemblies::CONFIG if data.is_empty() => Ok(()),
            assemblies::CONFIG => Err(General::TooMuchData.into()),
            _ => Err(General::AttributeNotSettable.into()),
        }
    }

    fn classes(&self) -> &[ClassDef] {
        &[
            position_controller::CLASS_DEF,
            parameter::CLASS_DEF,
            supervisor::CLASS_DEF,
        ]
    }

    fn has_instance(&self, class: &ClassDef, instance: u32) -> bool {
        match class.id {
            parameter::CLASS => params::view(instance).is_some() || maps::which(instance).is_some(),
            _ => instance == 1,
        }
    }

    fn instance_count(&self, class: &ClassDef) -> u32 {
        match class.id {
            parameter::CLASS => {
                (params::instances().count() as u32).saturating_add(maps::INSTANCES)
            }
            _ => 1,
        }
    }

    fn attribute_access(&self, at: &AttributeRef<'_>) -> Access {
        match (at.class.id, params::view(at.instance)) {
            (parameter::CLASS, Some(view)) => {
                parameter::access(&view, at.attribute.id, at.attribute.access)
            }
            _ => at.attribute.access,
        }
    }

    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        match at.class.id {
            parameter::CLASS => {
                if let Some(which) = maps::which(at.instance) {
                    return parameter::get_map(&self.state.maps, which, at.attribute.id, w);
                }
                let view = params::view(at.instance).ok_or(General::ObjectDoesNotExist)?;
                parameter::get(&self.state, &view, at.attribute.id, w)
            }
            supervisor::CLASS => {
                supervisor::read(&self.state, self.io.command(), at.attribute.id, w)
            }
            _ => position_controller::read(&self.state, at.attribute.id, w),
        }
    }

    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        match at.class.id {
            parameter::CLASS => {
                if let Some(which) = maps::which(at.instance) {
                    return parameter::set_map(&mut self.state.maps, which, value);
                }
                let view = params::view(at.instance).ok_or(General::ObjectDoesNotExist)?;
                let v = parameter::decode(&view, value)?;
                self.write_parameter(&view, v)
            }
            supervisor::CLASS => Err(General::AttributeNotSettable.into()),
            _ => position_controller::write(&mut self.state, at.attribute.id, value),
        }
    }

    /// A class the drive does not have: 0x16, the manual's "Class Not Supported" (p.10,
    /// \[R\] item 11); symbolic paths stay the stack's (0x05).
    fn handle_request(
        &mut self,
        _cx: &RequestContext,
        req: &Request<'_>,
        _reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        let declared = [
            position_controller::CLASS,
            parameter::CLASS,
            supervisor::CLASS,
        ];
        match req.path.class {
            Some(c) if !declared.iter().any(|&d| u32::from(d) == c) => {
                Some(Err(General::ObjectDoesNotExist.into()))
            }
            _ => None,
        }
    }

    /// 0 restarts from the saved parameters (a power cycle); 1 also erases them.
    fn reset(&mut self, kind: u8) -> CipResult {
        if kind == 1 {
            self.nv
                .clear()
                .map_err(|_| General::StoreOperationFailure)?;
        }
        self.restore();
        Ok(())
    }

    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(c) if c.kind == Kind::ExclusiveOwner => {
                self.io.restart();
                self.state.drive.keep_enabled();
            }
            // Timeout or close: a controlled stop, then the drive disables at rest.
            ConnectionEvent::OwnershipLost(_) => {
                self.state.drive.controlled_stop(true);
                self.io.restart();
            }
            // The PLC went to Program mode: a controlled stop; the drive stays enabled.
            ConnectionEvent::RunIdle(false) => self.state.drive.controlled_stop(false),
            _ => {}
        }
    }

    fn poll(&mut self, now: Instant) -> Option<Instant> {
        Some(self.state.drive.poll(now))
    }

    /// Cyclic connections only (p.10: "transmitted on a timer"), RPI 10 ms or more.
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        if request.is_class1() && request.trigger != Trigger::Cyclic {
            return Err(CipError::connection(TRANSPORT_NOT_SUPPORTED));
        }
        if request.is_class1() {
            return request.refuse_rpi(MIN_RPI_US, MAX_RPI_US);
        }
        Ok(())
    }
}
