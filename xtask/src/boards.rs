//! The embedded boards: release builds for the Cortex-M target, and where their ELFs are.

use std::path::PathBuf;

use crate::setup::THUMB_TARGET;
use crate::util::{self, run, Result};

/// The NUCLEO-F767ZI board crate.
pub const NUCLEO: &str = "enip-nucleo-f767zi";
/// The QEMU mps2-an386 board crate.
pub const QEMU: &str = "enip-qemu-mps2";
/// The example firmware: the I/O block on the NUCLEO-F767ZI through the board's library.
pub const EXAMPLE_NUCLEO: &str = "io-block-nucleo";
/// The profile a board runs unless told otherwise.
pub const DEFAULT_PROFILE: &str = "generic";

/// The release ELF of `board` (its binary has the crate's name).
pub fn elf(board: &str) -> PathBuf {
    util::target_dir()
        .join(THUMB_TARGET)
        .join("release")
        .join(board)
}

/// Builds `board` in release for the Cortex-M target, running `profile` (its
/// `profile-NAME` feature; the default profile needs none); returns the ELF.
pub fn build(board: &str, profile: &str) -> Result<PathBuf> {
    let mut cargo = util::cargo();
    cargo.args(["build", "-p", board, "--release", "--target", THUMB_TARGET]);
    if profile != DEFAULT_PROFILE {
        cargo.args(["--features", &format!("profile-{profile}")]);
    }
    run(&mut cargo)?;
    Ok(elf(board))
}

/// Clippy on `board` as it is built (release, Cortex-M target), warnings denied.
pub fn clippy(board: &str) -> Result {
    run(util::cargo().args([
        "clippy",
        "-p",
        board,
        "--release",
        "--target",
        THUMB_TARGET,
        "--",
        "-D",
        "warnings",
    ]))
}

#[cfg(test)]
mod tests {
    use std::fs;

    use crate::util;

    /// Every profile the firmware has (its `profile-NAME` features) can be chosen on both
    /// embedded boards and is compiled into `enip-host`.
    #[test]
    fn every_profile_has_a_board_feature() {
        let manifest = |path: &str| {
            fs::read_to_string(util::root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
        };
        let firmware = manifest("firmware/Cargo.toml");
        let names: Vec<&str> = firmware
            .lines()
            .filter_map(|l| l.strip_prefix("profile-"))
            .filter_map(|l| l.split_once(" = ").map(|(name, _)| name))
            .collect();
        assert!(names.contains(&"generic"), "{names:?}");
        for board in ["nucleo-f767zi", "qemu-mps2", "host"] {
            let path = format!("boards/{board}/Cargo.toml");
            let board_manifest = manifest(&path);
            for name in &names {
                let line = format!("\nprofile-{name} = [\"enip-firmware/profile-{name}\"]");
                assert!(board_manifest.contains(&line), "{path} lacks{line}");
            }
        }
        let host = manifest("boards/host/Cargo.toml");
        let defaults = crate::workspace::string_array(&host, "default");
        for name in &names {
            let feature = format!("profile-{name}");
            assert!(
                defaults.contains(&feature),
                "enip-host's defaults lack {feature}"
            );
        }
    }
}
