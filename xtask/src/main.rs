//! `cargo xtask`: the project's commands.
//!
//! - `setup`: installs what the tests need (Rust target and nightly, cargo-fuzz, Debian
//!   packages, pinned Python and npm peers under `target/`).
//! - `test`: the whole suite, stopping at the first failure, with a summary.
//! - `fuzz [--seconds N]`: every fuzz target for N seconds (default 60); `fuzz --campaign
//!   MINUTES`: a long run that merges new coverage into the seeds.
//! - `qemu [--profile NAME] [--machine NAME]`: the emulated board (QEMU mps2-an386, or
//!   another core's machine) in a network namespace.
//! - `demo [--host]`: the emulated board (or the host board) read by scanners: identity and
//!   a live Class 1 view.
//! - `bench`: benchmarks, written to `target/bench/report.json`, and the boards' footprint,
//!   written to `target/bench/footprint.json` (`footprint` alone).
//! - `smoke`: the QEMU smoke run of `test`, alone.
//! - `faults`: the long fault tests, written to `target/faults/report.json` (not in `test`);
//!   `faults --chaos MINUTES [--seed S]`: the chaos soak, written to `target/bench/chaos.json`.
//! - `stack`: the emulated board's call stack after each profile's tests, and the margin on
//!   the NUCLEO-F767ZI, written to `target/bench/stack.json` (not in `test`).

#![forbid(unsafe_code)]

mod bench;
mod bench_fleet;
mod bench_fleet_opener;
mod bench_host;
mod bench_qemu;
mod bench_qemu_paths;
mod bench_qemu_trace;
mod bench_scale;
mod boards;
mod chaos;
mod demo;
mod faults;
mod footprint;
mod fuzz;
mod json;
mod module_graph;
mod own_device;
mod qemu;
mod qemu_cores;
mod setup;
mod smoke;
mod stack;
mod test;
mod util;
mod workspace;

use std::ffi::OsString;
use std::process::ExitCode;

const USAGE: &str = "\
usage: cargo xtask <command>

commands:
  setup               install what the tests need (idempotent)
  test                fmt, clippy, doc, tests, no_std builds, fuzz (5 s each), TAP interop
  fuzz [--seconds N]  run every fuzz target for N seconds each (default 60)
  fuzz --campaign MINUTES
                      every target in turn for a share of MINUTES; merge new coverage into
                      the committed seeds; report in target/fuzz-logs/campaign.md
  qemu [--profile NAME] [--machine an385|an500|an505]
                      boot the emulated board (QEMU mps2-an386, or the M3, M7 or M33 machine)
                      in netns enip-qemu until Ctrl-C
  demo [--host]       boot the emulated board (--host: the Linux host board) in netns
                      enip-demo; show its identity and a live Class 1 connection
  bench [--qemu | --host | --check | --fleet [--seconds S] [--devices N]]
                      boards' footprint; Class 1 cycle cost (callgrind, native) and
                      10 x 1 ms I/O on the host TAP; the emulated board's instructions per
                      cycle and 10 x 1 ms / 2 ms I/O (--qemu: that part alone); the host
                      adapter process per Class 1 cycle (instructions, context switches) and
                      requests/s, TAP vs kernel sockets, vs OpENer when ENIP_OPENER_BIN names
                      its POSIX build (--host: that part alone); --check: every part once and
                      briefly into target/bench-check, checking that each figure is reported
                      (a step of test); --fleet: that part alone, N = 1, 16, 64, 128, 256
                      devices in one enip-host --devices process (up to --devices N), an owner
                      at 10 ms and an explicit request a second on each, S s each (default 30)
  modules             the module check: no cycle among the stack's modules, the profiles
                      or the files of one profile (part of test)
  footprint           the boards' release image sizes and their budgets (part of bench)
  smoke               the QEMU smoke run alone (part of test)
  faults              the long fault tests (link flap, Reset, churn, idle sockets, vanishing
                      scanner, 10-minute soak, floods); figures in target/faults/report.json
                      (ENIP_FAULTS_FILTER=faults_flood: the floods alone)
  faults --chaos MINUTES [--seed S]
                      the chaos soak: seeded random faults over 1 ms I/O for MINUTES
                      minutes, invariants checked; report in target/bench/chaos.json
  stack               the emulated board's call stack high-water mark after the TAP tests
                      each profile can run on it; worst depth per profile and the margin on
                      the NUCLEO-F767ZI; figures in target/bench/stack.json
  eds                 regenerate eds/<profile>.eds from every profile's own description
                      (`cargo run -p enip-host -- --eds --profile NAME` prints one)
  own-device          build examples/own-device in a project of its own outside the
                      workspace from the README's snippets, and check its EDS (part of test)
