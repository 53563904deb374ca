//! The profile options of the host board: `--pls-rpm` and `--pls-resolver-fault` for the
//! ametek-pls profile's simulated resolver; and every profile's saved settings kept in the
//! adapter's non-volatile store (`--nv-file`).

use enip_profiles::Profile;
use enip_stack::nv::SharedStore;

/// The profile options of the command line.
#[derive(Debug, Default)]
pub struct ProfileOptions {
    /// `--pls-rpm RPM`: speed of the ametek-pls profile's simulated resolver (else the
    /// speed built in, `ENIP_PLS_RPM`, 0 by default).
    pub pls_rpm: Option<u16>,
    /// `--pls-resolver-fault on|off`: the simulated resolver reports a fault.
    pub pls_resolver_fault: bool,
}

impl ProfileOptions {
    /// Takes `flag value` if it is one of these options.
    pub fn take(&mut self, flag: &str, value: &str) -> Result<bool, String> {
        match flag {
            "--pls-rpm" => {
                self.pls_rpm = Some(
                    value
                        .parse()
                        .map_err(|_| format!("bad --pls-rpm {value:?} (0 to 65535)"))?,
                )
            }
            "--pls-resolver-fault" => {
                self.pls_resolver_fault = match value {
                    "on" => true,
                    "off" => false,
                    _ => return Err(format!("bad --pls-resolver-fault {value:?} (on or off)")),
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Powers `profile` up from its records in `store` and applies the profile options.
pub fn set_up(profile: &mut Profile, options: &ProfileOptions, store: SharedStore) {
    profile.attach_store(store);
    if let Profile::AmetekPls(pls) = profile {
        let rpm = options.pls_rpm.unwrap_or(pls.engine().rpm());
        pls.set_resolver(rpm, options.pls_resolver_fault);
    }
}
