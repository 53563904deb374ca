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

    /// Every profile `firmware::Profile::NAMES` lists can be chosen on both boards.
    #[test]
    fn every_profile_has_a_board_feature() {
        let profiles = fs::read_to_string(util::root().join("firmware/src/profiles/mod.rs"))
            .expect("firmware/src/profiles/mod.rs");
        let names = profiles
            .lines()
            .find_map(|l| {
                l.trim()
                    .strip_prefix("pub const NAMES: &'static [&'static str] = &[")
            })
            .expect("Profile::NAMES on one line");
        let names: Vec<&str> = names
            .trim_end_matches("];")
            .split(',')
            .map(|n| n.trim().trim_matches('"'))
            .filter(|n| !n.is_empty())
            .collect();
        assert!(names.contains(&"generic"), "{names:?}");
        for board in ["nucleo-f767zi", "qemu-mps2"] {
            let manifest =
                fs::read_to_string(util::root().join("boards").join(board).join("Cargo.toml"))
                    .expect("board manifest");
            for name in &names {
                assert!(
                    manifest.contains(&format!("\nprofile-{name} = []")),
                    "boards/{board}/Cargo.toml lacks the feature profile-{name}"
                );
            }
        }
    }
}
