//! The Ametek 7500 UHS PLS EtherNet/IP module, as its network programming manual
//! (7500.MOR 4/05.Z185) describes it, with a simulated resolver and limit switch behind it.
//!
//! - [`identity`]: the Identity object (values are this project's, AM-ID-2).
//! - [`assemblies`]: input 100 (17 words), output 150 (7 words), configuration 1 (empty).
//! - [`classes`]: class 0xC0 (status, attributes 1-3) and 0xC1 (configuration, 1-38).
//! - [`params`]: the stored configuration words; [`validate`]: the manual's rules.
//! - [`device`]: the resolver, offsets, inputs and outputs, advanced by [`Device::poll`].
//! - [`storage`]: the program saved by program control (attribute 37).
//! - [`leds`]: the MS and NS LEDs of Figure 1, logged at each transition.
//! - [`board`]: the resolver speed a board without a command line builds in.
//!
//! A Set of 0xC1 is validated whole; a broken rule leaves everything as it was, answers
//! 0x09 (codes 1, 2), 0x10 (code 3), 0x19 (code 4) or 0x0C (the encoder object on this
//! resolver version), and latches (code, attribute, word) in input words 15-17 until a
//! rising edge of the Acknowledge bit. Idle O->T data, and the loss of the exclusive owner,
//! count as all-zero output data: Run Enable 0, no forces, soft inputs low.

pub mod assemblies;
pub mod board;
pub mod classes;
pub mod device;
pub mod eds;
pub mod identity;
pub mod leds;
pub mod params;
pub mod storage;
pub mod validate;

#[cfg(test)]
mod tests;

use enip_stack::cip::context::RequestContext;
use enip_stack::cip::object::ClassDef;
use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::{AttributeRef, ConnectionEvent, InputChanges};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyInfo, Device, Duration, IdentityInfo, Instant};

use assemblies::{INPUT, INPUT_BYTES, OUTPUT, OUTPUT_BYTES};
use device::{Engine, OutputData};
use params::{attr, decode_words, Config, CONTROL_WORDS, GROUPS, INPUTS, OFFSET_WORDS};
use storage::{Nvram, Program, IMAGE_BYTES};
use validate::Violation;

/// Program control codes (§2.9).
pub mod control {
    /// "No offset": clears every offset (\[R\] 8).
    pub const NO_OFFSET: u16 = 1;
    /// Save the current settings to NVRAM.
    pub const SAVE: u16 = 2;
    /// Restore the settings from NVRAM.
    pub const RESTORE: u16 = 3;
}

/// Simulation tick: outputs are recomputed at least this often (digest section 7).
const TICK: Duration = Duration::from_millis(1);
/// Identity status bit 2: configured (a program was written or loaded).
const STATUS_CONFIGURED: u16 = 1 << 2;
/// Identity status bit 10: major recoverable fault (the resolver fault; MS flashes red).
const STATUS_MAJOR_RECOVERABLE: u16 = 1 << 10;

/// The 7500 PLS: configuration, NVRAM, the simulated limit switch and the error words.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AmetekPls {
    cfg: Config,
    engine: Engine,
    nvram: Nvram,
    /// Input words 15-17: error code, attribute, word (0 = none).
    error: [u16; 3],
    /// The last accepted offset object (attribute 36) and program control (37).
    last_offset: [u16; OFFSET_WORDS],
    last_control: [u16; CONTROL_WORDS],
    /// The last output data (O->T or Set of 150), as bytes for a Get of 150.
    output_bytes: [u8; OUTPUT_BYTES],
    /// A program was written or loaded since power-up.
    configured: bool,
    /// The last input data produced, to tell the stack when it changed.
    last_input: [u8; INPUT_BYTES],
    changes: InputChanges,
    leds: leds::Leds,
}

impl AmetekPls {
    /// A module at power-up with an empty NVRAM (every setting at its default).
    pub fn new() -> Self {
        Self::with_storage(Nvram::new())
    }
}

impl Default for AmetekPls {
    fn default() -> Self {
        Self::new()
    }
}

impl AmetekPls {
    /// A module at power-up that loads its program from `nvram` if one was saved.
    pub fn with_storage(nvram: Nvram) -> Self {
        let mut pls = AmetekPls {
            cfg: Config::new(),
            engine: Engine::new(),
            nvram,
            error: [0; 3],
            last_offset: [0; OFFSET_WORDS],
            last_control: [0; CONTROL_WORDS],
            output_bytes: [0; OUTPUT_BYTES],
            configured: false,
            last_input: [0; INPUT_BYTES],
            changes: InputChanges::new(),
            leds: leds::Leds::new(),
        };
        pls.engine.set_resolver(board::BUILD_RPM, false);
        pls.power_up();
        pls
    }

    /// The configuration as stored.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// The simulated limit switch.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The NVRAM.
    pub fn storage(&self) -> &Nvram {
        &self.nvram
    }

    /// The MS and NS LEDs.
    pub fn leds(&self) -> &leds::Leds {
        &self.leds
    }

    /// Input words 15-17: (error code, attribute, word).
    pub fn error(&self) -> [u16; 3] {
        self.error
    }

