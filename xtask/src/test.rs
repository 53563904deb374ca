//! `cargo xtask test`: the whole test suite, in order, stopping at the first failure.

use enip_lab::{peers, rig};

use crate::util::{self, loud, run, Outcome, Result, Steps};
use crate::workspace::Metadata;
use crate::{boards, footprint, fuzz, setup, smoke};

/// Seconds per fuzz target in the test run: a smoke run from the seeds (22 targets; the
/// long runs are `cargo xtask fuzz --campaign MINUTES`).
const FUZZ_SECONDS: u64 = 2;
/// The published crate whose `rust-version` the run builds with.
const PUBLISHED: &str = "enip-stack";
/// Every crate a device author needs: the `no_std` ones and the Linux host board's.
const PUBLISHED_CRATES: [&str; 5] = [
    "enip-stack",
    "enip-firmware",
    "enip-profiles",
    "enip-host-runtime",
    "enip-host",
];

/// `-p NAME` for each of `names`.
fn packages<'a>(names: &[&'a str]) -> Vec<&'a str> {
    names.iter().flat_map(|n| ["-p", n]).collect()
}

/// The TAP interop test file (written by the host-tests owners).
const TAP_INTEROP: &str = "host-tests/tests/tap_interop/main.rs";

/// Runs every step; true if none failed. Prints a summary either way.
pub fn run_all() -> bool {
    let mut steps = Steps::default();
    let cargo = |args: &[&str]| -> Result<Outcome> {
        run(util::cargo().args(args))?;
        Ok(Outcome::Passed)
    };
    // Host steps cover the default members (everything that builds on the host); the
    // workspace members outside them (the boards) build only for the embedded target, in
    // release as they ship.
    let no_std = ["enip-stack", "enip-firmware", "enip-profiles"];
    let mut cross_crates = Vec::new();
    // `&&` stops at the first failed step; the summary lists the steps that ran.
    let mut ok = steps.run("setup", || setup::all().map(|()| Outcome::Passed))
        && steps.run("rustfmt", || {
            cargo(&["fmt", "--all", "--", "--check"])?;
            cargo(&["fmt", "--manifest-path", "fuzz/Cargo.toml", "--", "--check"])
        })
        && steps.run("module graph (stack, profiles)", || {
            crate::module_graph::check().map(|()| Outcome::Passed)
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
        // host-tests' start-up checks run the enip-host binary, which `cargo test` alone
        // does not build.
        && steps.run("unit and integration tests", || {
            cargo(&["build", "-p", "enip-host"])?;
            cargo(&["test"])
        })
        && steps.run("list the cross-only crates", || {
            cross_crates.extend(Metadata::read()?.cross_only_packages());
            let each = cross_crates.iter().map(|b| format!("{b} ({})", boards::target(b)));
            println!("boards built: {}", each.collect::<Vec<_>>().join(", "));
            Ok(Outcome::Passed)
        });
    for package in no_std {
        ok = ok
            && steps.run(&format!("no_std build: {package}"), || {
                cargo(&["build", "-p", package, "--target", setup::THUMB_TARGET])
            });
    }
    // The published crates: the rust-version they claim builds them, and they package.
    ok =
        ok && steps.run(
            "rust-version and cargo publish --dry-run (every crate a device author needs)",
            || {
                // The claimed toolchain: the active one when it is that version (a fresh machine
                // may have no toolchain of that name), else that toolchain through rustup.
                let toolchain = Metadata::read()?.rust_version_toolchain(PUBLISHED)?;
                let active = util::output(std::process::Command::new("rustc").arg("--version"))
                    .unwrap_or_default();
                let mut build = if active.split_whitespace().nth(1) == Some(toolchain.as_str()) {
                    util::cargo()
                } else {
                    let mut rustup = std::process::Command::new("rustup");
                    rustup.args(["run", &toolchain, "cargo"]);
                    rustup
                };
                build.args(["build", "--target", setup::THUMB_TARGET]);
                run(build.args(packages(&no_std)))?;
                forget_packaged_crates();
                // Each packaged and verified in dependency order, against the others'
                // packages (cargo's local registry of the dry run), none from crates.io.
                let publish = ["publish", "--dry-run", "--allow-dirty"];
                cargo(&[&publish[..], &packages(&PUBLISHED_CRATES)].concat())
            },
        ) && steps.run(
            "an own device from a project of its own (README snippet, --eds)",
            crate::own_device::run_check,
        );
    for board in &cross_crates {
        ok = ok
            && steps.run(&format!("board: {board} (release build, clippy)"), || {
                boards::build(board, boards::DEFAULT_PROFILE)?;
                boards::clippy(board)?;
                Ok(Outcome::Passed)
            });
    }
    for core in crate::qemu_cores::CORES {
        ok = ok
            && steps.run(
                &format!("board: {} (release build, clippy)", core.label),
                || {
                    core.build(&[])?;
                    core.clippy()?;
                    Ok(Outcome::Passed)
                },
            );
    }
    let _all_passed =
        ok && steps.run("footprint and the F767 budget", || {
            footprint::footprint().map(|()| Outcome::Passed)
        }) && steps.run("fuzz", || fuzz::run_all(FUZZ_SECONDS))
            && steps.run("TAP interop", tap_interop)
            && steps.run("interop on kernel sockets (enip-host --bind)", bind_interop)
            && steps.run(
                "interop on one device of a fleet (enip-host --devices)",
                fleet_interop,
            )
            && steps.run("QEMU smoke run", smoke::run_smoke)
            && steps.run(
                "QEMU cores M3, M7, M33: pycomm3, ethernetip owner at 10 ms",
                crate::qemu_cores::run_tests,
            )
            && steps.run("the benchmark runs (bench --check)", || {
                crate::bench::check().map(|()| Outcome::Passed)
            });
    steps.summary()
}

/// The cargo profile the interop suites' boards are built with: optimized, so the 1 ms soak
/// measures the adapter rather than a debug build (whose CPU time under SCHED_FIFO ran into
/// the kernel's real-time throttling, a 50 ms stall), with overflow checks kept.
pub(crate) const INTEROP_PROFILE: &str = "interop";

/// The TAP interop suite: ignored tests in host-tests, run one at a time with the peers.
fn tap_interop() -> Result<Outcome> {
    let root = util::root();
    if !root.join(TAP_INTEROP).exists() {
        loud(&format!(
            "TAP interop: SKIPPED: {TAP_INTEROP} does not exist yet"
        ));
        return Ok(Outcome::Skipped);
    }
    build_interop_boards()?;
    // The profiles' scenarios (and the default profile's LLDP, QoS and ACD checks) also run on
    // the emulated board: a copy of its ELF per profile (ENIP_QEMU_<PROFILE>_ELF), since every
    // build writes the same path. The profiles' scenarios are built without Address Conflict
    // Detection (its seconds of probing are not what they test); the default profile's, which
    // the ACD tests boot, with.
    let mut elves = Vec::new();
    let profiles = boards::profiles(&Metadata::read()?)?;
    for profile in &profiles {
        let acd = if profile == boards::DEFAULT_PROFILE {
            "on"
        } else {
            "off"
        };
        let elf = util::target_dir().join(format!("qemu-{profile}.elf"));
        std::fs::copy(
            boards::build_with(boards::QEMU, profile, &[("ENIP_ACD", acd)])?,
            &elf,
        )?;
        elves.push((rig::qemu_elf_var(profile), elf));
    }
    // The Ametek PLS whose resolver turns from power-up (60 RPM, a build-time setting).
    let moving = util::target_dir().join("qemu-ametek-pls-moving.elf");
    let settings = [("ENIP_PLS_RPM", "60"), ("ENIP_ACD", "off")];
    let built = boards::build_with(boards::QEMU, "ametek-pls", &settings)?;
    std::fs::copy(built, &moving)?;
    elves.push(("ENIP_QEMU_AMETEK_PLS_MOVING_ELF".to_string(), moving));
    // EtherNet/IP over TLS through mbedTLS (issue 24).
    elves.push(("ENIP_QEMU_TLS_ELF".to_string(), boards::qemu_tls_image()?));
    // The test image that faults on purpose (stack overflow, hang, panic) when asked over CIP.
    let faults = boards::faults_image()?;
    elves.push(("ENIP_QEMU_FAULTS_ELF".to_string(), faults.clone()));
    run(interop(&[]).envs(elves))?;
    // The hostile battery again on the emulated board, which reports its stack's high-water
    // mark at the end of each test.
    run(interop(&["hostile_"]).env(rig::QEMU_BOARD_ENV, &faults))?;
    Ok(Outcome::Passed)
}

/// Builds the host boards the interop suites start (`enip-host`, `io-block-host`) with the
/// [`INTEROP_PROFILE`].
pub fn build_interop_boards() -> Result {
    run(util::cargo().args([
        "build",
        "--profile",
        INTEROP_PROFILE,
        "-p",
        "enip-host",
        "-p",
        "io-block-host",
    ]))
}

/// The same peers against `enip-host --bind` on kernel sockets over a veth pair (the lab's
/// `ENIP_HOST_LINK=bind`): explicit messaging (pycomm3, cpppo), Class 1 (ethernetip,
/// st-ethernet-ip, EIPScanner input-only, listen-only multicast), Class 3, the fourth client
/// refused, UDP, the hostile battery, and DSCP marking through `IP_TOS`.
fn bind_interop() -> Result<Outcome> {
    let filters = [
        "explicit::",
        "class1::",
        "class3::",
        "concurrency::",
        "udp::",
        "hostile_",
        "qos::dscp_marking_follows",
    ];
    run(interop(&filters).env(rig::LINK_ENV, "bind"))?;
    Ok(Outcome::Passed)
}

/// A share of the same peers against one device of a fleet of two in one `enip-host
/// --devices` process (the lab's `ENIP_HOST_LINK=fleet`): a device of a fleet behaves as a
/// lone `--bind` one, its neighbour's broadcast replies aside. (The whole `--bind` share
/// passes there too; this keeps the step short.)
fn fleet_interop() -> Result<Outcome> {
    let filters = [
        "explicit::pycomm3",
        "class1::ethernetip",
        "class3::",
        "concurrency::fourth",
        "udp::",
        "hostile_framing::",
    ];
    run(interop(&filters).env(rig::LINK_ENV, "fleet"))?;
    Ok(Outcome::Passed)
}

/// `cargo test` of the TAP interop suite, one test at a time, with the tests matching
/// `filters` (all without), and where the boards and peers are.
pub fn interop(filters: &[&str]) -> std::process::Command {
    let boards = util::target_dir().join(INTEROP_PROFILE);
    let mut cmd = util::cargo();
    cmd.args(["test", "-p", "host-tests", "--test", "tap_interop", "--"])
        .args(filters)
        .args(["--ignored", "--test-threads=1"])
        .env("ENIP_PEER_PYTHON", peers::venv_python())
        .env("ENIP_HOST_BIN", boards.join("enip-host"))
        .env("ENIP_EXAMPLE_BIN", boards.join("io-block-host"))
        .env("ENIP_PEER_NPM_DIR", peers::npm_dir());
    cmd
}

/// Removes what an earlier `cargo publish --dry-run` left in cargo's registry cache: the
/// packaged enip crates unpacked from its local registry, which cargo would otherwise reuse
/// (same name and version) instead of today's sources.
fn forget_packaged_crates() {
    let home = std::env::var_os("CARGO_HOME")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| std::path::Path::new(&h).join(".cargo")));
    let Some(registry) = home.map(|h| h.join("registry")) else {
        return;
    };
    for kind in ["src", "cache"] {
        let Ok(indexes) = std::fs::read_dir(registry.join(kind)) else {
            continue;
        };
        for entry in indexes
            .flatten()
            .flat_map(|i| std::fs::read_dir(i.path()).into_iter().flatten().flatten())
        {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            let ours = [
                "enip-stack-",
                "enip-firmware-",
                "enip-profiles-",
                "enip-host-",
            ];
            if ours.iter().any(|p| name.starts_with(p)) {
                let path = entry.path();
                let _ = if path.is_dir() {
                    std::fs::remove_dir_all(&path)
                } else {
                    std::fs::remove_file(&path)
                };
            }
        }
    }
    let _ = std::fs::remove_dir_all(util::target_dir().join("package"));
}
