//! `cargo xtask fuzz [--seconds N]`: every cargo-fuzz target for N seconds each; and
//! `cargo xtask fuzz --campaign MINUTES`: a long run of every target that grows the seeds.
//!
//! The committed seeds in `fuzz/corpus/seed/<target>` are inputs; what libFuzzer finds goes
//! to a scratch corpus in `target/fuzz-corpus/<target>` (kept between runs, so later runs
//! start from more coverage). Each target's log is in `target/fuzz-logs/`. A campaign then
//! merges (`-merge=1`) the scratch inputs that add coverage into the committed seeds, and
//! writes its figures to `target/fuzz-logs/campaign.{md,json}`.

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

/// Checks the seeds and builds every target; `false` if the nightly toolchain is missing.
fn prepare() -> Result<bool> {
    if !setup::nightly() {
        loud("fuzz: SKIPPED: the nightly toolchain is missing and could not be installed");
        return Ok(false);
    }
    setup::cargo_fuzz()?;
    // The seeds must still be valid requests to the current stack (stable toolchain).
    run(util::cargo().args([
        "run",
        "--quiet",
        "--manifest-path",
        "fuzz/Cargo.toml",
        "--example",
        "gen_seeds",
        "--",
        "--check",
    ]))?;
    // One build for all targets; `cargo fuzz run` then finds them up to date.
    run(util::cargo_toolchain(setup::NIGHTLY).args(["fuzz", "build"]))?;
    Ok(true)
}

/// Runs every target for `seconds`; `Skipped` if the nightly toolchain is unavailable.
pub fn run_all(seconds: u64) -> Result<Outcome> {
    if !prepare()? {
        return Ok(Outcome::Skipped);
    }
    let targets = targets()?;
    println!(
        "fuzz: {} targets, {seconds} s each: {}",
        targets.len(),
        targets.join(", ")
    );
    let logs = logs_dir()?;
    let mut crashed = Vec::new();
    for t in &targets {
        if util::interrupted() {
            return err("interrupted");
        }
        if let Err(e) = run_one(t, seconds, &logs.join(format!("{t}.log"))) {
            println!("fuzz: {t}: {e}");
            crashed.push(t.clone());
        }
    }
    crashed_error(&crashed).map(|()| Outcome::Passed)
}

fn crashed_error(crashed: &[String]) -> Result {
    if crashed.is_empty() {
        return Ok(());
    }
    err(format!(
        "fuzz targets failed: {} (inputs in fuzz/artifacts/<target>/)",
        crashed.join(", ")
    ))
}

fn logs_dir() -> Result<PathBuf> {
    let logs = util::target_dir().join("fuzz-logs");
    fs::create_dir_all(&logs)?;
    Ok(logs)
}

fn seed_dir(target: &str) -> PathBuf {
    util::root().join("fuzz/corpus/seed").join(target)
}

fn scratch_dir(target: &str) -> Result<PathBuf> {
    let scratch = util::target_dir().join("fuzz-corpus").join(target);
    fs::create_dir_all(&scratch)?;
    Ok(scratch)
}

/// What libFuzzer reported at the end of one run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Stats {
    /// Inputs executed (`stat::number_of_executed_units`).
    executions: u64,
    /// Coverage counters hit (`cov:` of the last status line).
    cov: u64,
    /// Features (`ft:` of the last status line).
    ft: u64,
}

impl Stats {
    /// The figures in a libFuzzer log (`-print_final_stats=1`); missing ones are 0.
    fn parse(log: &str) -> Stats {
        let stat = |key: &str| {
            log.lines()
                .find_map(|l| l.strip_prefix(key)?.trim().parse().ok())
                .unwrap_or(0)
        };
        let status = log
            .lines()
            .rev()
            .find(|l| l.contains(" cov: "))
            .unwrap_or("");
        let field = |key: &str| {
            let mut words = status.split_whitespace();
            words.find(|&w| w == key);
            words.next().and_then(|v| v.parse().ok()).unwrap_or(0)
        };
        Stats {
            executions: stat("stat::number_of_executed_units:"),
            cov: field("cov:"),
            ft: field("ft:"),
        }
    }
}

