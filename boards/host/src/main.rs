//! `enip-host`: the EtherNet/IP adapter on a Linux host, attached to an existing TAP device,
//! running one of the shipped device profiles; `enip-host --eds [--profile NAME]` prints the
//! profile's EDS file instead.

mod profile_options;

use std::process::exit;

use enip_profiles::Profile;
use profile_options::ProfileOptions;

/// How to invoke the program.
fn usage() -> String {
    format!(
        "usage: enip-host --tap IFNAME --ip A.B.C.D/LEN [--gateway A.B.C.D] [--profile NAME] \
         [--mac xx:xx:xx:xx:xx:xx] [--nv-file PATH] [--create-tap]\n       \
         enip-host --eds [--profile NAME]\n\n\
         \x20 --profile NAME     device profile: {} (default: generic)\n\
         \x20 --eds              print the profile's EDS file and exit (with --profile and\n\
         \x20                    the profile's options only)\n\
         \x20 --pls-rpm RPM      ametek-pls: speed of the simulated resolver (default 0)\n\
         \x20 --pls-resolver-fault on|off\n\
         \x20                    ametek-pls: the resolver reports a fault (default off)\n{}",
        Profile::NAMES.join(", "),
        enip_host::OPTIONS_USAGE
    )
}

/// The profile called `name`, or the error naming the known ones.
fn profile(name: &str) -> Result<Profile, String> {
    Profile::from_name(name).ok_or_else(|| {
        format!(
            "unknown profile {name:?} (known: {})",
            Profile::NAMES.join(", ")
        )
    })
}

fn main() {
    let mut chosen = Profile::default();
    let mut profile_options = ProfileOptions::default();
    let command = enip_host::Command::from_env_args(&usage(), |flag, value| {
        if flag != "--profile" {
            return profile_options.take(flag, &value);
        }
        chosen = profile(&value)?;
        Ok(true)
    });
    let options = match command {
        enip_host::Command::Run(options) => options,
        // `from_env_args` printed the usage and exited.
        enip_host::Command::Help => return,
        enip_host::Command::Eds => {
            let mut eds = String::new();
            if let Err(e) = chosen.write_eds(&mut eds) {
                eprintln!("enip-host: {e}");
                exit(1);
            }
            print!("{eds}");
            return;
        }
    };
    if let Err(e) =
        profile_options::set_up(&mut chosen, &profile_options, options.nv_file.as_deref())
    {
        eprintln!("enip-host: {e}");
        exit(1);
    }
    enip_host::run(chosen, options)
}
