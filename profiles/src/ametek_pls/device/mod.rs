//! The simulated PLS: a resolver, the group positions and offsets, the input functions and
//! the limit-switch outputs, recomputed on every tick (§2.1, 2.3-2.8, 2.12, 2.13).
//!
//! The resolver is a 32-bit fraction of a revolution advanced from the time of each tick at
//! a settable RPM (0, stationary, by default; forward rotation only). Group position =
//! (angle x SF / 2^32 + group offset) mod SF. Outputs follow the precedence of the digest
//! (section 6): Run Enable 0, group force, individual force, add-on test, minimum speed
//! disable and output-enable inputs, setpoint pattern; outputs in no group are off.

// Position arithmetic: u16 positions, offsets and speeds are widened to 32, 64 or 128 bits
// before every sum or product, every divisor is a scale factor of at least 1, and the
// interpolation guards its span; nothing here can overflow or divide by zero.
#![allow(clippy::arithmetic_side_effects)]

use enip_stack::{Duration, Instant};

use super::params::{setpoint, Config, GROUPS, HIGH_SPEED, INPUTS, INPUT_STRIDE, OUTPUTS};
use super::validate::input_type as t;

mod addon;
mod geometry;
mod inputs;
mod output_data;
mod setpoints;

use addon::Addon;
pub use geometry::window;
use geometry::{advance, bits, crossed, shift};
use inputs::{Effect, InputState};
pub use output_data::{OutputData, ACKNOWLEDGE, ADDON_ENABLE, RUN_ENABLE};

/// The limit switch's state.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Engine {
    angle: u32,
    rem: u128,
    rpm: u16,
    fault: bool,
    last: Option<Instant>,
    /// Group offsets (0xC0/3 words 1-8), 0..SF-1.
    pub group_offset: [u16; GROUPS],
    /// The group offsets without the resets to preset of the whole group: the frame the
    /// average reset to preset records its positions in.
    base_offset: [u16; GROUPS],
    /// Input offsets (0xC0/3 words 9-24).
    pub input_offset: [u16; INPUTS],
    /// Outputs reset by a reset-to-preset input of a subset: their own offset.
    output_offset: [Option<u16>; OUTPUTS],
    /// Remote setpoint tune: counts each output's setpoints are advanced by.
    tune: [i32; OUTPUTS],
    positions: [u16; GROUPS],
    travel: [u32; GROUPS],
    timed_until: [Option<Instant>; OUTPUTS],
    inputs: [InputState; INPUTS],
    warnings: u16,
    addon: Addon,
    outputs: u32,
    now: Instant,
    /// The last output data.
    data: OutputData,
    /// Input levels, bit 0 = input 1 (hardware 1-8, soft 9-16).
    levels: u16,
}

impl Default for Engine {
    fn default() -> Self {
        Self::new()
    }
}

impl Engine {
    /// A stationary resolver at angle 0, no offsets, outputs off.
    pub const fn new() -> Self {
        Engine {
            angle: 0,
            rem: 0,
            rpm: 0,
            fault: false,
            last: None,
            group_offset: [0; GROUPS],
            base_offset: [0; GROUPS],
            input_offset: [0; INPUTS],
            output_offset: [None; OUTPUTS],
            tune: [0; OUTPUTS],
            positions: [0; GROUPS],
            travel: [0; GROUPS],
            timed_until: [None; OUTPUTS],
            inputs: [InputState::IDLE; INPUTS],
            warnings: 0,
            addon: Addon::IDLE,
            outputs: 0,
            now: Instant(0),
            data: OutputData {
                bits: 0,
                force: [0; 4],
                group_force: 0,
                soft: 0,
            },
            levels: 0,
        }
    }

    /// Sets the resolver speed (RPM, forward) and its fault flag (input word 10).
    pub fn set_resolver(&mut self, rpm: u16, fault: bool) {
        self.rpm = rpm;
        self.fault = fault;
    }

    /// The resolver speed, RPM (input word 9).
    pub fn rpm(&self) -> u16 {
        if self.fault {
            0
        } else {
            self.rpm
        }
    }

    /// True while the resolver reports a fault (input word 10).
    pub fn fault(&self) -> bool {
        self.fault
    }

    /// The time of the last tick.
    pub fn now(&self) -> Instant {
        self.now
    }

    /// The position of group `g` (input words 1-8).
    pub fn position(&self, g: usize) -> u16 {
        self.positions.get(g).copied().unwrap_or(0)
    }

    /// Output status, bit 0 = output 1 ... bit 31 = output 32 (input words 11-12).
    pub fn outputs(&self) -> u32 {
        self.outputs
    }

    /// Input warning map (input word 14).
    pub fn warnings(&self) -> u16 {
        self.warnings
    }