    /// Sets the simulated resolver's speed (RPM, forward) and fault flag (a board option).
    pub fn set_resolver(&mut self, rpm: u16, fault: bool) {
        self.engine.set_resolver(rpm, fault);
    }

    /// Drives hardware inputs 1-8 (bit 0 = input 1; a board option).
    pub fn set_hardware_inputs(&mut self, levels: u8) {
        self.engine.set_hardware_inputs(&self.cfg, levels);
    }

    /// Power-up: everything volatile restarts, the program comes from NVRAM if saved.
    fn power_up(&mut self) {
        let (rpm, fault) = (self.engine.rpm(), self.engine.fault());
        self.cfg = Config::new();
        self.engine = Engine::new();
        self.engine.set_resolver(rpm, fault);
        self.error = [0; 3];
        self.last_offset = [0; OFFSET_WORDS];
        self.last_control = [0; CONTROL_WORDS];
        self.output_bytes = [0; OUTPUT_BYTES];
        self.configured = self.restore().is_ok();
        self.engine.compute(&self.cfg);
    }

    /// The NVRAM image of the current program: attributes 1-35 and 38, group offsets.
    fn image(&self) -> [u8; IMAGE_BYTES] {
        let mut image = [0; IMAGE_BYTES];
        let words = self
            .cfg
            .all_words()
            .chain(self.engine.group_offset.iter().copied());
        for (chunk, w) in image.chunks_exact_mut(2).zip(words) {
            chunk.copy_from_slice(&w.to_le_bytes());
        }
        image
    }

    /// Loads the program saved in NVRAM; `Err` if none was saved.
    fn restore(&mut self) -> Result<(), ()> {
        let Program(image) = *self.nvram.load().ok_or(())?;
        let mut words = image
            .chunks_exact(2)
            .filter_map(|b| <[u8; 2]>::try_from(b).ok())
            .map(u16::from_le_bytes);
        let mut cfg = Config::new();
        for (slot, w) in cfg.all_words_mut().zip(&mut words) {
            *slot = w;
        }
        let mut offsets = [0; GROUPS];
        for (slot, w) in offsets.iter_mut().zip(&mut words) {
            *slot = w;
        }
        self.cfg = cfg;
        self.engine.set_group_offsets(&self.cfg, offsets);
        Ok(())
    }

    /// Reports a broken rule of attribute `a` in input words 15-17 and as a CIP status.
    fn reject(&mut self, a: u16, (code, word): Violation) -> CipError {
        self.error = [code, a, word];
        self.mark_changed();
        warn!(
            "PLS: Set of 0xC1/{} refused: code {} word {}",
            a, code, word
        );
        match (a, code) {
            (attr::ENCODER, _) => CipError::new(General::ObjectStateConflict),
            (_, validate::RESOLVER) => CipError::new(General::DeviceStateConflict),
            // Error code 4: store operation failure ([R] AM-EX-5).
            (_, validate::MEMORY) => CipError::new(General::StoreOperationFailure),
            _ => CipError::new(General::InvalidAttributeValue),
        }
    }

    /// A Set of class 0xC1 attribute `a` with `bytes` (exactly its size).
    fn set_config(&mut self, a: u16, bytes: &[u8]) -> CipResult {
        let mut buf = [0u16; params::INPUT_WORDS];
        let n = params::attribute_words(a);
        let words = buf.get_mut(..n).ok_or(General::AttributeNotSupported)?;
        decode_words(bytes, words);
        let words = &*words;
        if let Err(v) = validate::check(&self.cfg, a, words, self.engine.fault()) {
            return Err(self.reject(a, v));
        }
        match a {
            attr::OFFSET => {
                self.engine.apply_offsets(&self.cfg, words);
                self.last_offset.copy_from_slice(words);
            }
            attr::CONTROL => {
                self.program_control(words.first().copied().unwrap_or(0))
                    .map_err(|v| self.reject(a, v))?;
                self.last_control.copy_from_slice(words);
            }
            _ => {
                let old: [_; INPUTS] = core::array::from_fn(|i| self.cfg.input(i));
                let slot = self
                    .cfg
                    .words_mut(a)
                    .ok_or(General::AttributeNotSupported)?;
                slot.copy_from_slice(words);
                self.configured = true;
                self.engine.inputs_changed(&self.cfg, &old);
            }
        }
        self.engine.rescale(&self.cfg);
        self.engine.compute(&self.cfg);
        self.mark_changed();
        Ok(())
    }

    /// Program control (§2.9), already validated.
    fn program_control(&mut self, code: u16) -> Result<(), Violation> {
        match code {
            control::NO_OFFSET => self.engine.clear_offsets(&self.cfg),
            control::SAVE => {
                let image = self.image();
                self.nvram
                    .save(Program(image))
                    .map_err(|_| (validate::MEMORY, 1))?;
                info!("PLS: program saved to NVRAM");
            }
            _ => {
                self.restore().map_err(|_| (validate::MEMORY, 1))?;
                self.configured = true;
                info!("PLS: program restored from NVRAM");
            }
        }
        Ok(())
    }

