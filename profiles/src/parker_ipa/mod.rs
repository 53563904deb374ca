//! The Parker IPA / ACR9000 controller, as its EtherNet/IP Programmer's Guide
//! (88-032525-01 A, February 2015) describes it, with a simulated ACR controller behind it.
//!
//! - [`identity`]: the Identity object (the manual has none; digest section 2).
//! - [`params`]: the P parameters (float, long and flag ranges, axes, user banks), typed,
//!   with conversion; [`device`]: the axes, which move while their jog command bits say so.
//! - [`classes`]: class 0x64 "ACR Parameter", services 0x50-0x54; class 0x65 "ACR Group",
//!   0x53 Read Group and 0x34 Write Binary ([`classes::binary`]); the tag services
//!   0x4C/0x4D/0x48/0x4E on "P4012" symbolic paths.
//! - [`ioconfig`]: the I/O groups P37434, P37440-P37503 and their validation (Table 3);
//!   [`assemblies`]: 101/102/3; [`status`]: the CIP status parameters P37424-P37439.
//!
//! Connections: one Class 1 connection at a time (p.3), exclusive owner of 102/101 with
//! configuration point 3, RPI at least 1 ms (Table 4), T->O point-to-point or multicast;
//! Class 3 connections alongside. The group configuration is validated at each Class 1
//! Forward_Open and latched while the connection runs (R5.5). Run/idle: O->T data is applied
//! in Run only (the stack never hands Idle data over, R6.4).

pub mod assemblies;
pub mod classes;
pub mod device;
pub mod eds;
pub mod identity;
pub mod ioconfig;
pub mod memory;
pub mod params;
pub mod status;

#[cfg(test)]
mod tests;

use enip_stack::cip::connection_status::{NOT_CONFIGURED, OUT_OF_CONNECTIONS, OWNERSHIP_CONFLICT};
use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::ClassDef;
use enip_stack::cip::{CipError, CipResult, Request};
use enip_stack::config::MAX_RPI_US;
use enip_stack::device::Kind as ConnectionKind;
use enip_stack::device::{ConnectionEvent, InputChanges, OpenRequest};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, Device, IdentityInfo, Instant};

use classes::{class64, class65, tags};
use device::Axes;
use ioconfig::{Direction, Layout};
use memory::Memory;
use params::Value;
use status::CipStatus;

/// Minimum RPI, both directions (Table 4: 1 ms).
pub const MIN_RPI_US: u32 = 1_000;

/// The IPA controller: its parameters, the latched I/O layout, the CIP status and the axes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParkerIpa {
    memory: Memory,
    /// The I/O layout validated at the last accepted Class 1 Forward_Open.
    layout: Layout,
    axes: Axes,
    changes: InputChanges,
    /// Bytes of binary commands executed (class 0x65 service 0x34).
    pub binary_bytes: u32,
}

impl Default for ParkerIpa {
    fn default() -> Self {
        Self::new()
    }
}

impl ParkerIpa {
    /// The controller at power-up: Program1 has loaded the AOI I/O configuration (p.9).
    pub fn new() -> Self {
        let memory = Memory::power_up();
        let store = &memory.store;
        let layout = ioconfig::validate(store.groups_in_use(), &store.config())
            .unwrap_or_else(|_| Layout::empty());
        ParkerIpa {
            memory,
            layout,
            axes: Axes::default(),
            changes: InputChanges::new(),
            binary_bytes: 0,
        }
    }

    /// The value of parameter `p` in its native type, or `None` if it does not exist.
    pub fn get(&self, p: u32) -> Option<Value> {
        self.memory.get(p)
    }

    /// Writes `value` to parameter `p`, converted to its type; `None` if it does not exist.
    /// Computed status parameters ignore the write (R7.2).
    pub fn set(&mut self, p: u32, value: Value) -> Option<()> {
        self.memory.set(p, value)
    }

    /// The CIP status behind P37424-P37439.
    pub fn cip_status(&self) -> &CipStatus {
        &self.memory.status
    }

    /// The I/O layout latched at the last accepted Class 1 Forward_Open.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Validates the current group configuration for a Class 1 Forward_Open: latches it, or
    /// reports the Table 3 status in P37433-P37437 and refuses with 0x01/0x0110 (R5.8).
    fn configure(&mut self) -> CipResult {
        match ioconfig::validate(
            self.memory.store.groups_in_use(),
            &self.memory.store.config(),
        ) {
            Ok(layout) => {
                self.memory.status.entry = layout.last;
                self.layout = layout;
                Ok(())
            }
            Err(e) => {
                self.memory.status.status = e.status;
                self.memory.status.entry = e.entry;
                Err(CipError::connection(NOT_CONFIGURED))
            }
        }
    }
}

impl Device for ParkerIpa {
    fn identity(&self) -> &IdentityInfo {
        &identity::IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &assemblies::INFOS
    }

