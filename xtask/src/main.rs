//! `cargo xtask`: the project's commands.
//!
//! - `setup`: installs what the tests need (Rust target and nightly, cargo-fuzz, Debian
//!   packages, pinned Python and npm peers under `target/`).
//! - `test`: the whole suite, stopping at the first failure, with a summary.
//! - `fuzz [--seconds N]`: every fuzz target for N seconds (default 60).
//! - `demo`: the host board in a network namespace, read by a scanner.

mod demo;
mod fuzz;
mod setup;
mod test;
mod util;

use std::process::ExitCode;

const USAGE: &str = "\
usage: cargo xtask <command>

commands:
  setup               install what the tests need (idempotent)
  test                fmt, clippy, doc, tests, no_std builds, fuzz (5 s each), TAP interop
  fuzz [--seconds N]  run every fuzz target for N seconds each (default 60)
  demo                start the host board in netns enip-demo and read it with a scanner
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
        ["demo"] => demo::run_demo(),
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
