//! `cargo xtask`: the project's commands.
//!
//! - `setup`: installs what the tests need (Rust target and nightly, cargo-fuzz, Debian
//!   packages, pinned Python and npm peers under `target/`).
//! - `test`: the whole suite, stopping at the first failure, with a summary.
//! - `fuzz [--seconds N]`: every fuzz target for N seconds (default 60).
//! - `qemu [--profile NAME]`: the emulated board (QEMU mps2-an386) in a network namespace.
//! - `demo [--host]`: the emulated board (or the host board) read by scanners: identity and
//!   a live Class 1 view.
//! - `bench`: benchmarks, written to `target/bench/report.json`, and the boards' footprint,
//!   written to `target/bench/footprint.json` (`footprint` alone).
//! - `smoke`: the QEMU smoke run of `test`, alone.

mod bench;
mod bench_host;
mod boards;
mod demo;
mod footprint;
mod fuzz;
mod json;
mod netns;
mod qemu;
mod setup;
mod smoke;
mod test;
mod util;
mod workspace;

use std::process::ExitCode;

const USAGE: &str = "\
usage: cargo xtask <command>

commands:
  setup               install what the tests need (idempotent)
  test                fmt, clippy, doc, tests, no_std builds, fuzz (5 s each), TAP interop
  fuzz [--seconds N]  run every fuzz target for N seconds each (default 60)
  qemu [--profile NAME]
                      boot the emulated board (QEMU mps2-an386) in netns enip-qemu until Ctrl-C
  demo [--host]       boot the emulated board (--host: the Linux host board) in netns
                      enip-demo; show its identity and a live Class 1 connection
  bench               boards' footprint; Class 1 cycle cost (callgrind, native) and
                      10 x 1 ms I/O on the host TAP; and bench --host
  bench --host        the host adapter process per Class 1 cycle (instructions, context
                      switches) and requests/s, TAP vs kernel sockets (vs OpENer when
                      ENIP_OPENER_BIN names its POSIX build)
  footprint           the boards' release image sizes and the F767 budget (part of bench)
  smoke               the QEMU smoke run alone (part of test)
  eds                 regenerate eds/<profile>.eds from every profile's own description
                      (`cargo run -p enip-host -- --eds --profile NAME` prints one)
";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args.as_slice() {
        ["setup"] => setup::all(),
        ["test"] => {
            return if test::run_all() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            };
        }
        ["fuzz", rest @ ..] => match parse_seconds(rest) {
            Ok(seconds) => fuzz::run_all(seconds).map(|_| ()),
            Err(e) => Err(e),
        },
        ["qemu"] => qemu::run_interactive(boards::DEFAULT_PROFILE),
        ["qemu", "--profile", name] => qemu::run_interactive(name),
        ["demo"] => demo::run_demo(demo::Board::Qemu),
        ["demo", "--host"] => demo::run_demo(demo::Board::Host),
        ["bench"] => bench::run_all(),
        ["bench", "--host"] => bench_host::run_all(),
        ["footprint"] => footprint::footprint(),
        ["smoke"] => smoke::run_smoke().map(|_| ()),
        // The firmware's EDS test knows every profile; asked to, it rewrites the files.
        ["eds"] => util::run(
            util::cargo()
                .args(["test", "every_eds_file_is_current"])
                .env("UPDATE_EDS", "1"),
        ),
        ["help" | "-h" | "--help"] => {
            print!("{USAGE}");
            Ok(())
        }
        _ => {
            eprint!("{USAGE}");
            return ExitCode::from(2);
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

/// `--seconds N` (or nothing, for the default).
fn parse_seconds(args: &[&str]) -> util::Result<u64> {
    match args {
        [] => Ok(fuzz::DEFAULT_SECONDS),
        ["--seconds", n] => n
            .parse()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| util::Error(format!("--seconds wants a positive number, not {n:?}"))),
        _ => util::err(format!("unexpected arguments {args:?}\n{USAGE}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seconds_argument() {
        assert_eq!(parse_seconds(&[]).unwrap(), fuzz::DEFAULT_SECONDS);
        assert_eq!(parse_seconds(&["--seconds", "5"]).unwrap(), 5);
        assert!(parse_seconds(&["--seconds", "0"]).is_err());
        assert!(parse_seconds(&["--seconds", "x"]).is_err());
        assert!(parse_seconds(&["--seconds"]).is_err());
        assert!(parse_seconds(&["-s", "5"]).is_err());
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
        let manifest = std::fs::read_to_string(util::root().join("fuzz/Cargo.toml")).unwrap();
        let targets = fuzz::targets().unwrap();
        for t in &targets {
            let entry = format!("name = \"{t}\"\npath = \"fuzz_targets/{t}.rs\"");
            assert!(
                manifest.contains(&entry),
                "fuzz/Cargo.toml has no [[bin]] {t}"
            );
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
