//! The emulated board on QEMU's other cores: the `enip-qemu-mps2` crate built with a machine
//! feature for `mps2-an385` (Cortex-M3), `mps2-an500` (Cortex-M7) and `mps2-an505`
//! (Cortex-M33); their release builds and clippy, their footprints and budgets, the test
//! that boots each (`host-tests/tests/qemu_cores.rs`), and their instructions per Class 1
//! cycle in the QEMU benchmark beside the Cortex-M4's.

use std::path::{Path, PathBuf};

use enip_lab::peers;

use crate::bench_scale::Scale;
use crate::boards;
use crate::util::{self, loud, run, Outcome, Result};

/// One emulated core: the board's cargo feature, QEMU's machine, the core, the Rust target,
/// and its footprint budget (flash, static RAM; bytes).
#[derive(Debug, Clone, Copy)]
pub struct Core {
    /// Its image's name in reports.
    pub label: &'static str,
    /// The `enip-qemu-mps2` feature.
    pub feature: &'static str,
    /// QEMU's `-M`.
    pub machine: &'static str,
    /// The core.
    pub core: &'static str,
    /// The Rust target.
    pub target: &'static str,
    /// Most flash bytes the generic image may take.
    pub flash_budget: u64,
    /// Most static RAM bytes it may take.
    pub ram_budget: u64,
}

/// The cores beside the Cortex-M4 (mps2-an386, the board's default). The budgets leave about
/// 10 % over the generic image measured when they were set (flash / static RAM: M3
/// 119.0 KiB / 59.2 KiB, M7 119.2 / 59.2, M33 119.8 / 59.2; the M4's is 119.1 / 59.2).
pub const CORES: [Core; 3] = [
    Core {
        label: "enip-qemu-mps2 (an385)",
        feature: "an385",
        machine: "mps2-an385",
        core: "Cortex-M3",
        target: "thumbv7m-none-eabi",
        flash_budget: 132 * 1024,
        ram_budget: 66 * 1024,
    },
    Core {
        label: "enip-qemu-mps2 (an500)",
        feature: "an500",
        machine: "mps2-an500",
        core: "Cortex-M7",
        target: "thumbv7em-none-eabihf",
        flash_budget: 132 * 1024,
        ram_budget: 66 * 1024,
    },
    Core {
        label: "enip-qemu-mps2 (an505)",
        feature: "an505",
        machine: "mps2-an505",
        core: "Cortex-M33",
        target: "thumbv8m.main-none-eabihf",
        flash_budget: 132 * 1024,
        ram_budget: 66 * 1024,
    },
];

impl Core {
    /// Builds the generic image for this core in release with the build-time settings
    /// `env`; returns its copy `target/qemu-<feature>.elf` (the M7's build writes the same
    /// path as the M4's).
    pub fn build(&self, env: &[(&str, &str)]) -> Result<PathBuf> {
        self.build_with(boards::DEFAULT_PROFILE, env)
    }

    /// [`Core::build`] with the device profile `profile`.
    pub fn build_with(&self, profile: &str, env: &[(&str, &str)]) -> Result<PathBuf> {
        crate::setup::flip_link()?;
        let mut features = self.feature.to_string();
        if profile != boards::DEFAULT_PROFILE {
            features += &format!(",profile-{profile}");
        }
        let build = [
            "build",
            "-p",
            boards::QEMU,
            "--release",
            "--target",
            self.target,
        ];
        run(util::cargo()
            .args(build)
            .args(["--features", &features])
            .envs(env.iter().copied()))?;
        let built = util::target_dir()
            .join(self.target)
            .join("release")
            .join(boards::QEMU);
        let elf = util::target_dir().join(format!("qemu-{}.elf", self.feature));
        std::fs::copy(built, &elf)?;
        Ok(elf)
    }

    /// Clippy on its build, warnings denied.
    pub fn clippy(&self) -> Result {
        run(util::cargo()
            .args([
                "clippy",
                "-p",
                boards::QEMU,
                "--release",
                "--target",
                self.target,
            ])
            .args(["--features", self.feature, "--", "-D", "warnings"]))
    }

    /// The variable naming its ELF for the test: `ENIP_QEMU_AN385_ELF`.
    fn elf_var(&self) -> String {
        format!("ENIP_QEMU_{}_ELF", self.feature.to_uppercase())
    }
}

/// The step of `cargo xtask test`: each core's image boots in QEMU and serves pycomm3 and an
/// `ethernetip` owner at 10 ms (skipped, loudly, without root).
pub fn run_tests() -> Result<Outcome> {
    if !util::is_root() {
        loud("QEMU cores: SKIPPED: network namespaces need root");
        return Ok(Outcome::Skipped);
    }
    crate::qemu::ensure_installed()?;
    crate::setup::python_peers()?;
    let mut test = util::cargo();
    test.args(["test", "-p", "host-tests", "--test", "qemu_cores"])
        .args(["--", "--ignored", "--nocapture", "--test-threads=1"])
        .env("ENIP_PEER_PYTHON", peers::venv_python());
    for core in CORES {
        test.env(core.elf_var(), core.build(&[("ENIP_ACD", "off")])?);
    }
    run(&mut test)?;
    Ok(Outcome::Passed)
}

/// The traced runs of the QEMU benchmark on each core: the 1-connection one (and in the
/// full benchmark the 10-connection one too), as on the M4, whose results are `m4`; files
/// in `dir/<machine>`. Prints the cores side by side and returns their JSON by machine.
pub fn bench(scale: Scale, dir: &Path, m4: &[serde_json::Value]) -> Result<serde_json::Value> {
    let configs = match scale {
        Scale::Full => &crate::bench_qemu::TRACED[..],
        Scale::Check => &crate::bench_qemu::TRACED[..1],
    };
    let mut cores = serde_json::Map::new();
    let mut rows = vec![("Cortex-M4 (mps2-an386)".to_string(), m4.to_vec())];
    for core in CORES {
        let elf = core.build(&[("ENIP_ACD", "off")])?;
        let dir = dir.join(core.machine);
        std::fs::create_dir_all(&dir)?;
        let mut traced = Vec::new();
        for config in configs {
            let json = crate::bench_qemu::traced_median(core.machine, &elf, &dir, *config, scale)?;
            traced.push(json);
        }
        rows.push((format!("{} ({})", core.core, core.machine), traced.clone()));
        let entry = serde_json::json!({"core": core.core, "instructions_per_cycle": traced});
        cores.insert(core.machine.to_string(), entry);
    }
    println!("\nInstructions per Class 1 cycle by core (median of the traced runs):");
    for (name, traced) in rows {
        let figures: Vec<String> = traced
            .iter()
            .map(|t| format!("{} conn: {}", t["connections"], t["per_cycle"]))
            .collect();
        println!("  {name:<28} {}", figures.join(", "));
    }
    Ok(serde_json::Value::Object(cores))
}
