//! The device's own clock: calls [`stack::Device::poll`] at the instant it asks for (a
//! simulated drive's control tick), and triggers application-triggered production when an
//! input assembly's data changed since the previous poll.

use embassy_time::Timer;
use stack::config::MAX_ASSEMBLY_SIZE;
use stack::{Adapter, AssemblyRole, Device};

use crate::clock::{now, to_embassy};
use crate::shared::{with_adapter, SharedAdapter};

/// Input assemblies whose changes are watched (the rest are never triggered).
const WATCHED: usize = 8;

/// Runs the device's clock forever; a device that never asks to be polled again is left
/// alone.
pub(crate) async fn serve<D: Device>(adapter: &SharedAdapter<D>) -> ! {
    let mut watch = InputWatch::new();
    loop {
        let next = with_adapter(adapter, |a| {
            let next = a.device_mut().poll(now());
            watch.trigger_changed(a);
            next
        });
        match next {
            Some(at) => Timer::at(to_embassy(at)).await,
            None => core::future::pending::<()>().await,
        }
    }
}

/// A digest of each input assembly's data at the previous poll.
struct InputWatch {
    digests: heapless::Vec<(u16, u32), WATCHED>,
}

impl InputWatch {
    const fn new() -> Self {
        InputWatch {
            digests: heapless::Vec::new(),
        }
    }

    /// Calls [`Adapter::trigger_input`] for every input assembly whose data changed.
    fn trigger_changed<D: Device>(&mut self, a: &mut Adapter<D>) {
        let mut buf = [0u8; MAX_ASSEMBLY_SIZE];
        for i in 0..a.device().assemblies().len() {
            let Some(info) = a.device().assemblies().get(i).copied() else {
                break;
            };
            if info.role != AssemblyRole::Input {
                continue;
            }
            let out = buf.get_mut(..usize::from(info.size)).unwrap_or(&mut []);
            let Ok(n) = a.device_mut().read_assembly(info.instance, out) else {
                continue;
            };
            let digest = fnv1a(out.get(..n).unwrap_or(&[]));
            match self.digests.iter_mut().find(|(id, _)| *id == info.instance) {
                Some((_, old)) if *old == digest => {}
                Some((_, old)) => {
                    *old = digest;
                    a.trigger_input(info.instance);
                }
                // The first sight of an assembly only records it; a full list stops watching.
                None => {
                    let _ = self.digests.push((info.instance, digest));
                }
            }
        }
    }
}

/// 32-bit FNV-1a: a cheap digest to notice that data changed.
fn fnv1a(data: &[u8]) -> u32 {
    data.iter().fold(0x811C_9DC5, |h, &b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digest_notices_changes() {
        assert_eq!(fnv1a(&[]), 0x811C_9DC5);
        assert_ne!(fnv1a(&[0, 1]), fnv1a(&[1, 0]));
        assert_eq!(fnv1a(b"a"), 0xE40C_292C);
    }
}