    /// New output data: edges of word 1 and the soft inputs; Acknowledge clears the error.
    fn consume(&mut self, data: &[u8]) {
        if let Ok(bytes) = <[u8; OUTPUT_BYTES]>::try_from(data) {
            self.output_bytes = bytes;
        }
        if self.engine.consume(&self.cfg, OutputData::decode(data)) {
            self.error = [0; 3];
        }
        self.mark_changed();
    }

    /// The input data (§2.1, 17 words).
    fn input_data(&self) -> [u8; INPUT_BYTES] {
        let e = &self.engine;
        let out = e.outputs();
        let mut words = [0u16; INPUT_BYTES / 2];
        for (g, w) in words.iter_mut().take(GROUPS).enumerate() {
            *w = e.position(g);
        }
        words[8] = e.rpm();
        words[9] = u16::from(e.fault());
        words[10] = out as u16;
        words[11] = (out >> 16) as u16;
        words[12] = e.hardware_inputs();
        words[13] = e.warnings();
        words[14..17].copy_from_slice(&self.error);
        let mut bytes = [0u8; INPUT_BYTES];
        for (chunk, w) in bytes.chunks_exact_mut(2).zip(words) {
            chunk.copy_from_slice(&w.to_le_bytes());
        }
        bytes
    }

    /// Marks the input assembly changed if its data did (application-triggered production).
    fn mark_changed(&mut self) {
        self.leds.module(self.configured, self.engine.fault());
        let now = self.input_data();
        if now != self.last_input {
            self.last_input = now;
            self.changes.mark(INPUT);
        }
    }
}

impl Device for AmetekPls {
    fn identity(&self) -> &IdentityInfo {
        &identity::IDENTITY
    }

    fn status_bits(&self) -> u16 {
        let configured = if self.configured {
            STATUS_CONFIGURED
        } else {
            0
        };
        let fault = if self.engine.fault() {
            STATUS_MAJOR_RECOVERABLE
        } else {
            0
        };
        configured | fault
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &assemblies::INFOS
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let data: &[u8] = match instance {
            INPUT => &self.input_data(),
            OUTPUT => &self.output_bytes,
            _ => &[],
        };
        let n = data.len().min(out.len());
        for (o, b) in out.iter_mut().zip(data) {
            *o = *b;
        }
        Ok(n)
    }

    /// Output data (O->T in Run, or a Set without an owner, \[R\] AM-IO-7); the empty
    /// configuration assembly accepts its 0 bytes.
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            OUTPUT => self.consume(data),
            assemblies::CONFIG => {}
            _ => return Err(General::AttributeNotSettable.into()),
        }
        Ok(())
    }

    fn classes(&self) -> &[ClassDef] {
        &classes::CLASSES
    }

    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        w: &mut Writer<'_>,
    ) -> CipResult {
        let a = at.attribute.id;
        if at.class.id == classes::STATUS {
            match a {
                classes::SYSTEM_INFORMATION => {
                    let (major, minor) = identity::SOFTWARE_VERSION;
                    w.u16(major.into())?;
                    w.u16(minor.into())?;
                }
                classes::INPUT_STATUS => {
                    for i in 0..INPUTS {
                        for v in self.engine.input_status(i) {
                            w.u16(v)?;
                        }
                    }
                }
                _ => {
                    for v in self.engine.group_offset.iter() {
                        w.u16(*v)?;
                    }
                    for v in self.engine.input_offset.iter() {
                        w.u16(*v)?;
                    }
                }
            }
            return Ok(());
        }
        let words: &[u16] = match a {
            attr::OFFSET => &self.last_offset,
            attr::CONTROL => &self.last_control,
            _ => self.cfg.words(a).ok_or(General::AttributeNotSupported)?,
        };
        for v in words {
            w.u16(*v)?;
        }
        Ok(())
    }

    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        at: &AttributeRef<'_>,
        value: &[u8],
    ) -> CipResult {
        if at.class.id != classes::CONFIG {
            return Err(General::AttributeNotSettable.into());
        }
        self.set_config(at.attribute.id, value)
    }

    /// 0 restarts from NVRAM (a power cycle); 1 also erases NVRAM (factory defaults).
    fn reset(&mut self, kind: u8) -> CipResult {
        if kind == 1 {
            self.nvram
                .clear()
                .map_err(|_| General::StoreOperationFailure)?;
        }
        self.power_up();
        self.leds.reset();
        Ok(())
    }

    /// Idle data and the loss of the owner act as all-zero output data (\[R\] AM-IO-6).
    fn connection_event(&mut self, event: ConnectionEvent) {
        self.leds.connection_event(&event);
        match event {
            ConnectionEvent::RunIdle(false) | ConnectionEvent::OwnershipLost(_) => {
                info!("PLS: output data released (idle or owner gone): outputs disabled");
                self.consume(&[0; OUTPUT_BYTES]);
            }
            _ => {}
        }
    }

    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changes)
    }

    fn poll(&mut self, now: Instant) -> Option<Instant> {
        self.engine.tick(&self.cfg, now);
        self.mark_changed();
        Some(now.add(TICK))
    }
}
