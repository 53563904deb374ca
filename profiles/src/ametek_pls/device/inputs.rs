//! The 16 inputs (§2.6, attribute 34): edges latch positions into the capture registers and
//! start the input's function (setpoint or offset tune, reset to preset, output enable
//! windows, output force); crossings of zero and of the windows update them every tick; and
//! they gate or force the outputs.

use super::super::params::{Config, GROUPS, INPUTS, OUTPUTS};
use super::super::validate::input_type as t;
use super::geometry::{bits, crossed, window};

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
pub struct InputState {
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

/// What the leading edge of an input does to the offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// Nothing (or only to the input's own state).
    None,
    /// Remote setpoint tune: the input's outputs' setpoints advance by this many counts.
    SetpointTune(i16),
    /// Offset tune: the group's offset moves by this many counts.
    OffsetTune(i16),
    /// Reset to preset: the input's group or outputs read this position now.
    Preset(u16),
}

impl InputState {
    /// No edge seen, no function running.
    pub const IDLE: InputState = InputState {
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

    /// The 0xC0/2 words: leading position, trailing position, transition status.
    pub fn status(&self) -> [u16; 3] {
        [self.registers.0, self.registers.1, self.transition]
    }

    /// An edge at position `pos`: latched as the leading or trailing position, and into the
    /// capture registers when `update` (bits 1-2 of the input's bit register) says so.
    pub fn edge(&mut self, leading: bool, pos: u16, update: u16) {
        if leading {
            self.latch.0 = pos;
            self.transition |= 1;
            if update == 1 {
                self.registers = self.latch;
            }
        } else {
            self.latch.1 = pos;
            self.transition |= 2;
            if update == 2 {
                self.registers = self.latch;
            }
        }
    }

    /// Its function starts afresh (its configuration changed); the capture registers stay.
    pub fn restart(&mut self) {
        *self = InputState {
            latch: self.latch,
            registers: self.registers,
            transition: self.transition,
            ..InputState::IDLE
        };
    }

    /// The leading edge of input `i`, its group at `pos` (at `sample` in the frame an
    /// average records), its function acts on its own state and says what it does
    /// to the offsets.
    pub fn trigger(&mut self, cfg: &Config, i: usize, pos: u16, sample: u16) -> Effect {
        let [_, _, _, kind, p1, p2, p3] = cfg.input(i);
        let inside = |on: u16, off: u16| window(pos, on, off);
        match kind % t::GROUP {
            _ if kind == t::SETPOINT_TUNE => Effect::SetpointTune(p1 as i16),
            _ if kind == t::OFFSET_TUNE => Effect::OffsetTune(p1 as i16),
            20 => Effect::Preset(p1),
            21 => {
                self.shot = Shot::Running(0);
                Effect::Preset(p1)
            }
            22 => {
                let n = p1.clamp(1, 32) as u8;
                if let Some(slot) = self.history.get_mut(usize::from(self.history_next % 32)) {
                    *slot = sample;
                }
                self.history_next = (self.history_next + 1) % n;
                self.history_len = (self.history_len + 1).min(n);
                let len = usize::from(self.history_len);
                let sum: u32 = self.history.iter().take(len).map(|&p| u32::from(p)).sum();
                // The average of the recorded positions is the preset (§2.6): the position
                // at the input becomes it. The positions are recorded in a frame the
                // resets do not move, so the average settles.
                Effect::Preset((sum / len.max(1) as u32) as u16)
            }
            23 if inside(p2, p3) => {
                self.shot = Shot::Running(0);
                Effect::Preset(p1)
            }
            31 => {
                self.enabled = inside(p1, p2);
                self.seen |= inside(p1, p2);
                Effect::None
            }
            32 => {
                self.pending = inside(p1, p2);
                self.seen |= self.pending;
                Effect::None
            }
            _ => Effect::None,
        }
    }

    /// The crossings during the last tick, which travelled `travel` counts to the group
    /// position `pos` and the resolver's `raw` position (scale factor `sf`): zero (capture registers, transition status), the windows (single-shot
    /// and advanced enables), one revolution after a single shot. `Some(seen)` when the
    /// input's window ended: whether the input was seen in it (else its warning is set).
    pub fn revolution(
        &mut self,
        cfg: &Config,
        i: usize,
        (pos, raw): (u16, u16),
        travel: u32,
        sf: u16,
    ) -> Option<bool> {
        let [bits, _, _, kind, p1, p2, p3] = cfg.input(i);
        // The resolver's zero (§2.6 bits 1-2: "when the resolver position goes through
        // zero"), not the group's, which an offset moves.
        if crossed(raw, travel, 0, sf) {
            if (bits >> 1) & 3 == 0 {
                self.registers = self.latch;
            }
            self.transition = 0;
        }
        if let Shot::Running(n) = self.shot {
            let n = n.saturating_add(travel);
            self.shot = if n >= u32::from(sf) {
                Shot::Expired
            } else {
                Shot::Running(n)
            };
        }
        let mut warning = None;
        if let 31 | 32 = kind % t::GROUP {
            if crossed(pos, travel, p2, sf) {
                warning = Some(self.seen);
                self.seen = false;
            }
            if kind % t::GROUP == 31 && crossed(pos, travel, p1, sf) {
                self.enabled = false;
            }
            if kind % t::GROUP == 32 {
                if self.enabled {
                    self.enabled_travel = self.enabled_travel.saturating_add(travel);
                    if self.enabled_travel >= u32::from(sf) {
                        self.enabled = false;
                    }
                }
                if self.pending && crossed(pos, travel, p3, sf) {
                    self.pending = false;
                    self.enabled = true;
                    self.enabled_travel = 0;
                }
            }
        }
        warning
    }
}

/// True if input `i` is in its active state at `levels` (bit 0 of its bit register).
pub fn active(cfg: &Config, levels: u16, i: usize) -> bool {
    let [bits, ..] = cfg.input(i);
    ((levels >> i) & 1 == 1) == (bits & 1 == 1)
}

/// True for the reset to preset types (20-23, 120-123), the inputs with an input offset.
pub fn is_preset(kind: u16) -> bool {
    matches!(kind, 20..=23 | 120..=123)
}

/// The outputs (0-based bit mask) of group `g`.
pub fn group_outputs(cfg: &Config, g: usize) -> u32 {
    u32::from(cfg.group_word(g, 1)) | u32::from(cfg.group_word(g, 2)) << 16
}

/// The outputs (0-based bit mask) input `i` of type `kind` acts on: its group's outputs for
/// the group types, and for a reset to preset (20-23) without a mask; else its masks
/// (inside its group).
pub fn input_outputs(cfg: &Config, i: usize, kind: u16) -> u32 {
    let Some(g) = cfg.group_of_input(i) else {
        return 0;
    };
    let group = group_outputs(cfg, g);
    if kind >= t::GROUP {
        return group;
    }
    let [_, h, l, ..] = cfg.input(i);
    // §2.6: a reset to preset "is used to reset the position of a PLS group"; only "if the
    // output mask of the input is a subset of the outputs in the PLS group" are just those
    // outputs reset. No mask at all selects no subset: the group resets.
    if is_preset(kind) && h == 0 && l == 0 {
        return group;
    }
    (u32::from(h) | u32::from(l) << 16) & group
}

/// What the inputs do to the outputs now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gates {
    /// Outputs an input holds off (output enable, single shot expired).
    pub gated: u32,
    /// Force codes of the outputs from output force inputs (0: none).
    pub force: [u16; OUTPUTS],
    /// Force codes of the groups from group force inputs (0: none).
    pub group_force: [u16; GROUPS],
}

/// The gates and forces of `inputs` at `levels`.
pub fn gates(cfg: &Config, inputs: &[InputState; INPUTS], levels: u16) -> Gates {
    let mut gates = Gates {
        gated: 0,
        force: [0; OUTPUTS],
        group_force: [0; GROUPS],
    };
    for (i, st) in inputs.iter().enumerate() {
        let [_, _, _, kind, p1, p2, _] = cfg.input(i);
        let outs = input_outputs(cfg, i, kind);
        let active = active(cfg, levels, i);
        match kind % t::GROUP {
            30 if !active => gates.gated |= outs,
            31 | 32 if !st.enabled => gates.gated |= outs,
            21 | 23 if st.shot == Shot::Expired => gates.gated |= outs,
            40 => {
                let c = if active { p1 } else { p2 };
                if kind >= t::GROUP {
                    if let Some(g) = cfg.group_of_input(i) {
                        if let Some(slot) = gates.group_force.get_mut(g) {
                            *slot = c;
                        }
                    }
                } else {
                    for o in bits(outs) {
                        if let Some(slot) = gates.force.get_mut(o) {
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
    gates
}
