//! The embedded boards: release builds for the Cortex-M target, and where their ELFs are.

use std::path::PathBuf;

use crate::setup::{self, THUMBV6M_TARGET, THUMB_TARGET};
use crate::util::{self, run, Result};
use crate::workspace::Metadata;

/// The NUCLEO-F767ZI board crate.
pub const NUCLEO: &str = "enip-nucleo-f767zi";
/// The QEMU mps2-an386 board crate.
pub const QEMU: &str = "enip-qemu-mps2";
/// The example firmware: the I/O block on the NUCLEO-F767ZI through the board's library.
pub const EXAMPLE_NUCLEO: &str = "io-block-nucleo";
/// The NUCLEO-H743ZI board crate.
pub const NUCLEO_H743: &str = "enip-nucleo-h743zi";
/// The I/O block on the NUCLEO-H743ZI.
pub const EXAMPLE_NUCLEO_H743: &str = "io-block-nucleo-h743zi";
/// The NUCLEO-H563ZI board crate (Cortex-M33).
pub const NUCLEO_H563: &str = "enip-nucleo-h563zi";
/// The I/O block on the NUCLEO-H563ZI.
pub const EXAMPLE_NUCLEO_H563: &str = "io-block-nucleo-h563zi";
/// The W5500-EVB-Pico board crate (RP2040, Cortex-M0+).
pub const PICO: &str = "enip-w5500-evb-pico";
/// The example firmware: the I/O block on the W5500-EVB-Pico.
pub const EXAMPLE_PICO: &str = "io-block-pico";
/// The emulated board with EtherNet/IP over TLS through mbedTLS (its feature `tls`): the
/// footprint's name for [`qemu_tls_image`].
pub const QEMU_TLS: &str = "enip-qemu-mps2 +tls";
/// The profile a board runs unless told otherwise.
pub const DEFAULT_PROFILE: &str = "generic";

/// The profiles crate, whose features enabling [`ANY_PROFILE`] are the device profiles.
const PROFILES: &str = "enip-profiles";
/// The internal feature of the profiles crate that every profile's feature enables.
const ANY_PROFILE: &str = "_any-profile";

/// The device profiles: the features of the profiles crate that are a profile, sorted.
pub fn profiles(metadata: &Metadata) -> Result<Vec<String>> {
    let mut names = Vec::new();
    for feature in metadata.features(PROFILES)? {
        let enables = metadata.feature(PROFILES, &feature)?.unwrap_or_default();
        if enables.iter().any(|f| f == ANY_PROFILE) {
            names.push(feature);
        }
    }
    Ok(names)
}

/// The target `board` builds for: the Cortex-M33 boards' [`setup::V8M_TARGET`], else
/// [`THUMB_TARGET`].
pub fn target(board: &str) -> &'static str {
    match board {
        NUCLEO_H563 | EXAMPLE_NUCLEO_H563 => setup::V8M_TARGET,
        PICO | EXAMPLE_PICO => THUMBV6M_TARGET,
        _ => THUMB_TARGET,
    }
}

/// The release ELF of `board` (its binary has the crate's name).
pub fn elf(board: &str) -> PathBuf {
    util::target_dir()
        .join(target(board))
        .join("release")
        .join(board)
}

/// Builds `board` in release for its Cortex-M target ([`target`]), running `profile` (its
/// `profile-NAME` feature; the default profile needs none); returns the ELF.
pub fn build(board: &str, profile: &str) -> Result<PathBuf> {
    build_with(board, profile, &[])
}

/// [`build`] with build-time settings in the environment, read with `option_env!` so cargo
/// rebuilds when they change: the emulated board's `ENIP_ACD` (Address Conflict Detection on
/// or off at start; the others ignore it) and `ENIP_TEST_FAULTS`, the Ametek profile's
/// `ENIP_PLS_RPM`.
pub fn build_with(board: &str, profile: &str, env: &[(&str, &str)]) -> Result<PathBuf> {
    // The boards link through it (`.cargo/config.toml`).
    setup::flip_link()?;
    let mut cargo = util::cargo();
    cargo.args(["build", "-p", board, "--release", "--target", target(board)]);
    cargo.envs(env.iter().copied());
    if profile != DEFAULT_PROFILE {
        cargo.args(["--features", &format!("profile-{profile}")]);
    }
    run(&mut cargo)?;
    Ok(elf(board))
}

