//! `cargo xtask faults --chaos MINUTES [--seed S]`: the chaos soak (issue 28 item 4), the TAP
//! suite's `chaos::chaos_soak` test run for MINUTES minutes on release builds with the seed
//! given (or one drawn from the clock, printed); its `FAULT-REPORT` line is written to
//! `target/bench/chaos.json` and printed as a table. Not part of `cargo xtask test`.

use std::io::{BufRead, BufReader};
use std::process::Stdio;

use serde_json::Value;

use crate::faults::parse_report;
use crate::util::{self, cargo, err, run, Result};

/// Builds, runs the chaos soak, writes the report and prints the table.
pub fn run_chaos(minutes: u64, seed: Option<u64>) -> Result {
    if !util::is_root() {
        return err("the chaos soak needs root (network namespaces and TAP devices)");
    }
    let seed = seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.as_secs())
    });
    println!("chaos soak: seed {seed}, {minutes} minutes");
    run(cargo().args(["build", "--release", "-p", "enip-host"]))?;
    let host = util::target_dir().join("release/enip-host");
    let mut test = cargo();
    test.args(["test", "--release", "-p", "host-tests"])
        .args(["--test", "tap_interop", "--", "--ignored", "--exact"])
        .args(["--test-threads=1", "--nocapture", "chaos::chaos_soak"])
        .env("CHAOS_MINUTES", minutes.to_string())
        .env("CHAOS_SEED", seed.to_string())
        .env("ENIP_HOST_BIN", &host)
        .stdout(Stdio::piped());
    println!("$ {}", util::show(&test));
    let mut child = test
        .spawn()
        .map_err(|e| util::Error(format!("cargo test: {e}")))?;
    let mut report = None;
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines().map_while(std::io::Result::ok) {
            match parse_report(&line) {
                Some((name, figures)) if name == "chaos" => report = Some(figures),
                _ => println!("{line}"),
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| util::Error(format!("cargo test: {e}")))?;
    let Some(report) = report else {
        return err(format!("the chaos soak printed no report ({status})"));
    };
    let dir = util::target_dir().join("bench");
    std::fs::create_dir_all(&dir).map_err(|e| util::Error(format!("{}: {e}", dir.display())))?;
    let path = dir.join("chaos.json");
    let text = serde_json::to_string_pretty(&report).unwrap_or_default();
    std::fs::write(&path, text).map_err(|e| util::Error(format!("{}: {e}", path.display())))?;
    println!();
    print!("{}", table(&report));
    println!("report: {}", path.display());
    if status.success() {
        Ok(())
    } else {
        err(format!("an invariant of the chaos soak failed ({status})"))
    }
}

/// The report as Markdown tables: seed and totals, faults injected, invariants, per period.
fn table(r: &Value) -> String {
    let n = |k: &str| r[k].to_string();
    let mut out = format!(
        "seed {}, {} minutes: {} faults injected; T->O {} received, {} gaps over 20 ms \
         ({} in fault windows, {} in host stalls, {} unexplained); host timer stalls over \
         10 ms: {} (longest {} ms); explicit reads {} ok, {} failed ({} unexplained)\n\n",
        n("seed"),
        n("minutes"),
        n("faults_total"),
        n("t_o_received"),
        n("t_o_gaps_over_20ms"),
        n("t_o_gaps_in_fault_windows"),
        n("t_o_gaps_in_host_stalls"),
        r["t_o_gaps_unexplained"].as_array().map_or(0, Vec::len),
        n("host_timer_stalls_over_10ms"),
        // No stall at all: the test reports no longest one.
        r["host_timer_stall_max_ms"].as_f64().unwrap_or(0.0),
        n("explicit_reads_ok"),
        n("explicit_failures"),
        r["explicit_failures_unexplained_at_s"]
            .as_array()
            .map_or(0, Vec::len),
    );
    out.push_str("| fault | count |\n| --- | ---: |\n");
    for (k, v) in r["faults"].as_object().into_iter().flatten() {
        out.push_str(&format!("| {k} | {v} |\n"));
    }
    out.push_str("\n| invariant | result |\n| --- | --- |\n");
    for (k, v) in r["invariants"].as_object().into_iter().flatten() {
        let shown = if v == true { "pass" } else { "FAIL" };
        out.push_str(&format!("| {k} | {shown} |\n"));
    }
    out.push_str(
        "\n| period | board CPU % | RSS KiB | T->O | explicit reads | faults | gaps |\n\
         | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for p in r["per_period"].as_array().into_iter().flatten() {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            p["period"],
            p["cpu_percent"],
            p["rss_kib"],
            p["t_o"],
            p["explicit_reads"],
            p["faults"],
            p["gaps"]
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chaos_table() {
        let r = serde_json::json!({
            "seed": 42, "minutes": 1, "faults_total": 3,
            "faults": {"link_flap": 1, "nv_write": 2},
            "invariants": {"rss_level": true, "cpu_level": false},
            "t_o_gaps_unexplained": [], "explicit_failures_unexplained_at_s": [1.5],
            "per_period": [{"period": 1, "cpu_percent": 17.5, "rss_kib": 2892, "t_o": 100,
                "explicit_reads": 9, "faults": 3, "gaps": 0}],
        });
        let t = table(&r);
        assert!(t.starts_with("seed 42, 1 minutes: 3 faults"), "{t}");
        assert!(t.contains("(1 unexplained)"), "{t}");
        assert!(t.contains("| nv_write | 2 |"), "{t}");
        assert!(t.contains("| rss_level | pass |") && t.contains("| cpu_level | FAIL |"));
        assert!(t.contains("| 1 | 17.5 | 2892 | 100 | 9 | 3 | 0 |"), "{t}");
    }
}