/// Fuzzes `target` for `seconds` from its seeds and scratch corpus; fails if it crashed.
fn run_one(target: &str, seconds: u64, log: &Path) -> Result<Stats> {
    let seeds = seed_dir(target);
    let scratch = scratch_dir(target)?;
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
    let stats = Stats::parse(&text);
    println!(
        "fuzz: {target}: {} after {} runs in {} (cov {}, ft {}), scratch corpus {} inputs",
        if status.success() { "ok" } else { "FAILED" },
        stats.executions,
        secs(start.elapsed()),
        stats.cov,
        stats.ft,
        count_files(&scratch),
    );
    if status.success() {
        return Ok(stats);
    }
    // Show the end of the log: the panic message, the input and how to reproduce it.
    let tail: Vec<&str> = text.lines().rev().take(40).collect();
    for l in tail.iter().rev() {
        println!("  | {l}");
    }
    println!("  full log: {}", log.display());
    err(format!("crashed ({status})"))
}

fn count_files(dir: &Path) -> usize {
    fs::read_dir(dir).map_or(0, |d| d.count())
}

fn dir_bytes(dir: &Path) -> u64 {
    fs::read_dir(dir).map_or(0, |d| {
        d.filter_map(|e| e.ok()?.metadata().ok())
            .map(|m| m.len())
            .sum()
    })
}

/// `--campaign MINUTES`: the number of minutes.
pub fn parse_minutes(arg: &str) -> Result<u64> {
    arg.parse()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| util::Error(format!("--campaign wants a positive number, not {arg:?}")))
}

/// A target's share of a campaign's time: the targets that drive the adapter or a profile
/// run 5-50 times slower than a single parser, so they get twice a parser's time.
fn weight(target: &str) -> u64 {
    if target.starts_with("adapter_") || target.starts_with("profile_") {
        2
    } else {
        1
    }
}

/// One target's line of a campaign report.
#[derive(Debug, Clone)]
struct Row {
    target: String,
    seconds: f64,
    stats: Stats,
    crashed: bool,
    /// Seed files before and after the merge, and their total size after it.
    seeds_before: usize,
    seeds_after: usize,
    seed_bytes: u64,
}

/// Runs every target in turn for a share of `minutes`, then merges what adds coverage into
/// its committed seeds; prints and writes the report. Fails if any target crashed.
pub fn campaign(minutes: u64) -> Result {
    if !prepare()? {
        return err("the nightly toolchain is needed for a campaign");
    }
    let targets = targets()?;
    let shares: u64 = targets.iter().map(|t| weight(t)).sum();
    let budget = minutes * 60;
    println!(
        "fuzz campaign: {minutes} min over {} targets (adapter_*/profile_* twice a parser's time)",
        targets.len()
    );
    let logs = logs_dir()?;
    let start = Instant::now();
    let mut rows = Vec::new();
    for t in &targets {
        if util::interrupted() {
            return err("interrupted");
        }
        let seconds = (budget * weight(t) / shares).max(1);
        let began = Instant::now();
        let outcome = run_one(t, seconds, &logs.join(format!("{t}.log")));
        let elapsed = began.elapsed().as_secs_f64();
        let (stats, crashed) = match outcome {
            Ok(stats) => (stats, false),
            Err(_) => {
                let text = fs::read_to_string(logs.join(format!("{t}.log"))).unwrap_or_default();
                (Stats::parse(&text), true)
            }
        };
        let seeds = seed_dir(t);
        let seeds_before = count_files(&seeds);
        if !crashed {
            merge(t, &logs.join(format!("{t}.merge.log")))?;
        }
        rows.push(Row {
            target: t.clone(),
            seconds: elapsed,
            stats,
            crashed,
            seeds_before,
            seeds_after: count_files(&seeds),
            seed_bytes: dir_bytes(&seeds),
        });
    }
    let wall = start.elapsed();
    let table = report_table(&rows, wall.as_secs_f64());
    print!("{table}");
    fs::write(logs.join("campaign.md"), &table)?;
    fs::write(
        logs.join("campaign.json"),
        report_json(&rows, wall.as_secs_f64()),
    )?;
    println!("report: {}", logs.join("campaign.md").display());
    let crashed: Vec<String> = rows
        .iter()
        .filter(|r| r.crashed)
        .map(|r| r.target.clone())
        .collect();
    crashed_error(&crashed)
}

