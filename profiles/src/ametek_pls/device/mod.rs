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

use super::params::{setpoint, Config, GROUPS, HIGH_SPEED, INPUTS, OUTPUTS};
use super::validate::input_type as t;

/// Microseconds per minute: RPM to revolutions per microsecond.
const US_PER_MIN: u128 = 60_000_000;

/// Output data (O->T, §2.1 "Output Data Transfer"), words 1-7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OutputData {
    /// Word 1: bit 0 Run Enable, bit 1 Add-On Test Enable, bit 2 Acknowledge.
    pub bits: u16,
    /// Words 2-5: force masks of outputs 1-8, 9-16, 17-24, 25-32 (2 bits each).
    pub force: [u16; 4],
    /// Word 6: force mask of groups 1-8.
    pub group_force: u16,
    /// Word 7: soft inputs 9-16 (bit 0 = input 9).
    pub soft: u16,
}

/// Word 1 bit 0: Run Enable (level).
pub const RUN_ENABLE: u16 = 1 << 0;
/// Word 1 bit 1: Add-On Test Enable (0->1 starts the test).
pub const ADDON_ENABLE: u16 = 1 << 1;
/// Word 1 bit 2: Acknowledge (0->1 clears the error words).
pub const ACKNOWLEDGE: u16 = 1 << 2;

impl OutputData {
    /// Decodes the 14 bytes of the output assembly.
    pub fn decode(data: &[u8]) -> Self {
        let w = |i: usize| {
            data.get(2 * i..2 * i + 2)
                .and_then(|b| <[u8; 2]>::try_from(b).ok())
                .map_or(0, u16::from_le_bytes)
        };
        OutputData {
            bits: w(0),
            force: [w(1), w(2), w(3), w(4)],
            group_force: w(5),
            soft: w(6),
        }
    }

    /// The force code (0 unforce, 1 on, 2 off; 3 reserved = unforce) of output `o`.
    fn force_of(&self, o: usize) -> u16 {
        let word = self.force.get(o / 8).copied().unwrap_or(0);
        code((word >> (2 * (o % 8))) & 3)
    }

    /// The force code of group `g`.
    fn group_force_of(&self, g: usize) -> u16 {
        code((self.group_force >> (2 * (g % 8))) & 3)
    }
}

/// A 2-bit force code, reserved (3) read as unforce (\[R\]).
fn code(c: u16) -> u16 {
    if c == 3 {
        0
    } else {
        c
    }
}

/// A one-revolution window started by an input (single shot, advanced enable).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Shot {
    /// Not started: the outputs operate normally.
    #[default]
    Idle,
    /// Running: counts travelled since it started.
    Running(u32),
    /// A revolution passed without a new input: the outputs are off.
    Expired,
}

/// The run-time state of one input.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct InputState {
    /// Leading/trailing positions latched at the edges.
    latch: (u16, u16),
    /// The capture registers of 0xC0/2 (updated in pairs).
    registers: (u16, u16),
    /// Transition status of this revolution (bit 0 leading, bit 1 trailing).
    transition: u16,
    /// Single-shot reset to preset: the revolution after the input.
    shot: Shot,
    /// Output enable single shot / advanced: the outputs are enabled.
    enabled: bool,
    /// Advanced mode: triggered in the window, waiting for the enable position.
    pending: bool,
    /// Advanced mode: counts travelled since the enable position.
    enabled_travel: u32,
    /// Output enable windows: the input was seen inside the window this revolution.
    seen: bool,
    /// Reset to preset average: the last positions, their count and the next slot.
    history: [u16; 32],
    history_len: u8,
    history_next: u8,
}

