//! Example device: a 16-channel digital I/O block, written against the `enip-stack` device
//! API only (see `enip_stack::guide`). It runs unchanged on the host (`io-block-host`, one call to
//! `enip_host::run`) and on a board.
//!
//! - Assemblies: inputs 100 (2 bytes, channel 0 = bit 0), outputs 150 (2 bytes, with the
//!   run/idle header), configuration 151 (4 bytes: input filter in ms 0-100, safe-state mode
//!   0 = clear / 1 = hold, safe-state outputs), heartbeats 152 (input only) and 153 (listen
//!   only).
//! - The configuration check: a Forward_Open whose configuration is out of range is refused
//!   with 0x01 / [`BAD_CONFIGURATION`] and its additional word names the byte at fault.
//! - Vendor class 0x70 "Channel", one instance per channel: 1 debounce (USINT, ms, 0-100),
//!   2 edges counted (UDINT, read-only), 3 name (SHORT_STRING, up to 16); service 0x4B
//!   clears the edge counter.
//! - Wiring of the simulation: each input follows its output (a loop-back plug), except
//!   channel 15, a 1 Hz pulse from [`enip_stack::Device::poll`]. Inputs that change are marked, so
//!   change-of-state and application-triggered connections produce them at once.
//! - Safe state: when the last exclusive owner goes, or its data turns Idle, the outputs take
//!   the configured safe state.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod eds;

pub use eds::EDS;

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
use enip_stack::cip::{CipError, CipResult, General, Request};
use enip_stack::device::{AttributeRef, ConnectionEvent, InputChanges};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, AssemblyRole, Device, Duration, IdentityInfo, Instant};

/// Who the block is (vendor 0xFFFF: no ODVA vendor ID of its own).
pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 0xFFFF,
    device_type: 0x07, // general purpose discrete I/O
    product_code: 16,
    revision: (1, 1),
    serial_number: 0x0000_1616,
    product_name: "enip-rs 16-channel I/O block",
};

/// Input assembly: 16 input bits.
pub const INPUTS: u16 = 100;
/// Output assembly: 16 output bits (O->T, with the run/idle header).
pub const OUTPUTS: u16 = 150;
/// Configuration assembly: filter, safe-state mode, safe-state outputs.
pub const CONFIG: u16 = 151;
/// O->T point of input-only connections.
pub const INPUT_ONLY: u16 = 152;
/// O->T point of listen-only connections.
pub const LISTEN_ONLY: u16 = 153;
/// The vendor class of the channels.
pub const CHANNEL_CLASS: u16 = 0x70;
/// Vendor service of the channel class: clear the edge counter.
pub const CLEAR_EDGES: u8 = 0x4B;
/// Extended status of a refused configuration (0x0110: target not configured).
pub const BAD_CONFIGURATION: u16 = 0x0110;
/// Number of channels.
pub const CHANNELS: usize = 16;
/// The channel driven by the simulated pulse.
const PULSE_CHANNEL: usize = 15;
/// Half period of the pulse.
const PULSE_HALF_PERIOD: Duration = Duration::from_millis(500);

const ASSEMBLIES: [AssemblyInfo; 5] = [
    assembly(INPUTS, AssemblyRole::Input, 2, false),
    assembly(OUTPUTS, AssemblyRole::Output, 2, true),
    assembly(CONFIG, AssemblyRole::Config, 4, false),
    assembly(INPUT_ONLY, AssemblyRole::InputOnlyHeartbeat, 0, false),
    assembly(LISTEN_ONLY, AssemblyRole::ListenOnlyHeartbeat, 0, false),
];

const fn assembly(instance: u16, role: AssemblyRole, size: u16, header: bool) -> AssemblyInfo {
    AssemblyInfo {
        instance,
        role,
        size,
        run_idle_header: header,
    }
}

/// The channel class as the stack serves it.
pub const CHANNEL: ClassDef = ClassDef {
    id: CHANNEL_CLASS,
    name: "Channel",
    revision: 1,
    max_instance: CHANNELS as u32,
    attributes: &[
        AttributeDef::get_set(1, DataType::Usint, "Debounce"),
        AttributeDef::get(2, DataType::Udint, "Edges"),
        AttributeDef::get_set(3, DataType::ShortString { max: 16 }, "Name"),
    ],
    get_all: &[1, 2, 3],
    optional_attributes: &[],
};

/// The configuration assembly's contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Config {
    /// Input filter in ms (0-100).
    pub filter_ms: u8,
    /// True: hold the last outputs on connection loss; false: apply `safe_outputs`.
    pub hold: bool,
    /// Outputs applied on connection loss when not holding.
    pub safe_outputs: u16,
}

