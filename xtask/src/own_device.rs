//! The device-author path from outside the workspace: a cargo project of its own in a
//! temporary directory, made of the README's `[dependencies]` snippet and `main` ("An own
//! host device") and `examples/own-device/device.rs`, built offline against the
//! workspace's `Cargo.lock`; its `--eds` output must be an EDS that eds-pie parses cleanly.

use std::path::Path;
use std::process::Command;

use enip_lab::peers;
use enip_lab::process::run_bounded;

use crate::util::{self, err, run, Outcome, Result};

/// Where the README's snippets start: a marker line, then a fenced block.
const CARGO_TOML: &str = "<!-- own-device:Cargo.toml -->";
const MAIN_RS: &str = "<!-- own-device:main.rs -->";
/// The checkout's path as the README writes it.
const CHECKOUT: &str = "../enip-rs";
/// How long `--eds` and eds-pie may take.
const LIMIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Builds the own device from its own project and checks the EDS it prints.
pub fn run_check() -> Result<Outcome> {
    let root = util::root();
    let readme = std::fs::read_to_string(root.join("README.md"))?;
    let deps = block_after(&readme, CARGO_TOML)?;
    let main = block_after(&readme, MAIN_RS)?;
    let dir = std::env::temp_dir().join(format!("enip-own-device-{}", std::process::id()));
    let result = build_and_check(&root, &dir, &deps, &main);
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn build_and_check(root: &Path, dir: &Path, deps: &str, main: &str) -> Result<Outcome> {
    std::fs::create_dir_all(dir.join("src"))?;
    let checkout = root.to_string_lossy();
    let manifest = format!(
        "[package]\nname = \"own-device\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\n{}",
        deps.replace(CHECKOUT, &checkout)
    );
    println!("{}/Cargo.toml:\n{manifest}", dir.display());
    std::fs::write(dir.join("Cargo.toml"), manifest)?;
    std::fs::write(dir.join("src/main.rs"), main)?;
    std::fs::copy(
        root.join("examples/own-device/device.rs"),
        dir.join("src/device.rs"),
    )?;
    // The workspace's versions of every dependency: nothing to download.
    std::fs::copy(root.join("Cargo.lock"), dir.join("Cargo.lock"))?;
    let manifest = dir.join("Cargo.toml");
    let mut build = util::cargo();
    build
        .current_dir(dir)
        .args(["build", "--offline", "--manifest-path"])
        .arg(&manifest)
        .env("CARGO_TARGET_DIR", util::target_dir());
    run(&mut build)?;
    let bin = util::target_dir().join("debug/own-device");
    let mut cmd = Command::new(&bin);
    cmd.arg("--eds");
    let out = run_bounded(cmd, None, LIMIT)?;
    if !out.status.success() {
        return err(format!("`{} --eds` failed ({})", bin.display(), out.status));
    }
    let eds = String::from_utf8_lossy(&out.stdout);
    print!("{eds}");
    for needle in [
        "$ EDS of \"Analog 4/2 module\"",
        "Param2 = ",
        "8, Param2, 8, Param3, 16, Param4;",
    ] {
        if !eds.contains(needle) {
            return err(format!("the own device's EDS lacks {needle:?}"));
        }
    }
    let file = dir.join("own-device.eds");
    std::fs::write(&file, eds.as_bytes())?;
    eds_pie(&file)
}

/// eds-pie's verdict on `file` (skipped without the peers' Python).
fn eds_pie(file: &Path) -> Result<Outcome> {
    let python = peers::venv_python();
    if !python.exists() {
        util::loud("own device: eds-pie SKIPPED: no peers venv (cargo xtask setup)");
        return Ok(Outcome::Skipped);
    }
    let input = format!("{{\"path\": {:?}}}", file.to_string_lossy());
    let mut cmd = Command::new(python);
    cmd.arg(peers::script("eds_check.py"));
    let out = run_bounded(cmd, Some(input.as_bytes()), LIMIT)?;
    let verdict = String::from_utf8_lossy(&out.stdout);
    println!("eds-pie: {}", verdict.trim());
    if verdict.contains("\"problems\": []") && verdict.contains("\"Assem151\": 4") {
        Ok(Outcome::Passed)
    } else {
        err("eds-pie found problems in the own device's EDS")
    }
}

/// The fenced block after the line `marker` in `text`.
fn block_after(text: &str, marker: &str) -> Result<String> {
    let mut lines = text.lines().skip_while(|l| l.trim() != marker).skip(1);
    if !lines.next().is_some_and(|l| l.starts_with("```")) {
        return err(format!("README.md: no fenced block after {marker}"));
    }
    let block: Vec<&str> = lines.take_while(|l| !l.starts_with("```")).collect();
    Ok(block.join("\n") + "\n")
}
