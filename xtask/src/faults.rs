//! `cargo xtask faults`: the long versions of the fault tests (issue 13 item 2) on release
//! builds, their figures written to `target/faults/report.json` and printed as a table.
//!
//! The tests are host-tests' `faults_*` TAP tests run with `ENIP_FAULTS_LONG=1`; each prints
//! one `FAULT-REPORT {json}` line, which is collected here. Not part of `cargo xtask test`
//! (which runs the short versions): the soak alone takes 10 minutes. `ENIP_FAULTS_FILTER`
//! narrows the run to the tests whose names contain it (e.g. `faults_flood` for the floods
//! of issue 28, which need `hping3` and, for the emulated board's, its generic ELF: built
//! here).

use std::io::{BufRead, BufReader};
use std::process::Stdio;

use serde_json::{Map, Value};

use enip_lab::rig;

use crate::boards;
use crate::util::{self, cargo, err, run, Result};

/// What a test prints before its figures.
const PREFIX: &str = "FAULT-REPORT ";
/// The tests' name filter, unless `ENIP_FAULTS_FILTER` gives another.
const FILTER: &str = "faults_";
/// The environment variable that narrows the run.
const FILTER_ENV: &str = "ENIP_FAULTS_FILTER";

/// Builds, runs the long fault tests, writes the report and prints the table.
pub fn run_all() -> Result {
    if !util::is_root() {
        return err("the fault tests need root (network namespaces and TAP devices)");
    }
    run(cargo().args(["build", "--release", "-p", "enip-host"]))?;
    let host = util::target_dir().join("release/enip-host");
    // The emulated board of the flood tests (faults_flood_qemu): the generic profile.
    let elf = util::target_dir().join("qemu-generic.elf");
    std::fs::copy(
        boards::build_with(boards::QEMU, boards::DEFAULT_PROFILE, &[])?,
        &elf,
    )?;
    let filter = std::env::var(FILTER_ENV).unwrap_or_else(|_| FILTER.to_string());
    let mut test = cargo();
    test.args([
        "test",
        "--release",
        "-p",
        "host-tests",
        "--test",
        "tap_interop",
    ])
    .args([
        "--",
        "--ignored",
        "--test-threads=1",
        "--nocapture",
        &filter,
    ])
    .env("ENIP_FAULTS_LONG", "1")
    .env("ENIP_HOST_BIN", &host)
    .env(rig::qemu_elf_var(boards::DEFAULT_PROFILE), &elf)
    .env("ENIP_PEER_PYTHON", enip_lab::peers::venv_python())
    .stdout(Stdio::piped());
    println!("$ {}", util::show(&test));
    let mut child = test
        .spawn()
        .map_err(|e| util::Error(format!("cargo test: {e}")))?;
    let mut scenarios = Map::new();
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines().map_while(std::io::Result::ok) {
            println!("{line}");
            if let Some((name, figures)) = parse_report(&line) {
                scenarios.insert(name, figures);
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| util::Error(format!("cargo test: {e}")))?;
    let dir = util::target_dir().join("faults");
    std::fs::create_dir_all(&dir).map_err(|e| util::Error(format!("{}: {e}", dir.display())))?;
    let path = dir.join("report.json");
    let report = serde_json::json!({ "passed": status.success(), "scenarios": scenarios });
    let text = serde_json::to_string_pretty(&report).unwrap_or_default();
    std::fs::write(&path, text).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    println!();
    print!("{}", table(&scenarios));
    println!("report: {}", path.display());
    if status.success() {
        Ok(())
    } else {
        err(format!(
            "a fault test failed ({status}); figures so far in the report"
        ))
    }
}

/// The scenario name and figures of a `FAULT-REPORT` line (the prefix may follow other
/// output on the same line, as the test harness prints the test's name first).
pub(crate) fn parse_report(line: &str) -> Option<(String, Value)> {
    let json = line.split_once(PREFIX)?.1;
    let figures: Value = serde_json::from_str(json).ok()?;
    let name = figures.get("scenario")?.as_str()?.to_string();
    Some((name, figures))
}

/// One row per scalar figure (numbers, strings, booleans, short lists of numbers) of each
/// scenario, those of a nested object too (`object.figure`); per-round details stay in the
/// JSON report.
fn table(scenarios: &Map<String, Value>) -> String {
    let mut out = format!("{:<28} {:<44} {:>20}\n", "scenario", "figure", "value");
    for (name, figures) in scenarios {
        let Some(fields) = figures.as_object() else {
            continue;
        };
        for (key, value) in fields {
            if key == "scenario" {
                continue;
            }
            let rows: Vec<(String, &Value)> = match value {
                Value::Object(inner) => inner
                    .iter()
                    .map(|(k, v)| (format!("{key}.{k}"), v))
                    .collect(),
                _ => vec![(key.clone(), value)],
            };
            for (key, value) in rows {
                if let Some(shown) = scalar(value) {
                    out.push_str(&format!("{name:<28} {key:<44} {shown:>20}\n"));
                }
            }
        }
    }
    out
}

/// A figure as the table shows it, or `None` for one that stays in the report only.
fn scalar(value: &Value) -> Option<String> {
    match value {
        Value::Number(_) | Value::Bool(_) => Some(value.to_string()),
        Value::String(s) => Some(format!("{s:?}")),
        Value::Array(items) if items.len() <= 4 && items.iter().all(Value::is_number) => {
            Some(value.to_string())
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_lines_and_table() {
        let line = "test faults::x ... FAULT-REPORT {\"scenario\":\"churn\",\"cycles\":10000,\
                    \"rss\":[1,2],\"run\":\"long\",\"per_round\":[{\"a\":1}],\
                    \"floor\":{\"p99_us\":1065}}";
        let (name, figures) = parse_report(line).unwrap();
        assert_eq!(name, "churn");
        assert_eq!(figures["cycles"], 10000);
        assert!(parse_report("FAULT-REPORT {\"cycles\":1}").is_none());
        assert!(parse_report("test ok").is_none());
        let mut m = Map::new();
        m.insert(name, figures);
        let t = table(&m);
        assert!(t.contains("cycles") && t.contains("10000"), "{t}");
        assert!(t.contains("[1,2]") && t.contains("\"long\""), "{t}");
        assert!(!t.contains("per_round"), "{t}");
        assert!(t.contains("floor.p99_us") && t.contains("1065"), "{t}");
    }
}