    /// True while the add-on test runs.
    pub fn addon_active(&self) -> bool {
        self.addon.active()
    }

    /// Input `i`'s 0xC0/2 words: leading position, trailing position, transition status.
    pub fn input_status(&self, i: usize) -> [u16; 3] {
        self.inputs.get(i).map_or([0; 3], InputState::status)
    }

    /// The resolver's position in group `g`'s counts, without offset.
    fn raw(&self, cfg: &Config, g: usize) -> u16 {
        ((u64::from(self.angle) * u64::from(cfg.scale(g))) >> 32) as u16
    }

    /// Recomputes every group position from the angle and the offsets.
    fn refresh_positions(&mut self, cfg: &Config) {
        let raws: [u16; GROUPS] = core::array::from_fn(|g| self.raw(cfg, g));
        let groups = self.positions.iter_mut().zip(&self.group_offset).zip(raws);
        for (g, ((position, &offset), raw)) in groups.enumerate() {
            let sf = u32::from(cfg.scale(g));
            *position = ((u32::from(raw) + u32::from(offset) % sf) % sf) as u16;
        }
    }

    /// Applies the offset object (§2.8), already validated: 01 home, 10 absolute,
    /// 11 relative; positions wrap modulo SF.
    pub fn apply_offsets(&mut self, cfg: &Config, words: &[u16]) {
        let mask = words.first().copied().unwrap_or(0);
        for g in 0..GROUPS {
            let value = i32::from(words.get(g + 1).copied().unwrap_or(0) as i16);
            let sf = i32::from(cfg.scale(g));
            let raw = i32::from(self.raw(cfg, g));
            let (Some(slot), Some(base)) =
                (self.group_offset.get_mut(g), self.base_offset.get_mut(g))
            else {
                continue;
            };
            let (offset, frame) = match (mask >> (2 * g)) & 3 {
                1 => (value - raw, value - raw),
                2 => (value, value),
                3 => (i32::from(*slot) + value, i32::from(*base) + value),
                _ => continue,
            };
            *slot = offset.rem_euclid(sf) as u16;
            *base = frame.rem_euclid(sf) as u16;
        }
        self.refresh_positions(cfg);
    }

    /// Program control code 1: no offset (every group, input and output offset cleared,
    /// setpoint tuning undone).
    pub fn clear_offsets(&mut self, cfg: &Config) {
        self.group_offset = [0; GROUPS];
        self.base_offset = [0; GROUPS];
        self.input_offset = [0; INPUTS];
        self.output_offset = [None; OUTPUTS];
        self.tune = [0; OUTPUTS];
        self.refresh_positions(cfg);
    }

    /// Restores group offsets saved with the program.
    pub fn set_group_offsets(&mut self, cfg: &Config, offsets: [u16; GROUPS]) {
        self.group_offset = offsets;
        self.base_offset = offsets;
        self.rescale(cfg);
    }

    /// Brings the offsets inside 0..SF-1 after a change of the configuration.
    pub fn rescale(&mut self, cfg: &Config) {
        let groups = self
            .group_offset
            .iter_mut()
            .zip(self.base_offset.iter_mut());
        for (g, (slot, base)) in groups.enumerate() {
            *slot %= cfg.scale(g);
            *base %= cfg.scale(g);
        }
        self.refresh_positions(cfg);
    }

    /// Attribute 34 was written (`old`: the inputs before): an input whose words changed
    /// starts its function afresh (capture registers kept), and one that is no longer a
    /// reset to preset input reports input offset 0 (§2.13).
    pub fn inputs_changed(&mut self, cfg: &Config, old: &[[u16; INPUT_STRIDE]; INPUTS]) {
        let inputs = self.inputs.iter_mut().zip(self.input_offset.iter_mut());
        for (i, ((st, offset), before)) in inputs.zip(old).enumerate() {
            let now = cfg.input(i);
            if now == *before {
                continue;
            }
            st.restart();
            if !inputs::is_preset(now[3]) {
                *offset = 0;
            }
        }
    }

    /// Starts the add-on test (rising edge of output word 1 bit 1) with attribute 35.
    pub fn start_addon(&mut self, cfg: &Config) {
        self.addon = Addon::start(cfg, self.now, self.positions);
    }

    /// The enable bit went low: a test without a time ends; a timed one runs on (\[R\]).
    pub fn release_addon(&mut self) {
        self.addon.release();
    }