impl Config {
    /// Decodes and checks the 4 configuration bytes; `Err` names the byte at fault.
    pub fn parse(data: &[u8]) -> Result<Config, u16> {
        let [filter_ms, mode, lo, hi] = <[u8; 4]>::try_from(data).map_err(|_| 0u16)?;
        if filter_ms > 100 {
            return Err(0);
        }
        if mode > 1 {
            return Err(1);
        }
        Ok(Config {
            filter_ms,
            hold: mode == 1,
            safe_outputs: u16::from_le_bytes([lo, hi]),
        })
    }

    fn bytes(&self) -> [u8; 4] {
        let [lo, hi] = self.safe_outputs.to_le_bytes();
        [self.filter_ms, u8::from(self.hold), lo, hi]
    }
}

/// One channel's settings and counter.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Channel {
    debounce_ms: u8,
    edges: u32,
    name: [u8; 16],
    name_len: u8,
}

/// The I/O block.
#[derive(Debug, Clone, Default)]
pub struct IoBlock {
    outputs: u16,
    inputs: u16,
    pulse: bool,
    next_pulse: Option<Instant>,
    config: Config,
    channels: [Channel; CHANNELS],
    changes: InputChanges,
}

impl IoBlock {
    /// The block at power-up: outputs off, default configuration.
    pub fn new() -> Self {
        Self::default()
    }

    /// The current outputs.
    pub fn outputs(&self) -> u16 {
        self.outputs
    }

    /// The current configuration.
    pub fn config(&self) -> Config {
        self.config
    }

    /// Sets the outputs and recomputes the inputs they drive.
    fn set_outputs(&mut self, outputs: u16) {
        self.outputs = outputs;
        self.update_inputs();
    }

    /// Inputs = outputs looped back, channel 15 = the pulse; counts edges and marks changes.
    fn update_inputs(&mut self) {
        let pulse_bit = 1u16 << PULSE_CHANNEL;
        let mut inputs = self.outputs & !pulse_bit;
        if self.pulse {
            inputs |= pulse_bit;
        }
        let changed = inputs ^ self.inputs;
        if changed == 0 {
            return;
        }
        for (i, channel) in self.channels.iter_mut().enumerate() {
            if changed & (1 << i) != 0 {
                channel.edges = channel.edges.wrapping_add(1);
            }
        }
        self.inputs = inputs;
        self.changes.mark(INPUTS);
    }

    /// The outputs' safe state after a connection loss or Idle.
    fn safe_state(&mut self) {
        if !self.config.hold {
            self.set_outputs(self.config.safe_outputs);
        }
    }

    fn channel(&mut self, at: &AttributeRef<'_>) -> CipResult<&mut Channel> {
        let i = usize::try_from(at.instance).map_err(|_| General::ObjectDoesNotExist)?;
        self.channels
            .get_mut(i.wrapping_sub(1))
            .ok_or(CipError::new(General::ObjectDoesNotExist))
    }
}

