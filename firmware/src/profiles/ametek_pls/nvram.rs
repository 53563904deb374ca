//! Non-volatile storage of the program (§2.9: "save the current settings to NVRAM"):
//! [`Nvram`] is what the profile needs from it; [`RamNvram`] keeps the image in RAM, with an
//! optional hook a board uses to copy it to a file or flash.

use super::config::{CONFIG_BYTES, GROUPS};

/// Bytes of the saved image: attributes 1-35 and 38, then the 8 group offsets.
pub const IMAGE_BYTES: usize = CONFIG_BYTES + 2 * GROUPS;

/// Why the image could not be stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StoreError;

/// Non-volatile storage of one program image.
pub trait Nvram {
    /// The saved image, if one was saved.
    fn load(&self) -> Option<&[u8; IMAGE_BYTES]>;
    /// Saves `image`.
    fn store(&mut self, image: &[u8; IMAGE_BYTES]) -> Result<(), StoreError>;
    /// Forgets the saved image (factory defaults).
    fn clear(&mut self);
}

/// A board's copy of the image to its own medium; `false` if it failed.
pub type StoreHook = fn(&[u8]) -> bool;

/// An [`Nvram`] in RAM (host and QEMU boards); a board may add a [`StoreHook`] so the image
/// also survives a restart (the host board's `--nvram FILE`).
#[derive(Debug, Clone)]
pub struct RamNvram {
    image: [u8; IMAGE_BYTES],
    saved: bool,
    hook: Option<StoreHook>,
}

impl RamNvram {
    /// An empty store: the module powers up with its defaults.
    pub const fn new() -> Self {
        RamNvram {
            image: [0; IMAGE_BYTES],
            saved: false,
            hook: None,
        }
    }

    /// A store holding `image` (as a board read it back), if it has the right size, whose
    /// saves also go to `hook`.
    pub fn with_image(image: Option<&[u8]>, hook: Option<StoreHook>) -> Self {
        let mut nv = RamNvram::new();
        nv.hook = hook;
        if let Some(bytes) = image.and_then(|i| <&[u8; IMAGE_BYTES]>::try_from(i).ok()) {
            nv.image = *bytes;
            nv.saved = true;
        }
        nv
    }
}

/// Two stores are equal when they hold the same image (the hook is not compared).
impl PartialEq for RamNvram {
    fn eq(&self, other: &Self) -> bool {
        self.load() == other.load()
    }
}

impl Eq for RamNvram {}

impl Default for RamNvram {
    fn default() -> Self {
        Self::new()
    }
}

impl Nvram for RamNvram {
    fn load(&self) -> Option<&[u8; IMAGE_BYTES]> {
        self.saved.then_some(&self.image)
    }

    fn store(&mut self, image: &[u8; IMAGE_BYTES]) -> Result<(), StoreError> {
        if let Some(hook) = self.hook {
            if !hook(image) {
                return Err(StoreError);
            }
        }
        self.image = *image;
        self.saved = true;
        Ok(())
    }

    fn clear(&mut self) {
        self.saved = false;
    }
}
