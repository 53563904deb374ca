//! The manual's validation rules for every Set of class 0xC1 (§2.3-2.10), one function
//! per attribute. A rule broken gives `(code, word)`: code 1 invalid data value, 2 conflict
//! in data values, 3 resolver error, 4 memory error; the word is 1-based as in the manual's
//! tables. All range checks (code 1) come before the conflict checks (code 2); within each
//! pass the lowest word wins (\[R\] AM-EX-6).

// Word offsets only: group, setpoint and input indices below the tables' fixed sizes (at
// most a few hundred), and attribute IDs matched to their ranges before any subtraction.
#![allow(clippy::arithmetic_side_effects)]

use super::params::{attr, setpoint, Config, GROUPS, HIGH_SPEED, INPUTS, INPUT_STRIDE};

/// An error the module reports in input words 15-17: (code, 1-based word).
pub type Violation = (u16, u16);

/// Error code 1: invalid data value.
pub const INVALID: u16 = 1;
/// Error code 2: conflict in data values.
pub const CONFLICT: u16 = 2;
/// Error code 3: could not process because of a resolver error.
pub const RESOLVER: u16 = 3;
/// Error code 4: memory error.
pub const MEMORY: u16 = 4;

/// Highest RPM any RPM word accepts (§2.3, 2.4, 2.7).
pub const MAX_RPM: u16 = 2048;

/// Input type codes (§2.6).
pub mod input_type {
    /// No input type.
    pub const NONE: u16 = 0;
    /// Remote setpoint tuning.
    pub const SETPOINT_TUNE: u16 = 10;
    /// Reset to preset, standard.
    pub const PRESET: u16 = 20;
    /// Reset to preset, single shot.
    pub const PRESET_SINGLE: u16 = 21;
    /// Reset to preset, average.
    pub const PRESET_AVERAGE: u16 = 22;
    /// Reset to preset, window.
    pub const PRESET_WINDOW: u16 = 23;
    /// Output enable, level.
    pub const ENABLE_LEVEL: u16 = 30;
    /// Output enable, single shot.
    pub const ENABLE_SINGLE: u16 = 31;
    /// Output enable, advanced mode.
    pub const ENABLE_ADVANCED: u16 = 32;
    /// Force outputs.
    pub const FORCE: u16 = 40;
    /// Remote offset tune.
    pub const OFFSET_TUNE: u16 = 110;
    /// Group variants are the codes above plus this (120-123, 130-132, 140).
    pub const GROUP: u16 = 100;
    /// Every valid code (the manual's 18 types and "none").
    pub const ALL: [u16; 19] = [
        0, 10, 20, 21, 22, 23, 30, 31, 32, 40, 110, 120, 121, 122, 123, 130, 131, 132, 140,
    ];
}

/// Checks the words of a Set of attribute `a` against the rules and the current
/// configuration `cfg` (scale factors and group membership).
pub fn check(cfg: &Config, a: u16, w: &[u16], resolver_fault: bool) -> Result<(), Violation> {
    match a {
        attr::PLS => pls(w),
        attr::FIRST_HIGH..=attr::LAST_HIGH => output(cfg, usize::from(a - 2), w, 6),
        attr::FIRST_LOW..=attr::LAST_LOW => output(cfg, usize::from(a - 2), w, 0),
        attr::INPUTS => inputs(cfg, w),
        attr::ADDON => range(word(w, 0) <= MAX_RPM, 1),
        attr::OFFSET => offset(cfg, w, resolver_fault),
        attr::CONTROL => range(matches!(word(w, 0), 1..=3), 1),
        // The resolver version refuses the encoder object ([R] 12).
        _ => Err((CONFLICT, 1)),
    }
}

/// Word `i` (0-based) of `w`, 0 past its end.
fn word(w: &[u16], i: usize) -> u16 {
    w.get(i).copied().unwrap_or(0)
}

/// Code 1 at 1-based word `n` unless `ok`.
fn range(ok: bool, n: usize) -> Result<(), Violation> {
    if ok {
        Ok(())
    } else {
        Err((INVALID, n as u16))
    }
}

/// Attribute 1 (§2.3): scale factors 2-65535, min speed 0-2048, min speed mask inside the
/// group's high speed outputs (code 1); an output or input in two groups (code 2, reported
/// at the later group's word).
fn pls(w: &[u16]) -> Result<(), Violation> {
    for g in 0..GROUPS {
        let base = 6 * g;
        range(word(w, base) >= 2, base + 1)?;
        range(word(w, base + 4) <= MAX_RPM, base + 5)?;
        range(word(w, base + 5) & !word(w, base + 1) == 0, base + 6)?;
    }
    for g in 1..GROUPS {
        for k in 1..=3 {
            let taken = (0..g).fold(0, |acc, h| acc | word(w, 6 * h + k));
            if word(w, 6 * g + k) & taken != 0 {
                return Err((CONFLICT, (6 * g + k + 1) as u16));
            }
        }
    }
    Ok(())
}

