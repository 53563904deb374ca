//! The generic profile: the assemblies of the OpENer sample application under our identity.
//!
//! Output data written to assembly 150 is echoed into input assembly 100, so a scanner sees
//! its own outputs come back (an application-triggered connection produces it at once); 154
//! is a scratch assembly for explicit messaging.

pub mod assemblies;
pub mod eds;
pub mod identity;

#[cfg(test)]
mod tests;

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::device::InputChanges;
use enip_stack::{AssemblyInfo, Device, IdentityInfo};

use assemblies::ASSEMBLIES;
pub use assemblies::{
    CONFIG, CONFIG_SIZE, EXPLICIT, INPUT, INPUT_ONLY_HEARTBEAT, IO_SIZE, LISTEN_ONLY_HEARTBEAT,
    OUTPUT,
};
pub use eds::EDS;
pub use identity::IDENTITY;

/// The generic device: assembly data, all zero at power-up.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Generic {
    /// The outputs, which are also the inputs (the echo).
    output: [u8; IO_SIZE],
    config: [u8; CONFIG_SIZE],
    explicit: [u8; IO_SIZE],
    changed: InputChanges,
}

impl Generic {
    /// A device with every assembly zeroed.
    pub const fn new() -> Self {
        Generic {
            output: [0; IO_SIZE],
            config: [0; CONFIG_SIZE],
            explicit: [0; IO_SIZE],
            changed: InputChanges::new(),
        }
    }

    /// The data of assembly `instance`, if it exists.
    fn data(&self, instance: u16) -> Option<&[u8]> {
        match instance {
            INPUT | OUTPUT => Some(&self.output),
            CONFIG => Some(&self.config),
            INPUT_ONLY_HEARTBEAT | LISTEN_ONLY_HEARTBEAT => Some(&[]),
            EXPLICIT => Some(&self.explicit),
            _ => None,
        }
    }
}

impl Default for Generic {
    fn default() -> Self {
        Self::new()
    }
}

impl Device for Generic {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }

    fn assemblies(&self) -> &[AssemblyInfo] {
        &ASSEMBLIES
    }

    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        // The I/O data whole (each T->O datagram) on a Cortex-M: see `copy_words`.
        #[cfg(target_arch = "arm")]
        if let (INPUT | OUTPUT, Some(dst)) = (instance, out.first_chunk_mut::<IO_SIZE>()) {
            copy_words(dst, &self.output);
            return Ok(IO_SIZE);
        }
        let data = self.data(instance).ok_or(unknown())?;
        let n = data.len().min(out.len());
        if let (Some(dst), Some(src)) = (out.get_mut(..n), data.get(..n)) {
            dst.copy_from_slice(src);
        }
        Ok(n)
    }

    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        match instance {
            OUTPUT => self.write_output(data),
            CONFIG => copy_exact(&mut self.config, data),
            EXPLICIT => copy_exact(&mut self.explicit, data),
            INPUT_ONLY_HEARTBEAT | LISTEN_ONLY_HEARTBEAT => copy_exact(&mut [], data),
            INPUT => Err(General::AttributeNotSettable.into()),
            _ => Err(unknown()),
        }
    }

    /// The echo of new outputs into [`INPUT`].
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        Some(&mut self.changed)
    }
}

impl Generic {
    /// New outputs (each O->T datagram), echoed into [`INPUT`] if they changed.
    #[cfg(not(target_arch = "arm"))]
    fn write_output(&mut self, data: &[u8]) -> CipResult {
        if data != self.output {
            copy_exact(&mut self.output, data)?;
            self.changed.mark(INPUT);
        }
        Ok(())
    }

    /// New outputs (each O->T datagram), echoed into [`INPUT`] if they changed; on a
    /// Cortex-M compared and copied by `copy_words`.
    #[cfg(target_arch = "arm")]
    fn write_output(&mut self, data: &[u8]) -> CipResult {
        match <&[u8; IO_SIZE]>::try_from(data) {
            Ok(new) => {
                if copy_words(&mut self.output, new) {
                    self.changed.mark(INPUT);
                }
                Ok(())
            }
            Err(_) => copy_exact(&mut self.output, data),
        }
    }
}

/// Copies `src` into `dst` 16 bytes at a time; true if that changed `dst`. For the I/O data
/// of every datagram on a Cortex-M, where the compiler calls the library's `memcpy` and
/// `memcmp` for 32 bytes at the frame's 2-byte alignment, several times the instructions of
/// these word moves; elsewhere it inlines the plain array operations as vector moves.
#[cfg(any(target_arch = "arm", test))]
#[inline(never)] // Shared by both paths, and never a bare copy that becomes `memcpy` again.
fn copy_words(dst: &mut [u8; IO_SIZE], src: &[u8; IO_SIZE]) -> bool {
    let mut changed = false;
    for (to, from) in dst
        .as_chunks_mut::<16>()
        .0
        .iter_mut()
        .zip(src.as_chunks::<16>().0)
    {
        let (old, new) = (u128::from_ne_bytes(*to), u128::from_ne_bytes(*from));
        changed |= old != new;
        *to = new.to_ne_bytes();
    }
    changed
}

/// Error for an assembly instance the device does not have.
const fn unknown() -> CipError {
    CipError::new(General::PathDestinationUnknown)
}

/// Replaces `dst` with `src`, which must have exactly its length.
fn copy_exact(dst: &mut [u8], src: &[u8]) -> CipResult {
    match src.len().cmp(&dst.len()) {
        core::cmp::Ordering::Less => Err(General::NotEnoughData.into()),
        core::cmp::Ordering::Greater => Err(General::TooMuchData.into()),
        core::cmp::Ordering::Equal => {
            dst.copy_from_slice(src);
            Ok(())
        }
    }
}
