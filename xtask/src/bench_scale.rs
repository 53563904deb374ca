//! How long and how often `cargo xtask bench` measures: the benchmark itself, or the check
//! `cargo xtask test` runs (`bench --check`: every part once and briefly, into a directory
//! of its own) to show that the benchmark still runs and reports every figure.

use std::path::PathBuf;

use crate::util::{self, cargo, run, Result};

/// The benchmark's size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    /// The figures the README quotes.
    Full,
    /// Every part, briefly: that it runs, not what it measures.
    Check,
}

impl Scale {
    /// Where the reports go: `target/bench`, or `target/bench-check`.
    pub fn dir(self) -> PathBuf {
        util::target_dir().join(self.pick("bench", "bench-check"))
    }

    /// Iterations of the short and long callgrind runs of the cycle drivers.
    pub fn callgrind_cycles(self) -> (u64, u64) {
        self.pick((1_000, 11_000), (100, 1_100))
    }

    /// Iterations of each native timing run of `io_cycle`, and how many runs.
    pub fn native(self) -> (u64, usize) {
        self.pick((2_000_000, 3), (100_000, 1))
    }

    /// Seconds of the host board's 10 x 1 ms run, and of the timer floor beside it.
    pub fn tap_seconds(self) -> (u32, u32) {
        self.pick((60, 10), (3, 1))
    }

    /// Traced runs of the emulated board per configuration, and the O->T datagrams each
    /// skips and then counts per connection.
    pub fn qemu_traced(self) -> (usize, u64, u64) {
        self.pick((3, 100, 300), (1, 10, 30))
    }

    /// Seconds of each untraced timing run of the emulated board.
    pub fn qemu_timing_seconds(self) -> u32 {
        self.pick(10, 2)
    }

    /// Seconds of the host runtimes' short and long samples, and of each request-rate run.
    pub fn host_seconds(self) -> (u64, u64, u64) {
        self.pick((5, 15, 3), (2, 4, 1))
    }

    /// Rounds of the host boards' request-rate runs (the boards take turns). The rates of
    /// one board differ by up to 3x from round to round on a shared 2-core machine (where
    /// the scheduler puts the board and the client's threads), so the medians need many
    /// short rounds more than a few long ones.
    pub fn rate_rounds(self) -> usize {
        self.pick(15, 1)
    }

    /// Builds the host board and returns its binary: the release build for the figures; for
    /// the check, the interop suite's build of the same code (optimized, overflow checks on),
    /// which `cargo xtask test` has made by then, instead of two minutes more of building.
    pub fn enip_host(self) -> Result<PathBuf> {
        let profile = match self {
            Scale::Full => {
                run(cargo().args(["build", "--release", "-p", "enip-host"]))?;
                "release"
            }
            Scale::Check => {
                crate::test::build_interop_boards()?;
                crate::test::INTEROP_PROFILE
            }
        };
        Ok(util::target_dir().join(profile).join("enip-host"))
    }

    fn pick<T>(self, full: T, check: T) -> T {
        match self {
            Scale::Full => full,
            Scale::Check => check,
        }
    }
}
