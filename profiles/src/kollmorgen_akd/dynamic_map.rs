//! Map type 2, the dynamic map (added in the manual's December 2014 edition): bytes 36-63
//! of the command and response assemblies carry the parameters EIP.CMDMAP and EIP.RSPMAP
//! list ([`super::maps`]).
//!
//! Layout: [`super::maps::SLOTS`] slots of 4 bytes, slot k at bytes 36 + 4k .. 40 + 4k, LSB first, in
//! list order; an empty slot is 0. A value is the parameter's value in its network scaling
//! (Appendix B); a 1- or 2-byte parameter is widened (sign-extended when signed), an 8-byte
//! one keeps its lower 32 bits, as its instance N + 1 reads (the manual's EIP.RSPMAP page:
//! position values are "scaled from 8 bytes to 4 bytes").
//!
//! - Response: every production, the current values of the EIP.RSPMAP parameters.
//! - Command: on a Load/Start 0 -> 1 edge with map type 2, before the command type is
//!   executed, each slot is written to its EIP.CMDMAP parameter (a 4-byte value: signed
//!   parameters and the lower-word instances sign-extend it, unsigned ones zero-extend it),
//!   in list order. A value a parameter refuses refuses the whole load (error response
//!   0x09) and none of the slots is kept.

use enip_stack::cip::CipResult;

use super::assemblies::{DYNAMIC_MAP_LEN, DYNAMIC_MAP_START};
use super::classes::parameter;
use super::maps::{self, Which};
use super::state::State;

/// Bytes of the dynamic map (36-63).
pub const LEN: usize = DYNAMIC_MAP_LEN;
/// First byte of the dynamic map in both assemblies.
pub const START: usize = DYNAMIC_MAP_START;

/// Response bytes 36-63: the values of the EIP.RSPMAP parameters.
pub fn response(state: &State) -> [u8; LEN] {
    let mut out = [0u8; LEN];
    for (slot, &entry) in out.chunks_exact_mut(4).zip(state.maps.response.iter()) {
        // The list only holds entries `maps::entry` accepted; anything else reads 0.
        if let Ok(view) = maps::entry(Which::Response, entry) {
            let value = parameter::value(state, &view).to_le_bytes();
            for (dst, src) in slot.iter_mut().zip(value) {
                *dst = src;
            }
        }
    }
    out
}

/// Writes command bytes 36-63 to the EIP.CMDMAP parameters; all of them or none (the
/// writes go to a copy of the state, kept only when every slot is accepted: about 1.1 KB of
/// stack, on a Load/Start edge with map type 2 only).
pub fn apply_command(state: &mut State, data: &[u8; LEN]) -> CipResult {
    let list = state.maps.command;
    let mut trial = state.clone();
    for (&entry, slot) in list.iter().zip(data.chunks_exact(4)) {
        if entry == 0 {
            continue;
        }
        let view = maps::entry(Which::Command, entry)?;
        let mut bytes = [0u8; 4];
        for (dst, src) in bytes.iter_mut().zip(slot) {
            *dst = *src;
        }
        let value = if view.param.signed || view.low_word {
            i64::from(i32::from_le_bytes(bytes))
        } else {
            i64::from(u32::from_le_bytes(bytes))
        };
        trial.set_param(view.param, value)?;
    }
    *state = trial;
    Ok(())
}