";

/// Which benchmarks `bench` runs.
#[derive(Debug, PartialEq, Eq)]
enum BenchPart {
    /// Every one, with the footprint.
    All,
    /// The emulated Cortex-M board's Class 1 cycle only.
    Qemu,
    /// The host adapter processes (TAP and kernel sockets, OpENer) only.
    Host,
    /// Every one, briefly, into target/bench-check: that the benchmark runs.
    Check,
    /// The fleet of devices in one process, up to `max_devices`, `seconds` per size.
    Fleet { seconds: u64, max_devices: u32 },
}

/// A command line, parsed.
#[derive(Debug, PartialEq, Eq)]
enum Command {
    Setup,
    Test,
    Fuzz {
        seconds: u64,
    },
    Campaign {
        minutes: u64,
    },
    Qemu {
        profile: String,
        machine: Option<String>,
    },
    Demo {
        board: demo::Board,
    },
    Bench {
        part: BenchPart,
    },
    Footprint,
    Modules,
    Smoke,
    Faults,
    Stack,
    Chaos {
        minutes: u64,
        seed: Option<u64>,
    },
    Eds,
    OwnDevice,
    Help,
}

fn main() -> ExitCode {
    let command = match parse(std::env::args_os().skip(1)) {
        Ok(c) => c,
        Err(e) => {
            eprint!("error: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let result = match command {
        Command::Setup => setup::all(),
        Command::Test => {
            return if test::run_all() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            };
        }
        Command::Fuzz { seconds } => fuzz::run_all(seconds).map(|_| ()),
        Command::Campaign { minutes } => fuzz::campaign(minutes),
        Command::Qemu { profile, machine } => qemu::run_interactive(&profile, machine.as_deref()),
        Command::Demo { board } => demo::run_demo(board),
        Command::Bench {
            part: BenchPart::All,
        } => bench::run_all(bench_scale::Scale::Full),
        Command::Bench {
            part: BenchPart::Check,
        } => bench::check(),
        Command::Bench {
            part: BenchPart::Qemu,
        } => bench_qemu::run_alone(),
        Command::Bench {
            part: BenchPart::Host,
        } => bench_host::run_all(),
        Command::Bench {
            part:
                BenchPart::Fleet {
                    seconds,
                    max_devices,
                },
        } => bench_fleet::run_all(seconds, max_devices),
        Command::Footprint => footprint::footprint(),
        Command::Modules => module_graph::check(),
        Command::Smoke => smoke::run_smoke().map(|_| ()),
        Command::Faults => faults::run_all(),
        Command::Stack => stack::run_all(),
        Command::Chaos { minutes, seed } => chaos::run_chaos(minutes, seed),
        // The profiles' EDS test knows every profile; asked to, it rewrites the files.
        Command::Eds => util::run(
            util::cargo()
                .args(["test", "every_eds_file_is_current"])
                .env("UPDATE_EDS", "1"),
        ),
        Command::OwnDevice => own_device::run_check().map(|_| ()),
        Command::Help => {
            print!("{USAGE}");
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Parses the arguments after `cargo xtask`.
fn parse(args: impl IntoIterator<Item = impl Into<OsString>>) -> Result<Command, lexopt::Error> {
    use lexopt::prelude::*;
    let mut parser = lexopt::Parser::from_args(args);
    let name = match parser.next()? {
        Some(Value(name)) => name.string()?,
        Some(Short('h') | Long("help")) => return Ok(Command::Help),
        Some(other) => return Err(other.unexpected()),
        None => return Err("no command given".into()),
    };
    let mut command = match name.as_str() {
        "setup" => Command::Setup,
        "test" => Command::Test,
        "fuzz" => Command::Fuzz {
            seconds: fuzz::DEFAULT_SECONDS,
        },
        "qemu" => Command::Qemu {
            profile: boards::DEFAULT_PROFILE.to_string(),
            machine: None,
        },
        "demo" => Command::Demo {
            board: demo::Board::Qemu,
        },
        "bench" => Command::Bench {
            part: BenchPart::All,
        },
        "footprint" => Command::Footprint,
        "modules" => Command::Modules,
        "smoke" => Command::Smoke,
        "faults" => Command::Faults,
        "stack" => Command::Stack,
        "eds" => Command::Eds,
        "own-device" => Command::OwnDevice,
        "help" => Command::Help,
        _ => return Err(format!("unknown command {name:?}").into()),
    };
    while let Some(arg) = parser.next()? {
        match (&mut command, arg) {
            (Command::Fuzz { .. }, Long("campaign")) => {
                let minutes = fuzz::parse_minutes(&parser.value()?.string()?);
                command = Command::Campaign {
                    minutes: minutes.map_err(|e| e.0)?,
                };
            }
            (Command::Fuzz { seconds }, Long("seconds")) => {
                *seconds = parser.value()?.parse()?;
                if *seconds == 0 {
                    return Err("--seconds wants a positive number".into());
                }
            }
            (Command::Faults, Long("chaos")) => {
                let minutes = parser.value()?.parse()?;
                if minutes == 0 {
                    return Err("--chaos wants a positive number of minutes".into());
                }
                command = Command::Chaos {
                    minutes,
                    seed: None,
                };
            }
            (Command::Chaos { seed, .. }, Long("seed")) => *seed = Some(parser.value()?.parse()?),
            (Command::Qemu { profile, .. }, Long("profile")) => {
                *profile = parser.value()?.string()?
            }
            (Command::Qemu { machine, .. }, Long("machine")) => {
                *machine = Some(parser.value()?.string()?)
            }
            (Command::Demo { board }, Long("host")) => *board = demo::Board::Host,
            (Command::Bench { part }, Long("qemu")) => *part = BenchPart::Qemu,
            (Command::Bench { part }, Long("host")) => *part = BenchPart::Host,
            (Command::Bench { part }, Long("check")) => *part = BenchPart::Check,
            (Command::Bench { part }, Long("fleet")) => {
                *part = BenchPart::Fleet {
                    seconds: bench_fleet::SECONDS,
                    max_devices: bench_fleet::SIZES[bench_fleet::SIZES.len() - 1],
                }
            }
            (
                Command::Bench {
                    part: BenchPart::Fleet { seconds, .. },
                },
                Long("seconds"),
            ) => {
                *seconds = parser.value()?.parse()?;
                if *seconds == 0 {
                    return Err("--seconds wants a positive number".into());
                }
            }
            (
                Command::Bench {
                    part: BenchPart::Fleet { max_devices, .. },
                },
                Long("devices"),
            ) => *max_devices = parser.value()?.parse()?,
            (_, other) => return Err(other.unexpected()),
        }
    }
    Ok(command)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn command_lines() {
        let p = |args: &[&str]| parse(args.iter().copied());
        let fuzz = |seconds| Command::Fuzz { seconds };
        assert_eq!(p(&["fuzz"]).unwrap(), fuzz(fuzz::DEFAULT_SECONDS));
        assert_eq!(p(&["fuzz", "--seconds", "5"]).unwrap(), fuzz(5));
        assert!(p(&["fuzz", "--seconds", "0"]).is_err());
        assert!(p(&["fuzz", "--seconds", "x"]).is_err());
        assert!(p(&["fuzz", "--seconds"]).is_err());
        assert!(p(&["fuzz", "-s", "5"]).is_err());
        assert_eq!(
            p(&["fuzz", "--campaign", "30"]).unwrap(),
            Command::Campaign { minutes: 30 }
        );
        assert!(p(&["fuzz", "--campaign", "0"]).is_err());
        assert!(p(&["fuzz", "--campaign", "30", "--seconds", "5"]).is_err());
        assert_eq!(
            p(&["qemu", "--profile", "parker-ipa"]).unwrap(),
            Command::Qemu {
                profile: "parker-ipa".into(),
                machine: None,
            }
        );
        assert_eq!(
            p(&["qemu", "--machine", "an505"]).unwrap(),
            Command::Qemu {
                profile: boards::DEFAULT_PROFILE.into(),
                machine: Some("an505".into()),
            }
        );
        assert_eq!(
            p(&["demo", "--host"]).unwrap(),
            Command::Demo {
                board: demo::Board::Host
            }
        );
        assert!(p(&["demo", "--seconds", "5"]).is_err());
        assert!(p(&["test", "extra"]).is_err());
        assert!(p(&["nothing"]).is_err());
        assert!(p(&[]).is_err());
        assert_eq!(p(&["--help"]).unwrap(), Command::Help);
        assert_eq!(p(&["smoke"]).unwrap(), Command::Smoke);
        let chaos = |minutes, seed| Command::Chaos { minutes, seed };
        assert_eq!(p(&["faults", "--chaos", "30"]).unwrap(), chaos(30, None));
        assert_eq!(
            p(&["faults", "--chaos", "1", "--seed", "42"]).unwrap(),
            chaos(1, Some(42))
        );
        assert!(p(&["faults", "--chaos", "0"]).is_err());
        assert!(p(&["faults", "--seed", "42"]).is_err());
        let fleet = |seconds, max_devices| Command::Bench {
            part: BenchPart::Fleet {
                seconds,
                max_devices,
            },
        };
        assert_eq!(p(&["bench", "--fleet"]).unwrap(), fleet(30, 256));
        assert_eq!(
            p(&["bench", "--fleet", "--seconds", "3", "--devices", "16"]).unwrap(),
            fleet(3, 16)
        );
        assert!(p(&["bench", "--seconds", "3"]).is_err());
        assert!(p(&["bench", "--fleet", "--seconds", "0"]).is_err());
    }

    #[test]
    fn every_fuzz_target_has_seeds() {
        let seeds = util::root().join("fuzz/corpus/seed");
        let targets = fuzz::targets().unwrap();
        assert!(targets.len() >= 9, "{targets:?}");
        for t in targets {
            let n = std::fs::read_dir(seeds.join(&t)).map_or(0, |d| d.count());
            assert!(n > 0, "fuzz target {t} has no seed in fuzz/corpus/seed/{t}");
        }
    }

    /// `cargo fuzz run` needs a `[[bin]]` for every file in `fuzz/fuzz_targets/` (the
    /// per-profile targets included), or `cargo xtask fuzz` fails on it.
    #[test]
    fn every_fuzz_target_is_a_fuzz_crate_bin() {
        let bins = workspace::Metadata::read_manifest(Some("fuzz/Cargo.toml"))
            .unwrap()
            .bins();
        let targets = fuzz::targets().unwrap();
        for t in &targets {
            let path = util::root().join(format!("fuzz/fuzz_targets/{t}.rs"));
            let bin = (t.clone(), path.to_string_lossy().into_owned());
            assert!(bins.contains(&bin), "fuzz/Cargo.toml has no [[bin]] {t}");
        }
        for p in [
            "position_servo",
            "parker_ipa",
            "ametek_pls",
            "kollmorgen_akd",
        ] {
            let t = format!("profile_{p}");
            assert!(targets.contains(&t), "no fuzz target {t}");
        }
    }

    #[test]
    fn summary_counts() {
        let mut s = util::Steps::default();
        assert!(s.run("a", || Ok(util::Outcome::Passed)));
        assert!(s.run("b", || Ok(util::Outcome::Skipped)));
        assert!(s.summary());
        assert!(!s.run("c", || util::err("boom")));
        assert!(!s.summary());
    }
}
