//! `enip-host`: the EtherNet/IP adapter on a Linux host, attached to an existing TAP device,
//! running one of the shipped device profiles; `enip-host --devices FILE` runs the devices of
//! a device list on the kernel's sockets; `enip-host --eds [--profile NAME]` prints the
//! profile's EDS file instead.

mod fleet_setup;
mod profile_options;

use std::process::exit;

use enip_profiles::Profile;
use profile_options::ProfileOptions;

/// How to invoke the program.
fn usage() -> String {
    format!(
        "usage: enip-host --tap IFNAME --ip A.B.C.D/LEN [--gateway A.B.C.D] [--profile NAME] \
         [--mac xx:xx:xx:xx:xx:xx] [--nv-file PATH] [--create-tap]\n       \
         enip-host --devices FILE\n       \
         enip-host --eds [--profile NAME]\n\n\
         \x20 --profile NAME     device profile: {} (default: generic)\n\
         \x20 --eds              print the profile's EDS file and exit (with --profile and\n\
         \x20                    the profile's options only)\n\
         \x20 --devices FILE     run every device of the device list FILE (TOML: one\n\
         \x20                    [[device]] table each, with address, profile, serial_number,\n\
         \x20                    product_name, nv_file, name, count) on the kernel's sockets\n\
         \x20                    at its own address, in this one process\n\
         \x20 --pls-rpm RPM      ametek-pls: speed of the simulated resolver (default 0)\n\
         \x20 --pls-resolver-fault on|off\n\
         \x20                    ametek-pls: the resolver reports a fault (default off)\n{}",
        Profile::NAMES.join(", "),
        enip_host::OPTIONS_USAGE
    )
}

/// The profile called `name`, or the error naming the known ones.
pub(crate) fn profile(name: &str) -> Result<Profile, String> {
    Profile::from_name(name).ok_or_else(|| {
        format!(
            "unknown profile {name:?} (known: {})",
            Profile::NAMES.join(", ")
        )
    })
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().is_some_and(|a| a == "--devices") {
        let devices = match &args[..] {
            [_, path] => fleet_setup::devices(path),
            _ => Err("--devices takes only the device list's path".into()),
        };
        match devices {
            Ok(devices) => enip_host::run_fleet(devices),
            Err(e) => {
                eprintln!("enip-host: {e}\n\n{}", usage());
                exit(2);
            }
        }
    }
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
    match enip_host::shared_store(options.nv_file.as_deref()) {
        Ok(store) => profile_options::set_up(&mut chosen, &profile_options, store),
        Err(e) => {
            eprintln!("enip-host: {e}");
            exit(1);
        }
    }
    enip_host::run(chosen, options)
}
