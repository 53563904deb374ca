//! `cargo xtask test`: the whole test suite, in order, stopping at the first failure.

use crate::util::{self, loud, run, Outcome, Result, Steps};
use crate::{fuzz, setup, workspace};

/// Seconds per fuzz target in the test run.
const FUZZ_SECONDS: u64 = 5;
/// The TAP interop test file (written by the host-tests owners).
const TAP_INTEROP: &str = "host-tests/tests/tap_interop.rs";

/// Runs every step; true if none failed. Prints a summary either way.
pub fn run_all() -> bool {
    let mut steps = Steps::default();
    let cargo = |args: &[&str]| -> Result<Outcome> {
        run(util::cargo().args(args))?;
        Ok(Outcome::Passed)
    };
    // Host steps cover the default members (everything that builds on the host); the
    // workspace members outside them build only for the embedded target.
    let mut cross = vec!["enip-stack".to_string(), "enip-firmware".to_string()];
    // `&&` stops at the first failed step; the summary lists the steps that ran.
    let mut ok = steps.run("setup", || setup::all().map(|()| Outcome::Passed))
        && steps.run("rustfmt", || {
            cargo(&["fmt", "--all", "--", "--check"])?;
            cargo(&["fmt", "--manifest-path", "fuzz/Cargo.toml", "--", "--check"])
        })
        && steps.run("clippy", || {
            cargo(&["clippy", "--all-targets", "--", "-D", "warnings"])?;
            cargo(&[
                "clippy",
                "--manifest-path",
                "fuzz/Cargo.toml",
                "--all-targets",
                "--",
                "-D",
                "warnings",
            ])
        })
        && steps.run("rustdoc", || {
            run(util::cargo()
                .args(["doc", "--no-deps"])
                .env("RUSTDOCFLAGS", "-Dwarnings"))?;
            Ok(Outcome::Passed)
        })
        && steps.run("unit and integration tests", || cargo(&["test"]))
        && steps.run("list the cross-only crates", || {
            cross.extend(workspace::cross_only_packages()?);
            println!("built for {}: {}", setup::THUMB_TARGET, cross.join(", "));
            Ok(Outcome::Passed)
        });
    for package in &cross {
        ok = ok
            && steps.run(&format!("no_std build: {package}"), || {
                cargo(&["build", "-p", package, "--target", setup::THUMB_TARGET])
            });
    }
    let _all_passed = ok
        && steps.run("fuzz", || fuzz::run_all(FUZZ_SECONDS))
        && steps.run("TAP interop", tap_interop);
    steps.summary()
}

/// The TAP interop suite: ignored tests in host-tests, run one at a time with the peers.
fn tap_interop() -> Result<Outcome> {
    let root = util::root();
    if !root.join(TAP_INTEROP).exists() {
        loud(&format!(
            "TAP interop: SKIPPED: {TAP_INTEROP} does not exist yet"
        ));
        return Ok(Outcome::Skipped);
    }
    run(util::cargo().args(["build", "-p", "enip-host"]))?;
    let host_bin = util::target_dir().join("debug/enip-host");
    let python = setup::venv_python();
    run(util::cargo()
        .args([
            "test",
            "-p",
            "host-tests",
            "--test",
            "tap_interop",
            "--",
            "--ignored",
            "--test-threads=1",
        ])
        .env("ENIP_PEER_PYTHON", &python)
        .env("ENIP_HOST_BIN", &host_bin)
        .env("ENIP_PEER_NPM_DIR", setup::npm_dir()))?;
    Ok(Outcome::Passed)
}