/// Merges the scratch inputs of `target` that add coverage into its committed seeds
/// (libFuzzer `-merge=1`: the seeds stay; each added input is named by its SHA-1). Only new
/// edges count (`-use_counters=0`), not new hit counts of known ones: that keeps the
/// committed seeds about half as many as the scratch corpus's features would want.
fn merge(target: &str, log: &Path) -> Result {
    let seeds = seed_dir(target);
    fs::create_dir_all(&seeds)?;
    let mut cmd = util::cargo_toolchain(setup::NIGHTLY);
    cmd.args(["fuzz", "run", target])
        .arg(&seeds)
        .arg(scratch_dir(target)?)
        .args([
            "--",
            "-merge=1",
            "-use_counters=0",
            "-timeout=10",
            "-rss_limit_mb=2048",
        ]);
    println!("$ {}", util::show(&cmd));
    let file = fs::File::create(log)?;
    let status = cmd
        .stdout(file.try_clone()?)
        .stderr(file)
        .stdin(Stdio::null())
        .status()?;
    if status.success() {
        Ok(())
    } else {
        err(format!("merge of {target} failed; see {}", log.display()))
    }
}

fn report_table(rows: &[Row], wall: f64) -> String {
    let mut s = String::from(
        "| target | time (s) | executions | exec/s | cov | ft | seeds (before -> after, size) |\n\
         |---|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {}{} | {:.0} | {} | {:.0} | {} | {} | {} -> {}, {} KiB |\n",
            r.target,
            if r.crashed { " (CRASHED)" } else { "" },
            r.seconds,
            r.stats.executions,
            r.stats.executions as f64 / r.seconds.max(1e-3),
            r.stats.cov,
            r.stats.ft,
            r.seeds_before,
            r.seeds_after,
            r.seed_bytes.div_ceil(1024),
        ));
    }
    let total: u64 = rows.iter().map(|r| r.stats.executions).sum();
    s.push_str(&format!(
        "| **total** | {wall:.0} | **{total}** | {:.0} | | | |\n",
        total as f64 / wall.max(1e-3)
    ));
    s
}

fn report_json(rows: &[Row], wall: f64) -> String {
    let targets: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "target": r.target,
                "seconds": r.seconds,
                "executions": r.stats.executions,
                "cov": r.stats.cov,
                "ft": r.stats.ft,
                "crashed": r.crashed,
                "seeds_before": r.seeds_before,
                "seeds_after": r.seeds_after,
                "seed_bytes": r.seed_bytes,
            })
        })
        .collect();
    let total: u64 = rows.iter().map(|r| r.stats.executions).sum();
    serde_json::json!({
        "wall_seconds": wall,
        "total_executions": total,
        "targets": targets,
    })
    .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_from_a_libfuzzer_log() {
        let log = "#2\tINITED cov: 10 ft: 12 corp: 1/1b exec/s: 0 rss: 30Mb\n\
                   #4096\tpulse  cov: 90 ft: 150 corp: 9/1Kb lim: 4 exec/s: 2048 rss: 31Mb\n\
                   #9000\tDONE   cov: 97 ft: 160 corp: 11/1Kb lim: 4 exec/s: 3000 rss: 31Mb\n\
                   Done 9000 runs in 3 second(s)\n\
                   stat::number_of_executed_units: 9000\n\
                   stat::average_exec_per_sec:     3000\n";
        assert_eq!(
            Stats::parse(log),
            Stats {
                executions: 9000,
                cov: 97,
                ft: 160
            }
        );
        assert_eq!(Stats::parse("crashed early"), Stats::default());
    }

    #[test]
    fn campaign_minutes() {
        assert_eq!(parse_minutes("40").unwrap(), 40);
        assert!(parse_minutes("0").is_err());
        assert!(parse_minutes("x").is_err());
    }

    #[test]
    fn drivers_get_twice_a_parsers_time() {
        assert_eq!(weight("adapter_io"), 2);
        assert_eq!(weight("profile_parker_ipa"), 2);
        assert_eq!(weight("epath"), 1);
    }
}