/// Builds the emulated board's test image (generic profile, `ENIP_TEST_FAULTS=on`, Address
/// Conflict Detection off), which faults on purpose when asked over CIP; returns its copy,
/// `target/qemu-faults.elf`.
pub fn faults_image() -> Result<PathBuf> {
    let elf = util::target_dir().join("qemu-faults.elf");
    let settings = [("ENIP_TEST_FAULTS", "on"), ("ENIP_ACD", "off")];
    std::fs::copy(build_with(QEMU, DEFAULT_PROFILE, &settings)?, &elf)?;
    Ok(elf)
}

/// Builds the emulated board with feature `tls` (mbedTLS on 2221; generic profile); returns
/// its copy, `target/qemu-tls.elf` (the build itself has the plain image's path).
pub fn qemu_tls_image() -> Result<PathBuf> {
    setup::flip_link()?;
    let elf = util::target_dir().join("qemu-tls.elf");
    run(util::cargo().args([
        "build",
        "-p",
        QEMU,
        "--release",
        "--target",
        THUMB_TARGET,
        "--features",
        "tls",
    ]))?;
    std::fs::copy(self::elf(QEMU), &elf)?;
    Ok(elf)
}

/// Clippy on `board` as it is built (release, its Cortex-M target), warnings denied; the
/// emulated board also with its `tls` feature.
pub fn clippy(board: &str) -> Result {
    let args = [
        "clippy",
        "-p",
        board,
        "--release",
        "--target",
        target(board),
    ];
    let deny = ["--", "-D", "warnings"];
    run(util::cargo().args(args).args(deny))?;
    if board == QEMU {
        run(util::cargo()
            .args(args)
            .args(["--features", "tls"])
            .args(deny))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every profile can be chosen on every embedded board (a `profile-NAME` feature
    /// enabling the profiles crate's `NAME`) and is compiled into `enip-host` by default.
    #[test]
    fn the_pico_and_its_example_build_for_the_cortex_m0_plus() {
        assert_eq!(target(PICO), "thumbv6m-none-eabi");
        assert_eq!(target(EXAMPLE_PICO), "thumbv6m-none-eabi");
        assert_eq!(target(NUCLEO), THUMB_TARGET);
        assert!(elf(PICO).ends_with("thumbv6m-none-eabi/release/enip-w5500-evb-pico"));
    }

    #[test]
    fn every_profile_has_a_board_feature() {
        let metadata = Metadata::read().unwrap();
        let names = profiles(&metadata).unwrap();
        assert!(names.contains(&DEFAULT_PROFILE.to_string()), "{names:?}");
        for board in [NUCLEO, QEMU, NUCLEO_H743, NUCLEO_H563, PICO, "enip-host"] {
            for name in &names {
                let feature = format!("profile-{name}");
                let enables = metadata.feature(board, &feature).unwrap();
                assert_eq!(
                    enables,
                    Some(vec![format!("{PROFILES}/{name}")]),
                    "{board}'s {feature}"
                );
            }
        }
        let defaults = metadata.feature("enip-host", "default").unwrap().unwrap();
        for name in &names {
            let feature = format!("profile-{name}");
            assert!(
                defaults.contains(&feature),
                "enip-host's defaults lack {feature}"
            );
        }
    }

    /// The Cortex-M33 boards build for thumbv8m.main, the others for thumbv7em, and their
    /// ELF is under their target's directory.
    #[test]
    fn each_board_builds_for_its_core() {
        for board in [NUCLEO_H563, EXAMPLE_NUCLEO_H563] {
            assert_eq!(target(board), "thumbv8m.main-none-eabihf");
            assert!(elf(board).starts_with(util::target_dir().join(setup::V8M_TARGET)));
        }
        for board in [
            NUCLEO,
            QEMU,
            EXAMPLE_NUCLEO,
            NUCLEO_H743,
            EXAMPLE_NUCLEO_H743,
        ] {
            assert_eq!(target(board), THUMB_TARGET);
        }
    }
}
