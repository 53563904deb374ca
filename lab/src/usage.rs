//! What a running process costs, read from `/proc`: its CPU time and resident memory
//! ([`usage`]) and the context switches of all its threads ([`context_switches`]); the fault
//! tests and the host benchmark read their boards with these.

use std::fs;
use std::io;

/// CPU time and resident memory of a process at one moment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Usage {
    /// User plus system CPU time, in clock ticks ([`ticks_per_second`]).
    pub cpu_ticks: u64,
    /// Resident set size, KiB.
    pub rss_kib: u64,
}

/// Clock ticks per second of `/proc/PID/stat`'s CPU times.
pub fn ticks_per_second() -> u64 {
    Some(rustix::param::clock_ticks_per_second())
        .filter(|&t| t > 0)
        .unwrap_or(100)
}

/// Reads process `pid`'s CPU time (`/proc/PID/stat` utime + stime) and resident memory
/// (`/proc/PID/status` VmRSS).
pub fn usage(pid: u32) -> io::Result<Usage> {
    let stat = fs::read_to_string(format!("/proc/{pid}/stat"))?;
    let status = fs::read_to_string(format!("/proc/{pid}/status"))?;
    Ok(Usage {
        cpu_ticks: cpu_ticks(&stat).ok_or_else(|| io::Error::other(format!("stat: {stat}")))?,
        rss_kib: rss_kib(&status).ok_or_else(|| io::Error::other("no VmRSS in status"))?,
    })
}

/// Context switches so far (voluntary and not) of every thread of process `pid`, from
/// `/proc/PID/task/*/status`; 0 if the process is gone.
pub fn context_switches(pid: u32) -> u64 {
    let Ok(tasks) = fs::read_dir(format!("/proc/{pid}/task")) else {
        return 0;
    };
    tasks
        .flatten()
        .filter_map(|t| fs::read_to_string(t.path().join("status")).ok())
        .map(|status| switches(&status))
        .sum()
}

/// utime + stime (fields 14 and 15) of a `/proc/PID/stat` line; the command name in
/// parentheses may contain spaces, so fields are counted after its closing parenthesis.
fn cpu_ticks(stat: &str) -> Option<u64> {
    let rest = stat.get(stat.rfind(')')? + 1..)?;
    let mut fields = rest.split_whitespace().skip(11);
    let utime: u64 = fields.next()?.parse().ok()?;
    let stime: u64 = fields.next()?.parse().ok()?;
    Some(utime + stime)
}

/// The `VmRSS:` value (KiB) of a `/proc/PID/status` text.
fn rss_kib(status: &str) -> Option<u64> {
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The sum of the `voluntary_ctxt_switches:` and `nonvoluntary_ctxt_switches:` values of a
/// thread's `status` text.
fn switches(status: &str) -> u64 {
    status
        .lines()
        .filter(|l| l.contains("ctxt_switches:"))
        .filter_map(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proc_fields() {
        let stat = "4242 (enip host) S 1 2 3 4 5 6 7 8 9 10 250 31 0 0 20 0 3 0 99 1000 200";
        assert_eq!(cpu_ticks(stat), Some(281));
        assert_eq!(cpu_ticks("4242 (x) S 1"), None);
        let status = "Name:\tenip-host\nVmPeak:\t  9000 kB\nVmRSS:\t    4711 kB\nThreads:\t1\n\
                      voluntary_ctxt_switches:\t120\nnonvoluntary_ctxt_switches:\t7\n";
        assert_eq!(rss_kib(status), Some(4711));
        assert_eq!(rss_kib("Name: x\n"), None);
        assert_eq!(switches(status), 127);
        assert_eq!(switches("Name: x\n"), 0);
    }

    #[test]
    fn own_usage_is_readable() {
        let u = usage(std::process::id()).unwrap();
        assert!(u.rss_kib > 0);
        assert!(context_switches(std::process::id()) > 0);
    }
}
