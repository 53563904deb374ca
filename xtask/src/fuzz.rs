//! `cargo xtask fuzz [--seconds N]`: every cargo-fuzz target for N seconds each.
//!
//! The committed seeds in `fuzz/corpus/seed/<target>` are read-only inputs; what libFuzzer
//! finds goes to a scratch corpus in `target/fuzz-corpus/<target>` (kept between runs, so
//! later runs start from more coverage). Each target's log is in `target/fuzz-logs/`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::Instant;

use crate::setup;
use crate::util::{self, err, loud, run, secs, Outcome, Result};

/// Default seconds per target.
pub const DEFAULT_SECONDS: u64 = 60;

/// The fuzz targets: the files in `fuzz/fuzz_targets/`, sorted.
pub fn targets() -> Result<Vec<String>> {
    let dir = util::root().join("fuzz/fuzz_targets");
    let mut names: Vec<String> = fs::read_dir(&dir)
        .map_err(|e| util::Error(format!("{}: {e}", dir.display())))?
        .filter_map(|e| {
            let p = e.ok()?.path();
            if p.extension()? != "rs" {
                return None;
            }
            Some(p.file_stem()?.to_string_lossy().into_owned())
        })
        .collect();
    names.sort();
    Ok(names)
}

/// Runs every target for `seconds`; `Skipped` if the nightly toolchain is unavailable.
pub fn run_all(seconds: u64) -> Result<Outcome> {
    if !setup::nightly() {
        loud("fuzz: SKIPPED: the nightly toolchain is missing and could not be installed");
        return Ok(Outcome::Skipped);
    }
    setup::cargo_fuzz()?;
    let targets = targets()?;
    println!(
        "fuzz: {} targets, {seconds} s each: {}",
        targets.len(),
        targets.join(", ")
    );
    // The seeds must still be valid requests to the current stack (stable toolchain).
    run(util::cargo().args([
        "run",
        "--quiet",
        "--manifest-path",
        "fuzz/Cargo.toml",
        "--bin",
        "gen_seeds",
        "--",
        "--check",
    ]))?;
    // One build for all targets; `cargo fuzz run` then finds them up to date.
    run(util::cargo_toolchain(setup::NIGHTLY).args(["fuzz", "build"]))?;
    let logs = util::target_dir().join("fuzz-logs");
    fs::create_dir_all(&logs)?;
    let mut crashed = Vec::new();
    for t in &targets {
        if util::interrupted() {
            return err("interrupted");
        }
        match run_one(t, seconds, &logs.join(format!("{t}.log"))) {
            Ok(()) => {}
            Err(e) => {
                println!("fuzz: {t}: {e}");
                crashed.push(t.clone());
            }
        }
    }
    if crashed.is_empty() {
        Ok(Outcome::Passed)
    } else {
        err(format!(
            "fuzz targets failed: {} (inputs in fuzz/artifacts/<target>/)",
            crashed.join(", ")
        ))
    }
}

fn run_one(target: &str, seconds: u64, log: &Path) -> Result {
    let root = util::root();
    let seeds = root.join("fuzz/corpus/seed").join(target);
    let scratch: PathBuf = util::target_dir().join("fuzz-corpus").join(target);
    fs::create_dir_all(&scratch)?;
    let mut cmd = util::cargo_toolchain(setup::NIGHTLY);
    cmd.args(["fuzz", "run", target]).arg(&scratch);
    if seeds.is_dir() {
        cmd.arg(&seeds);
    }
    cmd.arg("--")
        .arg(format!("-max_total_time={seconds}"))
        .arg("-timeout=10")
        .arg("-rss_limit_mb=2048")
        .arg("-print_final_stats=1");
    println!("$ {}", util::show(&cmd));
    let file = fs::File::create(log)?;
    let start = Instant::now();
    let status = cmd
        .stdout(file.try_clone()?)
        .stderr(file)
        .stdin(Stdio::null())
        .status()?;
    let text = fs::read_to_string(log).unwrap_or_default();
    let stat = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key).map(|v| v.trim().to_string()))
            .unwrap_or_else(|| "?".into())
    };
    println!(
        "fuzz: {target}: {} after {} runs in {}, scratch corpus {} inputs",
        if status.success() { "ok" } else { "FAILED" },
        stat("stat::number_of_executed_units:"),
        secs(start.elapsed()),
        fs::read_dir(&scratch).map_or(0, |d| d.count()),
    );
    if status.success() {
        return Ok(());
    }
    // Show the end of the log: the panic message, the input and how to reproduce it.
    let tail: Vec<&str> = text.lines().rev().take(40).collect();
    for l in tail.iter().rev() {
        println!("  | {l}");
    }
    println!("  full log: {}", log.display());
    err(format!("crashed ({status})"))
}
