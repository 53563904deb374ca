//! `enip-host`: the EtherNet/IP adapter on a Linux host, attached to an existing TAP device,
//! running one of the shipped device profiles.

use firmware::Profile;

/// How to invoke the program.
fn usage() -> String {
    format!(
        "usage: enip-host --tap IFNAME --ip A.B.C.D/LEN [--gateway A.B.C.D] [--profile NAME] \
         [--mac xx:xx:xx:xx:xx:xx] [--create-tap]\n\n\
         \x20 --profile NAME     device profile: {} (default: generic)\n{}",
        Profile::NAMES.join(", "),
        enip_host::OPTIONS_USAGE
    )
}

fn main() {
    let mut profile = Profile::default();
    let options = enip_host::Options::from_env_args(&usage(), |flag, value| {
        if flag != "--profile" {
            return Ok(false);
        }
        profile = Profile::from_name(&value).ok_or_else(|| {
            format!(
                "unknown profile {value:?} (known: {})",
                Profile::NAMES.join(", ")
            )
        })?;
        Ok(true)
    });
    enip_host::run(profile, options)
}
