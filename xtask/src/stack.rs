//! `cargo xtask stack`: the emulated board's call stack, measured. Each profile's image runs
//! the TAP interop tests that can run on it (the generic test image: the hostile battery, the
//! fault tests, Class 1 with 10 connections at 1 ms, explicit messaging, UDP, the fault
//! resets; every other profile: its own scenarios); the rig reads the board's high-water mark
//! (the diagnostics object, class 0x3A0) at the end of each test. Prints, per profile, the
//! worst depth and the margin it leaves in the NUCLEO-F767ZI's stack region (its RAM less the
//! statics, which flip-link puts above the stack); written to `target/bench/stack.json`.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::Command;

use enip_lab::diagnostics::MARKS_ENV;
use enip_lab::rig::{self, QEMU_BOARD_ENV};
use serde_json::{json, Value};

use crate::util::{self, run, Result};
use crate::workspace::Metadata;
use crate::{boards, qemu, setup, test};

/// The host-board tests the generic test image runs (the rig starts the emulated board for
/// every generic-profile board without extra arguments).
/// The other fault tests follow the host board's process (its memory, CPU, real-time
/// priority) and cannot run on the emulated board; `embedded_qemu::` is the emulated board's
/// own (overflow, hang, panic; 10 connections at 1 ms).
const GENERIC_SUITES: [&str; 6] = [
    "hostile_",
    "faults::faults_idle_and_half_open_sockets",
    "class1::",
    "explicit::",
    "udp::",
    "embedded_qemu::",
];

/// Runs the suites on the emulated board, prints and writes the figures.
pub fn run_all() -> Result {
    qemu::require_root("stack")?;
    setup::rust_target()?;
    qemu::ensure_installed()?;
    test::build_interop_boards()?;
    let dir = util::target_dir().join("bench");
    fs::create_dir_all(&dir)?;
    let marks = dir.join("stack-marks.jsonl");
    let _ = fs::remove_file(&marks);
    let faults = boards::faults_image()?;
    measured(
        test::interop(&GENERIC_SUITES)
            .env(QEMU_BOARD_ENV, &faults)
            .env("ENIP_QEMU_FAULTS_ELF", &faults)
            .env(MARKS_ENV, &marks),
    );
    let mut images = vec![(boards::DEFAULT_PROFILE.to_string(), faults)];
    for profile in boards::profiles(&Metadata::read()?)? {
        if profile == boards::DEFAULT_PROFILE {
            continue;
        }
        let elf = util::target_dir().join(format!("qemu-{profile}.elf"));
        fs::copy(
            boards::build_with(boards::QEMU, &profile, &[("ENIP_ACD", "off")])?,
            &elf,
        )?;
        let module = format!("{}::", profile.replace('-', "_"));
        measured(
            test::interop(&[&module])
                .env(rig::qemu_elf_var(&profile), &elf)
                .env(MARKS_ENV, &marks),
        );
        images.push((profile, elf));
    }
    let region = nucleo_stack_region()?;
    let report = summary(&fs::read_to_string(&marks)?, &images, region);
    fs::write(dir.join("stack.json"), report.to_string())?;
    println!("\nCall stack, worst depth per profile (emulated board), margin on the NUCLEO-F767ZI");
    println!("(stack region {region} bytes: 512 KiB of RAM less the statics):");
    println!(
        "{:<16} {:>6} {:>12} {:>12}",
        "profile", "tests", "worst bytes", "margin bytes"
    );
    for row in report["profiles"].as_array().into_iter().flatten() {
        let n = |k: &str| row[k].as_u64().unwrap_or(0);
        println!(
            "{:<16} {:>6} {:>12} {:>12}",
            row["profile"].as_str().unwrap_or("?"),
            n("tests"),
            n("worst"),
            n("margin")
        );
    }
    println!("report: {}", dir.join("stack.json").display());
    Ok(())
}

/// Runs the tests of `cmd`; a failure (a test written for the host board that the emulated
/// one does not pass) is reported, not fatal: the marks of every test that finished count.
fn measured(cmd: &mut Command) {
    if let Err(e) = run(cmd) {
        util::loud(&format!(
            "stack: {e}: some tests failed on the emulated board (marks of the others kept)"
        ));
    }
}

/// Bytes of the NUCLEO-F767ZI's stack region: `_stack_start - _stack_end` of its release
/// image (flip-link defines both).
fn nucleo_stack_region() -> Result<u64> {
    let elf = boards::build(boards::NUCLEO, boards::DEFAULT_PROFILE)?;
    let symbols = util::output(Command::new("arm-none-eabi-nm").arg(&elf))
        .ok_or_else(|| util::Error(format!("arm-none-eabi-nm {} failed", elf.display())))?;
    let address = |name: &str| {
        symbols.lines().find_map(|l| {
            let mut cols = l.split_whitespace();
            let (value, _, symbol) = (cols.next()?, cols.next()?, cols.next()?);
            (symbol == name).then(|| u64::from_str_radix(value, 16).ok())?
        })
    };
    match (address("_stack_start"), address("_stack_end")) {
        (Some(top), Some(bottom)) if top > bottom => Ok(top - bottom),
        _ => Err(util::Error(format!(
            "{}: no flip-link stack symbols",
            elf.display()
        ))),
    }
}

/// The per-profile worst depth from the JSON lines `marks` of the images `(profile, elf)`.
fn summary(marks: &str, images: &[(String, std::path::PathBuf)], region: u64) -> Value {
    let mut worst: BTreeMap<&str, (u64, u64)> = BTreeMap::new();
    for line in marks.lines() {
        let Ok(mark) = serde_json::from_str::<Value>(line) else {
            continue;
        };
        let elf = Path::new(mark["elf"].as_str().unwrap_or_default());
        let Some((profile, _)) = images.iter().find(|(_, e)| e == elf) else {
            continue;
        };
        let entry = worst.entry(profile.as_str()).or_default();
        entry.0 += 1;
        entry.1 = entry.1.max(mark["deepest"].as_u64().unwrap_or(0));
    }
    let rows: Vec<Value> = worst
        .iter()
        .map(|(profile, (tests, deepest))| {
            json!({
                "profile": profile,
                "tests": tests,
                "worst": deepest,
                "margin": region.saturating_sub(*deepest),
            })
        })
        .collect();
    json!({"nucleo_stack_region": region, "profiles": rows})
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_keeps_the_worst_mark_per_profile() {
        let marks = "{\"elf\":\"/t/a.elf\",\"deepest\":100}\n\
                     {\"elf\":\"/t/a.elf\",\"deepest\":300}\n\
                     not json\n\
                     {\"elf\":\"/t/b.elf\",\"deepest\":50}\n";
        let images = [
            ("generic".to_string(), "/t/a.elf".into()),
            ("other".to_string(), "/t/b.elf".into()),
        ];
        let r = summary(marks, &images, 1000);
        assert_eq!(
            r["profiles"],
            json!([
                {"profile": "generic", "tests": 2, "worst": 300, "margin": 700},
                {"profile": "other", "tests": 1, "worst": 50, "margin": 950},
            ])
        );
    }
}
