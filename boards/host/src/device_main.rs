//! [`run_device`] and [`Command`]: the whole `main` of a device program, `--eds` included.

use std::process::exit;

use enip_stack::eds::{write_eds, EdsInfo};
use enip_stack::Device;

use crate::{program_name, run, Options, Parsed, OPTIONS_USAGE};

/// What a device program's command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Run the adapter with these options.
    Run(Options),
    /// `--eds`: print the device's EDS file and exit (no network options needed).
    Eds,
    /// `--help`: print the usage and exit.
    Help,
}

impl Command {
    /// Parses the arguments after the program name: `--eds` anywhere asks for the EDS, and
    /// then only options `extra` takes may come with it (e.g. `--profile NAME`, choosing
    /// which device); otherwise as [`Options::parse`] (`--tap` and `--ip`, or `--bind`,
    /// required).
    pub fn parse(
        args: impl Iterator<Item = String>,
        mut extra: impl FnMut(&str, String) -> Result<bool, String>,
    ) -> Result<Command, String> {
        let args: Vec<String> = args.collect();
        if args.is_empty() {
            return Err(
                "say where to run (--tap IFNAME --ip A.B.C.D/LEN, or --bind \
                        A.B.C.D) or ask for the EDS (--eds)"
                    .into(),
            );
        }
        if !args.iter().any(|a| a == "--eds") {
            return Ok(match Options::parse(args.into_iter(), extra)? {
                Parsed::Run(options) => Command::Run(options),
                Parsed::Help => Command::Help,
            });
        }
        let mut rest = args.into_iter().filter(|a| a != "--eds");
        while let Some(flag) = rest.next() {
            if flag == "-h" || flag == "--help" {
                return Ok(Command::Help);
            }
            let taken = match rest.next() {
                Some(value) => extra(&flag, value)?,
                None => false,
            };
            if !taken {
                return Err(format!(
                    "--eds takes no {flag} (only the device's own options)"
                ));
            }
        }
        Ok(Command::Eds)
    }

    /// The command of this process's command line (`extra` as in [`Command::parse`]); on
    /// `--help` prints `usage` and exits 0, on an error prints it with `usage` and exits 2.
    pub fn from_env_args(
        usage: &str,
        extra: impl FnMut(&str, String) -> Result<bool, String>,
    ) -> Command {
        match Command::parse(std::env::args().skip(1), extra) {
            Ok(Command::Help) => {
                println!("{usage}");
                exit(0);
            }
            Ok(command) => command,
            Err(e) => {
                eprintln!("{}: {e}\n\n{usage}", program_name());
                exit(2);
            }
        }
    }
}

/// The usage of a program made by [`run_device`].
pub fn device_usage() -> String {
    let p = program_name();
    format!(
        "usage: {p} --tap IFNAME --ip A.B.C.D/LEN [options]\n       \
         {p} --bind A.B.C.D [options]\n       {p} --eds\n\n\
         \x20 --eds              print the device's EDS file and exit\n{OPTIONS_USAGE}"
    )
}

/// The whole `main` of a device program: `--eds` prints the EDS file of `device` described
/// by `eds` and exits 0; `--help` prints [`device_usage`]; anything else is the options of
/// [`run`], which runs `device` until SIGINT or SIGTERM. A bad command line exits 2.
pub fn run_device<D: Device + 'static>(device: D, eds: &EdsInfo<'_>) -> ! {
    match Command::from_env_args(&device_usage(), |_, _| Ok(false)) {
        Command::Run(options) => run(device, options),
        Command::Help => exit(0),
        Command::Eds => {
            let mut file = String::new();
            if write_eds(&mut file, &device, eds).is_err() {
                eprintln!(
                    "{}: the EDS cannot be written (a parameter of a type without a fixed \
                     size?)",
                    program_name()
                );
                exit(1);
            }
            print!("{file}");
            exit(0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parses `args`, taking `--profile NAME`.
    fn parse(args: &[&str]) -> Result<Command, String> {
        let profile = |flag: &str, _: String| Ok(flag == "--profile");
        Command::parse(args.iter().map(|s| s.to_string()), profile)
    }

    #[test]
    fn eds_needs_no_network_options() {
        assert_eq!(parse(&["--eds"]), Ok(Command::Eds));
        assert_eq!(parse(&["--profile", "x", "--eds"]), Ok(Command::Eds));
        assert_eq!(parse(&["--eds", "--profile", "x"]), Ok(Command::Eds));
        assert_eq!(parse(&["--eds", "--help"]), Ok(Command::Help));
        assert!(parse(&["--eds", "--tap", "t"]).is_err());
        assert!(parse(&["--eds", "--profile"]).is_err());
        assert!(parse(&["--eds", "--create-tap"]).is_err());
    }

    #[test]
    fn without_eds_the_network_options_are_required() {
        assert!(parse(&[]).is_err());
        assert!(parse(&["--tap", "t"]).is_err());
        assert!(matches!(
            parse(&["--tap", "t", "--ip", "198.18.0.2/24"]),
            Ok(Command::Run(_))
        ));
        assert!(matches!(
            parse(&["--bind", "198.18.0.2"]),
            Ok(Command::Run(_))
        ));
        assert_eq!(parse(&["-h"]), Ok(Command::Help));
    }
}