/// The add-on test (§2.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Addon {
    /// Running.
    active: bool,
    /// When it ends (timed test), or `None` while the enable bit holds it.
    until: Option<Instant>,
    /// The simulated angle travelled since the start (fraction of a revolution, and the
    /// remainder of the division).
    angle: u64,
    rem: u128,
    /// Group positions at the start.
    start: [u16; GROUPS],
    /// Simulated RPM.
    rpm: u16,
    /// Output mask (outputs 1-16).
    mask: u16,
}

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
        const IDLE: InputState = InputState {
            latch: (0, 0),
            registers: (0, 0),
            transition: 0,
            shot: Shot::Idle,
            enabled: false,
            pending: false,
            enabled_travel: 0,
            seen: false,
            history: [0; 32],
            history_len: 0,
            history_next: 0,
        };
        Engine {
            angle: 0,
            rem: 0,
            rpm: 0,
            fault: false,
            last: None,
            group_offset: [0; GROUPS],
            input_offset: [0; INPUTS],
            output_offset: [None; OUTPUTS],
            tune: [0; OUTPUTS],
            positions: [0; GROUPS],
            travel: [0; GROUPS],
            timed_until: [None; OUTPUTS],
            inputs: [IDLE; INPUTS],
            warnings: 0,
            addon: Addon {
                active: false,
                until: None,
                angle: 0,
                rem: 0,
                start: [0; GROUPS],
                rpm: 0,
                mask: 0,
            },
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
        self.addon.active
    }

    /// Input `i`'s 0xC0/2 words: leading position, trailing position, transition status.
    pub fn input_status(&self, i: usize) -> [u16; 3] {
        self.inputs
            .get(i)
            .map_or([0; 3], |s| [s.registers.0, s.registers.1, s.transition])
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
            let Some(slot) = self.group_offset.get_mut(g) else {
                continue;
            };
            let current = i32::from(*slot);
            let offset = match (mask >> (2 * g)) & 3 {
                1 => value - raw,
                2 => value,
                3 => current + value,
                _ => continue,
            };
            *slot = offset.rem_euclid(sf) as u16;
        }
        self.refresh_positions(cfg);
    }

    /// Program control code 1: no offset (every group, input and output offset cleared,
    /// setpoint tuning undone).
    pub fn clear_offsets(&mut self, cfg: &Config) {
        self.group_offset = [0; GROUPS];
        self.input_offset = [0; INPUTS];
        self.output_offset = [None; OUTPUTS];
        self.tune = [0; OUTPUTS];
        self.refresh_positions(cfg);
    }

    /// Restores group offsets saved with the program.
    pub fn set_group_offsets(&mut self, cfg: &Config, offsets: [u16; GROUPS]) {
        for (g, (slot, o)) in self.group_offset.iter_mut().zip(offsets).enumerate() {
            *slot = o % cfg.scale(g);
        }
        self.refresh_positions(cfg);
    }

    /// Starts the add-on test (rising edge of output word 1 bit 1) with attribute 35.
    pub fn start_addon(&mut self, cfg: &Config) {
        let [rpm, ms, mask] = cfg.addon;
        self.addon = Addon {
            active: true,
            until: (ms != 0).then(|| self.now.add(Duration::from_millis(ms.into()))),
            angle: 0,
            rem: 0,
            start: self.positions,
            rpm,
            mask,
        };
    }

    /// The enable bit went low: a test without a time ends; a timed one runs on (\[R\]).
    pub fn release_addon(&mut self) {
        if self.addon.until.is_none() {
            self.addon.active = false;
        }
    }

    /// Inputs 1-16 are now at `levels` (bit 0 = input 1): edges trigger the functions of
    /// attribute 34 (the leading edge is the rising one of an active-high input, the
    /// falling one of an active-low input) and the capture registers.
    fn set_inputs(&mut self, cfg: &Config, levels: u16) {
        let changed = levels ^ self.levels;
        self.levels = levels;
        for i in (0..INPUTS).filter(|i| changed & (1 << i) != 0) {
            let leading = self.active(cfg, i);
            let pos = cfg.group_of_input(i).map_or(0, |g| self.position(g));
            let [bits, ..] = cfg.input(i);
            let update = (bits >> 1) & 3;
            let Some(st) = self.inputs.get_mut(i) else {
                continue;
            };
            if leading {
                st.latch.0 = pos;
                st.transition |= 1;
                if update == 1 {
                    st.registers = st.latch;
                }
                self.trigger(cfg, i);
            } else {
                st.latch.1 = pos;
                st.transition |= 2;
                if update == 2 {
                    st.registers = st.latch;
                }
            }
        }
        self.compute(cfg);
    }

    /// The outputs (0-based bit mask) input `i` of type `kind` acts on: its group's outputs
    /// for the group types, else its masks (inside its group).
    fn input_outputs(cfg: &Config, i: usize, kind: u16) -> u32 {
        let Some(g) = cfg.group_of_input(i) else {
            return 0;
        };
        let [hs, ls] = [cfg.group_word(g, 1), cfg.group_word(g, 2)];
        let group = u32::from(hs) | u32::from(ls) << 16;
        if kind >= t::GROUP {
            return group;
        }
        let [_, h, l, ..] = cfg.input(i);
        (u32::from(h) | u32::from(l) << 16) & group
    }

    /// The leading edge of input `i`: its function acts.
    fn trigger(&mut self, cfg: &Config, i: usize) {
        let [_, _, _, kind, p1, p2, p3] = cfg.input(i);
        let Some(g) = cfg.group_of_input(i) else {
            return;
        };
        let sf = i32::from(cfg.scale(g));
        let pos = self.position(g);
        let raw = i32::from(self.raw(cfg, g));
        let outputs = Self::input_outputs(cfg, i, kind);
        let inside = |on: u16, off: u16| window(pos, on, off);
        let preset = |engine: &mut Self, value: u16| {
            let offset = (i32::from(value) - raw).rem_euclid(sf) as u16;
            if let Some(slot) = engine.input_offset.get_mut(i) {
                *slot = offset;
            }
            if kind >= t::GROUP {
                if let Some(slot) = engine.group_offset.get_mut(g) {
                    *slot = offset;
                }
            } else {
                for o in bits(outputs) {
                    if let Some(slot) = engine.output_offset.get_mut(o) {
                        *slot = Some(offset);
                    }
                }
            }
        };
        match kind % t::GROUP {
            _ if kind == t::SETPOINT_TUNE => {
                for o in bits(outputs) {
                    if let Some(tune) = self.tune.get_mut(o) {
                        *tune = (*tune + i32::from(p1 as i16)).rem_euclid(sf);
                    }
                }
            }
            _ if kind == t::OFFSET_TUNE => {
                if let Some(slot) = self.group_offset.get_mut(g) {
                    let offset = i32::from(*slot) + i32::from(p1 as i16);
                    *slot = offset.rem_euclid(sf) as u16;
                }
            }
            20 => preset(self, p1),
            21 => {
                preset(self, p1);
                if let Some(st) = self.inputs.get_mut(i) {
                    st.shot = Shot::Running(0);
                }
            }
            22 => {
                if let Some(st) = self.inputs.get_mut(i) {
                    let n = p1.clamp(1, 32) as u8;
                    if let Some(slot) = st.history.get_mut(usize::from(st.history_next % 32)) {
                        *slot = pos;
                    }
                    st.history_next = (st.history_next + 1) % n;
                    st.history_len = (st.history_len + 1).min(n);
                    let len = usize::from(st.history_len);
                    let sum: u32 = st.history.iter().take(len).map(|&p| u32::from(p)).sum();
                    let average = (sum / len.max(1) as u32) as u16;
                    // The average input position becomes the program's zero ([R], README).
                    let target = (i32::from(pos) - i32::from(average)).rem_euclid(sf) as u16;
                    preset(self, target);
                }
            }
            23 if inside(p2, p3) => {
                preset(self, p1);
                if let Some(st) = self.inputs.get_mut(i) {
                    st.shot = Shot::Running(0);
                }
            }
            31 => {
                if let Some(st) = self.inputs.get_mut(i) {
                    st.enabled = inside(p1, p2);
                    st.seen |= inside(p1, p2);
                }
            }
            32 => {
                if let Some(st) = self.inputs.get_mut(i) {
                    st.pending = inside(p1, p2);
                    st.seen |= st.pending;
                }
                let _ = p3;
            }
            _ => {}
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
        if self.addon.active {
            let (s, r) = advance(self.addon.rpm, dt, self.addon.rem);
            self.addon.angle = self.addon.angle.wrapping_add(s);
            self.addon.rem = r;
            if self
                .addon
                .until
                .is_some_and(|u| now.as_micros() >= u.as_micros())
            {
                self.addon.active = false;
            }
        }
        self.revolution_events(cfg);
        self.time_based(cfg, now);
        self.compute(cfg);
    }

    /// Crossings during the last tick: zero (capture registers, transition status),
    /// windows (warnings, single-shot enables), one revolution after a single shot.
    fn revolution_events(&mut self, cfg: &Config) {
        for i in 0..INPUTS {
            let Some(g) = cfg.group_of_input(i) else {
                continue;
            };
            let [bits, _, _, kind, p1, p2, p3] = cfg.input(i);
            let travel = self.travel.get(g).copied().unwrap_or(0);
            let (pos, sf) = (self.position(g), cfg.scale(g));
            let Some(st) = self.inputs.get_mut(i) else {
                continue;
            };
            if crossed(pos, travel, 0, sf) {
                if (bits >> 1) & 3 == 0 {
                    st.registers = st.latch;
                }
                st.transition = 0;
            }
            if let Shot::Running(n) = st.shot {
                let n = n.saturating_add(travel);
                st.shot = if n >= u32::from(sf) {
                    Shot::Expired
                } else {
                    Shot::Running(n)
                };
            }
            match kind % t::GROUP {
                31 | 32 => {
                    if crossed(pos, travel, p2, sf) {
                        let bit = 1 << i;
                        if st.seen {
                            self.warnings &= !bit;
                        } else {
                            self.warnings |= bit;
                        }
                        st.seen = false;
                    }
                    if kind % t::GROUP == 31 && crossed(pos, travel, p1, sf) {
                        st.enabled = false;
                    }
                    if kind % t::GROUP == 32 {
                        if st.enabled {
                            st.enabled_travel = st.enabled_travel.saturating_add(travel);
                            if st.enabled_travel >= u32::from(sf) {
                                st.enabled = false;
                            }
                        }
                        if st.pending && crossed(pos, travel, p3, sf) {
                            st.pending = false;
                            st.enabled = true;
                            st.enabled_travel = 0;
                        }
                    }
                }
                _ => {}
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
        let prog = cfg.program(o);
        if prog.count == 0 {
            return false;
        }
        let c = prog.compensation;
        let (lead, trail) = if o < HIGH_SPEED && c.iter().any(|&x| x != 0) {
            (
                interpolate(rpm, c[0], c[3], c[1], c[4]),
                interpolate(rpm, c[0], c[3], c[2], c[5]),
            )
        } else {
            (0, 0)
        };
        let tune = self.tune.get(o).copied().unwrap_or(0);
        let std_window = |on: u16, off: u16| {
            let on = shift(on, tune + lead, sf);
            let off = shift(off, tune + trail, sf);
            window(pos, on, off)
        };
        let [p1, p2, p3, p4] = prog.params;
        let first = match prog.kind {
            setpoint::STANDARD => std_window(p1, p2),
            setpoint::STITCHING => {
                let on = shift(p1, tune + lead, sf);
                let off = shift(p2, tune + trail, sf);
                let cycle = u32::from(p3) + u32::from(p4);
                let into = (u32::from(pos) + u32::from(sf) - u32::from(on)) % u32::from(sf);
                window(pos, on, off) && (cycle == 0 || into % cycle < u32::from(p3))
            }
            setpoint::TIME_BASED => {
                let until = self.timed_until.get(o).copied().flatten();
                until.is_some_and(|u| self.now.as_micros() < u.as_micros())
            }
            setpoint::MOTION_DETECT => rpm >= p1,
            _ => false,
        };
        let rest = prog
            .extra
            .iter()
            .take(usize::from(prog.count.saturating_sub(1)).min(7))
            .any(|&(on, off)| std_window(on, off));
        first || rest
    }

    /// True if input `i` is in its active state (bit 0 of its bit register).
    fn active(&self, cfg: &Config, i: usize) -> bool {
        let [bits, ..] = cfg.input(i);
        ((self.levels >> i) & 1 == 1) == (bits & 1 == 1)
    }

    /// Recomputes the output status from the configuration, the inputs and the output data.
    pub fn compute(&mut self, cfg: &Config) {
        let data = self.data;
        let rpm = self.rpm();
        let mut gated = 0u32;
        let mut input_force = [0u16; OUTPUTS];
        let mut input_group_force = [0u16; GROUPS];
        for i in 0..INPUTS {
            let [_, _, _, kind, p1, p2, _] = cfg.input(i);
            let Some(st) = self.inputs.get(i) else {
                continue;
            };
            let outs = Self::input_outputs(cfg, i, kind);
            let active = self.active(cfg, i);
            match kind % t::GROUP {
                30 if !active => gated |= outs,
                31 | 32 if !st.enabled => gated |= outs,
                21 | 23 if st.shot == Shot::Expired => gated |= outs,
                40 => {
                    let c = if active { p1 } else { p2 };
                    if kind >= t::GROUP {
                        if let Some(g) = cfg.group_of_input(i) {
                            if let Some(slot) = input_group_force.get_mut(g) {
                                *slot = c;
                            }
                        }
                    } else {
                        for o in bits(outs) {
                            if let Some(slot) = input_force.get_mut(o) {
                                if *slot == 0 {
                                    *slot = c;
                                }
                            }
                        }
                    }
                }
                _ => {}
            }
        }
        let mut out = 0u32;
        for (o, &by_input) in input_force.iter().enumerate() {
            if data.bits & RUN_ENABLE == 0 {
                break;
            }
            let Some(g) = cfg.group_of_output(o) else {
                continue;
            };
            let sf = cfg.scale(g);
            let group = match data.group_force_of(g) {
                0 => input_group_force.get(g).copied().unwrap_or(0),
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
                _ if self.addon.active && o < HIGH_SPEED && self.addon.mask & (1 << o) != 0 => {
                    let sim = (u64::from(self.addon.angle as u32) * u64::from(sf)) >> 32;
                    let start = self.addon.start.get(g).copied().unwrap_or(0);
                    let pos = ((u64::from(start) + sim) % u64::from(sf)) as u16;
                    self.pattern(cfg, o, pos, sf, self.addon.rpm)
                }
                _ => {
                    let (min, mask) = (cfg.group_word(g, 4), cfg.group_word(g, 5));
                    let slow = min != 0 && rpm < min && o < HIGH_SPEED && mask & (1 << o) != 0;
                    let pos = self.output_position(cfg, o, g);
                    !slow && gated & (1 << o) == 0 && self.pattern(cfg, o, pos, sf, rpm)
                }
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

/// The counts of angle (2^32 per revolution) `rpm` travels in `dt_us`, with the remainder
/// carried from the last call.
fn advance(rpm: u16, dt_us: u64, rem: u128) -> (u64, u128) {
    let total = u128::from(rpm) * u128::from(dt_us) * (1u128 << 32) + rem;
    ((total / US_PER_MIN) as u64, total % US_PER_MIN)
}

/// `p` moved earlier by `counts` (advance), modulo `sf`.
fn shift(p: u16, counts: i32, sf: u16) -> u16 {
    (i32::from(p) - counts).rem_euclid(i32::from(sf.max(1))) as u16
}

/// True inside the window on (inclusive) .. off (exclusive), wrapping when on > off; an
/// empty window when on = off (\[R\] 14).
pub fn window(pos: u16, on: u16, off: u16) -> bool {
    match on.cmp(&off) {
        core::cmp::Ordering::Less => (on..off).contains(&pos),
        core::cmp::Ordering::Greater => pos >= on || pos < off,
        core::cmp::Ordering::Equal => false,
    }
}

/// True if position `x` was reached during the last `travel` counts that ended at `pos`.
fn crossed(pos: u16, travel: u32, x: u16, sf: u16) -> bool {
    if travel == 0 {
        return false;
    }
    let back = (u32::from(pos) + u32::from(sf) - u32::from(x) % u32::from(sf)) % u32::from(sf);
    back < travel
}

/// Linear speed compensation: `start` counts at `rpm_start` and below, `end` at `rpm_end`
/// and above, linear between (\[R\] 14: clamped).
fn interpolate(rpm: u16, rpm_start: u16, rpm_end: u16, start: u16, end: u16) -> i32 {
    let (s, e) = (i32::from(start), i32::from(end));
    if rpm <= rpm_start || rpm_end <= rpm_start {
        s
    } else if rpm >= rpm_end {
        e
    } else {
        let span = i32::from(rpm_end - rpm_start);
        s + (e - s) * i32::from(rpm - rpm_start) / span
    }
}

/// The indices of the set bits of `mask`.
fn bits(mask: u32) -> impl Iterator<Item = usize> {
    (0..OUTPUTS).filter(move |&o| mask & (1 << o) != 0)
}
