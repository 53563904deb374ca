//! The profile options of the host board: `--nvram FILE` as the profile's non-volatile
//! memory (read at start, rewritten at every save) and `--pls-rpm` for the ametek-pls
//! profile's simulated resolver.

use std::path::PathBuf;
use std::sync::OnceLock;

use enip_firmware::profiles::ametek_pls::nvram::RamNvram;
use enip_firmware::profiles::AmetekPls;
use enip_firmware::Profile;

/// The file the store hook writes.
static NVRAM_FILE: OnceLock<PathBuf> = OnceLock::new();

/// The profile options of the command line.
#[derive(Debug, Default)]
pub struct ProfileOptions {
    /// `--nvram FILE`: the profile's non-volatile memory.
    pub nvram: Option<PathBuf>,
    /// `--pls-rpm RPM`: speed of the ametek-pls profile's simulated resolver.
    pub pls_rpm: u16,
}

impl ProfileOptions {
    /// Takes `flag value` if it is one of these options.
    pub fn take(&mut self, flag: &str, value: &str) -> Result<bool, String> {
        match flag {
            "--nvram" => self.nvram = Some(PathBuf::from(value)),
            "--pls-rpm" => {
                self.pls_rpm = value
                    .parse()
                    .map_err(|_| format!("bad --pls-rpm {value:?} (0 to 65535)"))?
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Applies the profile options to `profile`.
pub fn set_up(profile: &mut Profile, options: &ProfileOptions) -> Result<(), String> {
    let Profile::AmetekPls(pls) = profile else {
        return Ok(());
    };
    if let Some(path) = &options.nvram {
        let image = match std::fs::read(path) {
            Ok(bytes) => Some(bytes),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(format!("--nvram {}: {e}", path.display())),
        };
        let _ = NVRAM_FILE.set(path.clone());
        let nvram = RamNvram::with_image(image.as_deref(), Some(store));
        *pls = AmetekPls::with_nvram(nvram);
        log::info!(
            "ametek-pls: NVRAM in {} ({})",
            path.display(),
            if image.is_some() { "loaded" } else { "empty" }
        );
    }
    pls.set_resolver(options.pls_rpm, false);
    Ok(())
}

/// Writes the image to the `--nvram` file (through a temporary file, then a rename).
fn store(image: &[u8]) -> bool {
    let Some(path) = NVRAM_FILE.get() else {
        return false;
    };
    let tmp = path.with_extension("tmp");
    let ok = std::fs::write(&tmp, image).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = &ok {
        log::error!("NVRAM {}: {e}", path.display());
    }
    ok.is_ok()
}