    /// R5.6: a connection may carry from the configured groups' bytes (4 per parameter going
    /// that way) up to 400. While a Class 1 connection is open, or the configuration is
    /// invalid, any size up to 400 passes here, so that the admission answers first with
    /// 0x0106/0x0113 or the configuration status (R5.10: steps 2 and 5 before step 6).
    fn accepts_connection_size(&self, assembly: &AssemblyInfo, data: usize) -> bool {
        let direction = match assembly.instance {
            assemblies::INPUT => Direction::Produce,
            assemblies::OUTPUT => Direction::Consume,
            _ => return data == usize::from(assembly.size),
        };
        if self.memory.status.class1_slot.is_some() {
            return true;
        }
        match ioconfig::validate(
            self.memory.store.groups_in_use(),
            &self.memory.store.config(),
        ) {
            Ok(layout) => layout.longs(direction).saturating_mul(4) <= data,
            Err(_) => true,
        }
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let direction = match instance {
            assemblies::INPUT => Direction::Produce,
            assemblies::OUTPUT => Direction::Consume,
            _ => return Ok(0),
        };
        Ok(assemblies::image(
            &self.memory,
            &self.layout,
            direction,
            out,
        ))
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        if instance != assemblies::OUTPUT {
            return Ok(());
        }
        if self.memory.status.class1_slot.is_some() {
            self.memory.status.class1_messages = self.memory.status.class1_messages.wrapping_add(1);
        }
        let layout = self.layout.clone();
        assemblies::consume(&mut self.memory, &layout, data)
    }

    fn classes(&self) -> &[ClassDef] {
        &[class64::CLASS_DEF, class65::CLASS_DEF]
    }

    /// Every instance number is a P number (or a group and index): whether the parameters
    /// exist is each service's answer, 0x05 (Table 8, p.30: an instance "that is not
    /// known"), not the stack's 0x16, also above 65535 (class attribute 2 still says 65535,
    /// the highest P number).
    fn has_instance(&self, _class: &ClassDef, _instance: u32) -> bool {
        true
    }

    fn instance_count(&self, class: &ClassDef) -> u32 {
        match class.id {
            class64::CLASS => class64::INSTANCES,
            _ => class.max_instance,
        }
    }

    fn handle_request(
        &mut self,
        cx: &RequestContext,
        req: &Request<'_>,
        reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        let class = req.path.class.and_then(|c| u16::try_from(c).ok());
        let ours = match class {
            Some(c) => c == class64::CLASS || c == class65::CLASS,
            None => req.path.symbol.is_some(),
        };
        if ours {
            self.memory.status.class3_messages = self.memory.status.class3_messages.wrapping_add(1);
        }
        match class {
            Some(class64::CLASS) => class64::handle(&mut self.memory, req, reply),
            Some(class65::CLASS) => {
                class65::handle(&mut self.memory, &mut self.binary_bytes, cx, req, reply)
            }
            None => tags::handle(&mut self.memory, req, reply),
            Some(_) => None,
        }
    }

    /// Class 1 admission in the order of R5.10 (the stack has already refused duplicates,
    /// bad paths, sizes and RPIs below its own minimum): a second Class 1 connection 0x0106
    /// (exclusive owner) or 0x0113, leaving P37429/P37430 on the running connection's
    /// client; else note the attempt (P37429, P37430); RPI below 1 ms 0x0112; the group
    /// configuration (statuses 2-7, 0x0110).
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        if !request.is_class1() {
            return Ok(());
        }
        if self.memory.status.class1_slot.is_some() {
            let ext = match request.kind {
                ConnectionKind::ExclusiveOwner => OWNERSHIP_CONFLICT,
                _ => OUT_OF_CONNECTIONS,
            };
            return Err(CipError::connection(ext));
        }
        self.memory.status.attempt(request.originator);
        request.refuse_rpi(MIN_RPI_US, MAX_RPI_US)?;
        self.configure()
    }

    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(c) if c.kind == ConnectionKind::Explicit => {
                self.memory.status.class3_open = self.memory.status.class3_open.saturating_add(1);
            }
            ConnectionEvent::Opened(c) => {
                self.memory
                    .status
                    .opened(c.slot, c.t_o_rpi_us, c.o_t_rpi_us)
            }
            ConnectionEvent::Closed(c, _) if c.kind == ConnectionKind::Explicit => {
                self.memory.status.class3_open = self.memory.status.class3_open.saturating_sub(1);
            }
            ConnectionEvent::Closed(c, _) => self.memory.status.closed(c.slot),
            _ => {}
        }
    }

    /// The input assembly changes with any parameter written (explicit, O->T) and while an
    /// axis moves.
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        if self.memory.take_written() {
            self.changes.mark(assemblies::INPUT);
        }
        Some(&mut self.changes)
    }

    fn poll(&mut self, now: Instant) -> Option<Instant> {
        let (changed, next) = self.axes.poll(now, &mut self.memory.store);
        if changed {
            self.changes.mark(assemblies::INPUT);
        }
        Some(next)
    }

    /// Either reset is a power cycle: parameters back to their power-up values (Program1
    /// reloads the I/O configuration); the counters and connection state stay, the stack
    /// closes every connection and reports it.
    fn reset(&mut self, _kind: u8) -> CipResult {
        let status = self.memory.status.clone();
        *self = ParkerIpa::new();
        self.memory.status = status;
        Ok(())
    }
}