    /// Inputs 1-16 are now at `levels` (bit 0 = input 1): edges trigger the functions of
    /// attribute 34 (the leading edge is the rising one of an active-high input, the
    /// falling one of an active-low input) and the capture registers.
    fn set_inputs(&mut self, cfg: &Config, levels: u16) {
        let changed = levels ^ self.levels;
        self.levels = levels;
        for i in (0..INPUTS).filter(|i| changed & (1 << i) != 0) {
            let leading = inputs::active(cfg, self.levels, i);
            let pos = cfg.group_of_input(i).map_or(0, |g| self.position(g));
            let [bits, ..] = cfg.input(i);
            let Some(st) = self.inputs.get_mut(i) else {
                continue;
            };
            st.edge(leading, pos, (bits >> 1) & 3);
            if leading {
                self.trigger(cfg, i);
            }
        }
        self.compute(cfg);
    }

    /// The leading edge of input `i`: its function acts.
    fn trigger(&mut self, cfg: &Config, i: usize) {
        let [_, _, _, kind, ..] = cfg.input(i);
        let Some(g) = cfg.group_of_input(i) else {
            return;
        };
        let sf = i32::from(cfg.scale(g));
        let pos = self.position(g);
        let raw = i32::from(self.raw(cfg, g));
        let outputs = inputs::input_outputs(cfg, i, kind);
        let group = inputs::group_outputs(cfg, g);
        // A reset to preset of every output of the group resets the group (§2.6: only a
        // subset mask keeps the group position).
        let whole = kind >= t::GROUP || outputs == group;
        // The average records positions in the group's frame before its own resets.
        let base = i32::from(self.base_offset.get(g).copied().unwrap_or(0));
        let sample = if whole {
            (raw + base).rem_euclid(sf) as u16
        } else {
            pos
        };
        let effect = match self.inputs.get_mut(i) {
            Some(st) => st.trigger(cfg, i, pos, sample),
            None => Effect::None,
        };
        match effect {
            Effect::SetpointTune(counts) => {
                for o in bits(outputs) {
                    if let Some(tune) = self.tune.get_mut(o) {
                        *tune = (*tune + i32::from(counts)).rem_euclid(sf);
                    }
                }
            }
            Effect::OffsetTune(counts) => {
                let slots = self.group_offset.get_mut(g).into_iter();
                for slot in slots.chain(self.base_offset.get_mut(g)) {
                    let offset = i32::from(*slot) + i32::from(counts);
                    *slot = offset.rem_euclid(sf) as u16;
                }
            }
            Effect::Preset(value) => {
                let offset = (i32::from(value) - raw).rem_euclid(sf) as u16;
                if let Some(slot) = self.input_offset.get_mut(i) {
                    *slot = offset;
                }
                if whole {
                    if let Some(slot) = self.group_offset.get_mut(g) {
                        *slot = offset;
                    }
                }
                for o in bits(if whole { group } else { outputs }) {
                    if let Some(slot) = self.output_offset.get_mut(o) {
                        *slot = (!whole).then_some(offset);
                    }
                }
            }
            Effect::None => {}
        }
        self.refresh_positions(cfg);
    }

    /// Advances the resolver and the add-on test to `now` and recomputes everything.
    pub fn tick(&mut self, cfg: &Config, now: Instant) {
        let dt = self
            .last
            .map_or(0, |l| now.as_micros().saturating_sub(l.as_micros()));
        self.last = Some(now);
        self.now = now;
        let before: [u16; GROUPS] = core::array::from_fn(|g| self.raw(cfg, g));
        let (step, rem) = advance(self.rpm(), dt, self.rem);
        self.rem = rem;
        self.angle = self.angle.wrapping_add(step as u32);
        for (g, b) in before.iter().enumerate() {
            let sf = u32::from(cfg.scale(g));
            let after = u32::from(self.raw(cfg, g));
            let full = u32::try_from(step >> 32)
                .unwrap_or(u32::MAX)
                .saturating_mul(sf);
            if let Some(travel) = self.travel.get_mut(g) {
                *travel = ((after + sf - u32::from(*b)) % sf).saturating_add(full);
            }
        }
        self.refresh_positions(cfg);
        self.addon.advance(dt, now);
        self.revolution_events(cfg);
        self.time_based(cfg, now);
        self.compute(cfg);
    }

    /// Crossings during the last tick, input by input; an output enable window that ended
    /// without its input sets the input's warning (input word 14), one with it clears it.
    fn revolution_events(&mut self, cfg: &Config) {
        for i in 0..INPUTS {
            let Some(g) = cfg.group_of_input(i) else {
                continue;
            };
            let travel = self.travel.get(g).copied().unwrap_or(0);
            let (pos, raw, sf) = (self.position(g), self.raw(cfg, g), cfg.scale(g));
            let Some(st) = self.inputs.get_mut(i) else {
                continue;
            };
            match st.revolution(cfg, i, (pos, raw), travel, sf) {
                Some(true) => self.warnings &= !(1 << i),
                Some(false) => self.warnings |= 1 << i,
                None => {}
            }
        }
    }

