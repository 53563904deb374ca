//! The Class 1 I/O group configuration (p.8-10): up to 16 groups of up to 8 consecutive
//! parameters, each with a direction and a wire type, validated into a [`Layout`] when a
//! Class 1 Forward_Open arrives (R5.5), with the status values of Table 3 (p.6).
//!
//! Group `g` is P(37440+4g)..P(37443+4g): start, count, direction (0 = IPA sends to PLC,
//! produced T->O; 1 = IPA reads from PLC, consumed O->T), type (1 = DINT, 2 = REAL).
//! The T->O data is every direction-0 group in ascending group order, the O->T data every
//! direction-1 group, 4 bytes per parameter in the group's wire type (R5.4).

use super::params;

/// Most groups (Table 4).
pub const MAX_GROUPS: usize = 16;
/// Most parameters in a group (Table 4).
pub const MAX_PER_GROUP: i32 = 8;
/// Most parameters each way (Table 4: 100 parameters, 3200 bits).
pub const MAX_LONGS: usize = 100;

/// Which way a group's data goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// 0: IPA sends to PLC (produced, T->O, assembly 101).
    Produce,
    /// 1: IPA reads from PLC (consumed, O->T, assembly 102).
    Consume,
}

/// One validated group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Group {
    /// First parameter.
    pub start: u32,
    /// Number of consecutive parameters (1-8).
    pub count: u8,
    /// Direction.
    pub direction: Direction,
    /// The type on the wire (1 = DINT, 2 = REAL).
    pub wire: params::Kind,
}

/// Table 3 status values (P37433).
pub mod status {
    /// No connection attempted, or connection closed.
    pub const IDLE: i32 = 0;
    /// Connection active.
    pub const ACTIVE: i32 = 1;
    /// More than 16 groups (P37434 > 16).
    pub const TOO_MANY_GROUPS: i32 = 2;
    /// More than 8 parameters in a group.
    pub const GROUP_TOO_LONG: i32 = 3;
    /// More than 100 longs produced.
    pub const TOO_MANY_PRODUCED: i32 = 4;
    /// More than 100 longs consumed.
    pub const TOO_MANY_CONSUMED: i32 = 5;
    /// Length of FSTAT group not 80: reserved, never produced (A7).
    pub const FSTAT_LENGTH: i32 = 6;
    /// Invalid or non-existent parameter number.
    pub const BAD_PARAMETER: i32 = 7;
}

/// The "last configuration entry" P37435-P37437: group number, parameter number and
/// length (a parameter count, A10).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Entry {
    /// P37435, group number.
    pub group: i32,
    /// P37436, parameter number.
    pub parameter: i32,
    /// P37437, length (number of parameters).
    pub length: i32,
}

/// A configuration refused with a Table 3 status (2-7) and the failing entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ConfigError {
    /// Table 3 status value.
    pub status: i32,
    /// The failing entry.
    pub entry: Entry,
}

/// A validated configuration, latched while a connection runs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    groups: heapless::Vec<Group, MAX_GROUPS>,
    /// The last group's entry (reported in P37435-P37437 after a success).
    pub last: Entry,
}

impl Layout {
    /// No groups: nothing produced or consumed.
    pub const fn empty() -> Layout {
        Layout {
            groups: heapless::Vec::new(),
            last: Entry {
                group: 0,
                parameter: 0,
                length: 0,
            },
        }
    }
    /// The groups going `direction`, in ascending group order.
    pub fn groups(&self, direction: Direction) -> impl Iterator<Item = &Group> {
        self.groups.iter().filter(move |g| g.direction == direction)
    }
    /// Number of parameters going `direction`.
    pub fn longs(&self, direction: Direction) -> usize {
        self.groups(direction).map(|g| usize::from(g.count)).sum()
    }
    /// The parameters going `direction` with their wire type, in wire order.
    pub fn parameters(
        &self,
        direction: Direction,
    ) -> impl Iterator<Item = (u32, params::Kind)> + '_ {
        self.groups(direction)
            .flat_map(|g| (0..u32::from(g.count)).map(move |k| (g.start.saturating_add(k), g.wire)))
    }
}

/// Validates `groups_in_use` (P37434) and the configuration longs P37440-P37503 in the order
/// of R5.7: (a) P37434 outside 0..16 gives 2; (b) group by group, more than 8 parameters
/// gives 3, and a count below 1, a bad direction or type, or a parameter that does not exist
/// gives 7; (c) more than 100 longs produced gives 4; (d) consumed, 5.
pub fn validate(
    groups_in_use: i32,
    config: &[i32; params::CONFIG_COUNT],
) -> Result<Layout, ConfigError> {
    let n = usize::try_from(groups_in_use)
        .ok()
        .filter(|&n| n <= MAX_GROUPS)
        .ok_or(ConfigError {
            status: status::TOO_MANY_GROUPS,
            entry: Entry {
                group: groups_in_use,
                parameter: 0,
                length: 0,
            },
        })?;
    let mut layout = Layout::empty();
    for (g, entry) in config.chunks_exact(4).take(n).enumerate() {
        let &[start, count, direction, wire] = entry else {
            continue;
        };
        let here = |parameter: i32, status: i32| ConfigError {
            status,
            entry: Entry {
                group: g as i32,
                parameter,
                length: count,
            },
        };
        if count > MAX_PER_GROUP {
            return Err(here(start, status::GROUP_TOO_LONG));
        }
        let direction = match direction {
            0 => Direction::Produce,
            1 => Direction::Consume,
            _ => return Err(here(start, status::BAD_PARAMETER)),
        };
        let wire = match wire {
            1 => params::Kind::Long,
            2 => params::Kind::Float,
            _ => return Err(here(start, status::BAD_PARAMETER)),
        };
        if count < 1 || start < 0 {
            return Err(here(start, status::BAD_PARAMETER));
        }
        let first = start as u32;
        let end = first.saturating_add(count as u32);
        if let Some(missing) = (first..end).find(|&p| params::kind(p).is_none()) {
            return Err(here(missing as i32, status::BAD_PARAMETER));
        }
        let group = Group {
            start: first,
            count: count as u8,
            direction,
            wire,
        };
        // At most 16 groups: the push cannot fail.
        let _ = layout.groups.push(group);
        layout.last = Entry {
            group: g as i32,
            parameter: start,
            length: count,
        };
    }
    for (direction, code) in [
        (Direction::Produce, status::TOO_MANY_PRODUCED),
        (Direction::Consume, status::TOO_MANY_CONSUMED),
    ] {
        let mut sum = 0usize;
        for (g, group) in layout.groups.iter().enumerate() {
            if group.direction != direction {
                continue;
            }
            sum = sum.saturating_add(usize::from(group.count));
            if sum > MAX_LONGS {
                return Err(ConfigError {
                    status: code,
                    entry: Entry {
                        group: g as i32,
                        parameter: group.start as i32,
                        length: i32::from(group.count),
                    },
                });
            }
        }
    }
    Ok(layout)
}