impl Device for IoBlock {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let (inputs, outputs, config) = (
            self.inputs.to_le_bytes(),
            self.outputs.to_le_bytes(),
            self.config.bytes(),
        );
        let data: &[u8] = match instance {
            INPUTS => &inputs,
            OUTPUTS => &outputs,
            CONFIG => &config,
            _ => &[],
        };
        let n = data.len().min(out.len());
        if let (Some(dst), Some(src)) = (out.get_mut(..n), data.get(..n)) {
            dst.copy_from_slice(src);
        }
        Ok(n)
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            OUTPUTS => {
                let bytes = <[u8; 2]>::try_from(data).map_err(|_| General::NotEnoughData)?;
                self.set_outputs(u16::from_le_bytes(bytes));
            }
            // The one configuration check, for a Forward_Open's configuration data and an
            // explicit Set alike: the stack replies to a Set with 0x09 instead.
            CONFIG => {
                self.config = Config::parse(data).map_err(|byte| {
                    CipError::connection(BAD_CONFIGURATION).with_additional(BAD_CONFIGURATION, byte)
                })?;
            }
            // Heartbeat assemblies (size 0) never come here: no O->T data, not settable.
            _ => return Err(General::AttributeNotSettable.into()),
        }
        Ok(())
    }

    fn classes(&self) -> &[ClassDef] {
        &[CHANNEL]
    }

    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        let channel = self.channel(at)?;
        match at.attribute.id {
            1 => w.u8(channel.debounce_ms)?,
            2 => w.u32(channel.edges)?,
            _ => {
                let name = channel
                    .name
                    .get(..usize::from(channel.name_len))
                    .unwrap_or(&[]);
                w.u8(channel.name_len)?;
                w.bytes(name)?;
            }
        }
        Ok(())
    }

    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        let attribute = at.attribute.id;
        let channel = self.channel(at)?;
        match (attribute, value) {
            (1, [ms @ 0..=100]) => channel.debounce_ms = *ms,
            (1, _) => return Err(General::InvalidAttributeValue.into()),
            (_, [len, name @ ..]) => {
                // The stack checked the length against SHORT_STRING's 16 characters.
                let dst = channel
                    .name
                    .get_mut(..name.len())
                    .ok_or(General::InvalidAttributeValue)?;
                dst.copy_from_slice(name);
                channel.name_len = *len;
            }
            _ => return Err(General::NotEnoughData.into()),
        }
        Ok(())
    }

    fn handle_request(
        &mut self,
        _cx: &RequestContext,
        req: &Request<'_>,
        _reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        if req.service != CLEAR_EDGES || req.path.class != Some(CHANNEL_CLASS.into()) {
            return None;
        }
        let instance = req.path.instance.and_then(|i| usize::try_from(i).ok());
        let channel = instance.and_then(|i| self.channels.get_mut(i.wrapping_sub(1)));
        Some(match (channel, req.data) {
            (Some(c), []) => {
                c.edges = 0;
                Ok(())
            }
            (Some(_), _) => Err(General::TooMuchData.into()),
            // Class level: not a service of the class.
            (None, _) => Err(General::ServiceNotSupported.into()),
        })
    }

    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::OwnershipLost(_) | ConnectionEvent::RunIdle(false) => {
                self.safe_state()
            }
            _ => {}
        }
    }

    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changes)
    }

    /// The 1 Hz pulse on channel 15.
    fn poll(&mut self, now: Instant) -> Option<Instant> {
        let due = *self.next_pulse.get_or_insert(now);
        if now >= due {
            self.pulse = !self.pulse;
            self.update_inputs();
            self.next_pulse = Some(due.add(PULSE_HALF_PERIOD));
        }
        self.next_pulse
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use enip_stack::device::CloseReason;

    #[test]
    fn configuration_check_names_the_byte_at_fault() {
        assert_eq!(
            Config::parse(&[10, 1, 0x34, 0x12]),
            Ok(Config {
                filter_ms: 10,
                hold: true,
                safe_outputs: 0x1234
            })
        );
        assert_eq!(Config::parse(&[101, 0, 0, 0]), Err(0));
        assert_eq!(Config::parse(&[0, 2, 0, 0]), Err(1));
    }

    #[test]
    fn a_bad_configuration_set_is_invalid_and_changes_nothing() {
        let net = enip_stack::NetworkConfig::new_static(
            core::net::Ipv4Addr::new(198, 18, 0, 2),
            core::net::Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 2],
        );
        let mut adapter = enip_stack::Adapter::new(IoBlock::new(), net, 1);
        // Set_Attribute_Single, Assembly 151 attribute 3.
        let set = |adapter: &mut enip_stack::Adapter<IoBlock>, data: [u8; 4]| {
            let mut req = [0x10, 3, 0x20, 0x04, 0x24, 151, 0x30, 0x03, 0, 0, 0, 0];
            req[8..].copy_from_slice(&data);
            let mut reply = [0u8; 16];
            let n = adapter.execute(&req, Instant(0), &mut reply);
            (reply[2], n)
        };
        assert_eq!(
            set(&mut adapter, [200, 1, 0, 0]),
            (0x09, 4),
            "invalid value, no additional words"
        );
        assert_eq!(adapter.device().config(), Config::default());
        assert_eq!(set(&mut adapter, [10, 1, 0, 0]), (0x00, 4));
        assert_eq!(adapter.device().config().filter_ms, 10);
    }

    #[test]
    fn outputs_loop_back_and_take_the_safe_state() {
        let mut block = IoBlock::new();
        block.write_assembly(CONFIG, &[0, 0, 0x01, 0x00]).unwrap();
        block.write_assembly(OUTPUTS, &[0xF0, 0x00]).unwrap();
        let mut inputs = [0u8; 2];
        assert_eq!(block.read_assembly(INPUTS, &mut inputs), Ok(2));
        assert_eq!(inputs, [0xF0, 0x00]);
        assert_eq!(block.input_changes().map(|c| c.iter().count()), Some(1));
        block.connection_event(ConnectionEvent::OwnershipLost(CloseReason::Timeout));
        assert_eq!(block.outputs(), 0x0001, "the configured safe outputs");
    }

    #[test]
    fn the_pulse_toggles_channel_15_every_half_second() {
        let mut block = IoBlock::new();
        assert_eq!(block.poll(Instant(0)), Some(Instant(500_000)));
        assert_eq!(block.inputs & 0x8000, 0x8000);
        assert_eq!(block.poll(Instant(400_000)), Some(Instant(500_000)));
        assert_eq!(block.poll(Instant(500_000)), Some(Instant(1_000_000)));
        assert_eq!(block.inputs & 0x8000, 0);
        assert_eq!(block.channels[PULSE_CHANNEL].edges, 2);
    }
}