    /// Time-based setpoints: on when the resolver crosses the on position, for the time.
    fn time_based(&mut self, cfg: &Config, now: Instant) {
        for o in 0..OUTPUTS {
            let prog = cfg.program(o);
            let Some(g) = cfg.group_of_output(o) else {
                continue;
            };
            if prog.count == 0 || prog.kind != setpoint::TIME_BASED {
                if let Some(until) = self.timed_until.get_mut(o) {
                    *until = None;
                }
                continue;
            }
            let (pos, sf) = (self.output_position(cfg, o, g), cfg.scale(g));
            let tune = self.tune.get(o).copied().unwrap_or(0);
            let on = shift(prog.params[0], tune, sf);
            let travel = self.travel.get(g).copied().unwrap_or(0);
            if crossed(pos, travel, on, sf) {
                let ms = Duration::from_millis(prog.params[1].into());
                if let Some(until) = self.timed_until.get_mut(o) {
                    *until = Some(now.add(ms));
                }
            }
        }
    }

    /// Output `o`'s position: its group's, or its own after a reset to preset of a subset.
    fn output_position(&self, cfg: &Config, o: usize, g: usize) -> u16 {
        match self.output_offset.get(o).copied().flatten() {
            Some(offset) => {
                let sf = u32::from(cfg.scale(g));
                ((u32::from(self.raw(cfg, g)) + u32::from(offset)) % sf) as u16
            }
            None => self.position(g),
        }
    }

    /// Output `o`'s setpoint pattern at position `pos` and speed `rpm` (§2.4, 2.5).
    fn pattern(&self, cfg: &Config, o: usize, pos: u16, sf: u16, rpm: u16) -> bool {
        let tune = self.tune.get(o).copied().unwrap_or(0);
        let until = self.timed_until.get(o).copied().flatten();
        let timed = until.is_some_and(|u| self.now.as_micros() < u.as_micros());
        setpoints::pattern(cfg, o, pos, sf, rpm, tune, timed)
    }

    /// Recomputes the output status from the configuration, the inputs and the output data.
    pub fn compute(&mut self, cfg: &Config) {
        let data = self.data;
        let rpm = self.rpm();
        let gates = inputs::gates(cfg, &self.inputs, self.levels);
        let mut out = 0u32;
        for (o, &by_input) in gates.force.iter().enumerate() {
            if data.bits & RUN_ENABLE == 0 {
                break;
            }
            let Some(g) = cfg.group_of_output(o) else {
                continue;
            };
            let sf = cfg.scale(g);
            let group = match data.group_force_of(g) {
                0 => gates.group_force.get(g).copied().unwrap_or(0),
                c => c,
            };
            let single = match data.force_of(o) {
                0 => by_input,
                c => c,
            };
            let on = match (group, single) {
                (1, _) => true,
                (2, _) => false,
                (_, 1) => true,
                (_, 2) => false,
                _ => match self.addon.position(o, g, sf) {
                    Some(pos) => self.pattern(cfg, o, pos, sf, self.addon.rpm()),
                    None => {
                        let (min, mask) = (cfg.group_word(g, 4), cfg.group_word(g, 5));
                        let slow = min != 0 && rpm < min && o < HIGH_SPEED && mask & (1 << o) != 0;
                        let pos = self.output_position(cfg, o, g);
                        !slow && gates.gated & (1 << o) == 0 && self.pattern(cfg, o, pos, sf, rpm)
                    }
                },
            };
            if on {
                out |= 1 << o;
            }
        }
        self.outputs = out;
    }

    /// New output data (O->T in Run, or a Set of the output assembly; all zero on Idle and
    /// when the owner goes): acts on the edges of word 1 and the soft inputs. Returns true
    /// on a rising edge of Acknowledge.
    pub fn consume(&mut self, cfg: &Config, data: OutputData) -> bool {
        let rising = data.bits & !self.data.bits;
        let falling = self.data.bits & !data.bits;
        self.data = data;
        if rising & ADDON_ENABLE != 0 {
            self.start_addon(cfg);
        }
        if falling & ADDON_ENABLE != 0 {
            self.release_addon();
        }
        let levels = (self.levels & 0x00FF) | (data.soft & 0x00FF) << 8;
        self.set_inputs(cfg, levels);
        rising & ACKNOWLEDGE != 0
    }

    /// Drives hardware inputs 1-8 (a board option; all 0 otherwise).
    pub fn set_hardware_inputs(&mut self, cfg: &Config, levels: u8) {
        let levels = (self.levels & 0xFF00) | u16::from(levels);
        self.set_inputs(cfg, levels);
    }

    /// Input word 13: the 8 hardware inputs.
    pub fn hardware_inputs(&self) -> u16 {
        self.levels & 0x00FF
    }
}