/// Attributes 2-33 (§2.4, 2.5): output `o` (0-based); `base` is the 0-based index of the
/// "number of setpoints" word (6 for high speed, 0 for low speed).
fn output(cfg: &Config, o: usize, w: &[u16], base: usize) -> Result<(), Violation> {
    let limit = cfg.group_of_output(o).map_or(u16::MAX, |g| cfg.scale(g));
    let position = |i: usize| range(word(w, i) < limit, i + 1);
    if base == 6 {
        range(word(w, 0) <= MAX_RPM, 1)?;
        range(word(w, 3) <= MAX_RPM, 4)?;
    }
    let count = word(w, base);
    range(count <= 8, base + 1)?;
    let kind = word(w, base + 1);
    if count >= 1 {
        range(kind <= setpoint::MOTION_DETECT, base + 2)?;
        let p = base + 2;
        match kind {
            setpoint::STANDARD | setpoint::STITCHING => {
                position(p)?;
                position(p + 1)?;
            }
            setpoint::TIME_BASED => position(p)?,
            setpoint::MOTION_DETECT => range(word(w, p) <= MAX_RPM, p + 1)?,
            _ => {}
        }
        for k in 0..usize::from(count.saturating_sub(1)) {
            position(base + 6 + 2 * k)?;
            position(base + 7 + 2 * k)?;
        }
    }
    if base == 6 && w.iter().take(6).any(|&x| x != 0) {
        let conflict = |ok: bool, n: u16| if ok { Ok(()) } else { Err((CONFLICT, n)) };
        conflict(word(w, 0) < word(w, 3), 1)?;
        conflict(word(w, 1) <= word(w, 4), 2)?;
        conflict(word(w, 2) <= word(w, 5), 3)?;
    }
    let single = matches!(kind, setpoint::TIME_BASED | setpoint::MOTION_DETECT);
    if single && count > 1 {
        return Err((CONFLICT, (base + 1) as u16));
    }
    Ok(())
}

/// Attribute 34 (§2.6): per input, capture update 0-2, a known type, parameters in range
/// (code 1); output masks only with outputs of the input's own group (code 2).
fn inputs(cfg: &Config, w: &[u16]) -> Result<(), Violation> {
    use input_type as t;
    for i in 0..INPUTS {
        let b = INPUT_STRIDE * i;
        let limit = cfg.group_of_input(i).map_or(u16::MAX, |g| cfg.scale(g));
        let position = |k: usize| range(word(w, b + k) < limit, b + k + 1);
        range((word(w, b) >> 1) & 3 != 3, b + 1)?;
        let kind = word(w, b + 3);
        range(t::ALL.contains(&kind), b + 4)?;
        match kind % t::GROUP {
            _ if kind == t::SETPOINT_TUNE || kind == t::OFFSET_TUNE => {}
            20 | 21 => position(4)?,
            22 => range(matches!(word(w, b + 4), 1..=32), b + 5)?,
            23 => {
                position(4)?;
                position(5)?;
                position(6)?;
            }
            31 => {
                position(4)?;
                position(5)?;
            }
            32 => {
                position(4)?;
                position(5)?;
                position(6)?;
            }
            40 => {
                range(word(w, b + 4) <= 2, b + 5)?;
                range(word(w, b + 5) <= 2, b + 6)?;
            }
            _ => {}
        }
    }
    for i in 0..INPUTS {
        let b = INPUT_STRIDE * i;
        let kind = word(w, b + 3);
        if kind == t::NONE || kind >= t::GROUP {
            continue; // group types ignore the masks (§2.6)
        }
        let group = cfg.group_of_input(i);
        for (k, first) in [(1, 0), (2, HIGH_SPEED)] {
            let mask = word(w, b + k);
            let foreign = (0..16).any(|bit| {
                mask & (1 << bit) != 0
                    && (group.is_none() || cfg.group_of_output(first + bit) != group)
            });
            if foreign {
                return Err((CONFLICT, (b + k + 1) as u16));
            }
        }
    }
    Ok(())
}

/// Attribute 36 (§2.8): a home value must be a position of its group (\[R\]); nothing can be
/// offset while the resolver has a fault (code 3).
fn offset(cfg: &Config, w: &[u16], resolver_fault: bool) -> Result<(), Violation> {
    if resolver_fault {
        return Err((RESOLVER, 1));
    }
    let mask = word(w, 0);
    for g in 0..GROUPS {
        let home = (mask >> (2 * g)) & 3 == 1;
        let value = word(w, g + 1) as i16;
        if home && (value < 0 || value as u16 >= cfg.scale(g)) {
            return Err((INVALID, (g + 2) as u16));
        }
    }
    Ok(())
}
