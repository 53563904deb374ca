//! Network namespaces a test (or an xtask command) creates for itself, each with a TAP link
//! (198.18.0.0/24), so that every frame it sends stays there and nothing reaches the
//! machine's real networks.
//!
//! Programs run inside with `ip netns exec`; the test process itself reaches in by opening
//! sockets on a short-lived thread that joined the namespace (see [`Namespace::inside`]).
//! Sockets keep the namespace they were made in, so they can be used from any thread after.

use std::ffi::OsStr;
use std::fs::File;
use std::io;
use std::net::Ipv4Addr;
use std::os::fd::AsFd;
use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Duration;

use rustix::thread::{move_into_link_name_space, LinkNameSpaceType};

use crate::process::{run_bounded, signal, SIGKILL};

/// How long one `ip` command may take.
const IP_TIMEOUT: Duration = Duration::from_secs(10);
/// How often, and how many times, a new link is checked for its carrier.
const CARRIER_POLL: Duration = Duration::from_millis(20);
const CARRIER_POLLS: u32 = 100;

/// The kernel's address on the TAP (where every peer runs).
pub const HOST_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
/// The board's address (its own TCP/IP stack, not a kernel address).
pub const BOARD_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
/// The board's address with its prefix, as the boards' `--ip` takes it.
pub const BOARD_CIDR: &str = "198.18.0.2/24";
/// The subnet's directed broadcast address.
pub const BROADCAST_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 255);
/// Prefix length of the subnet.
pub const PREFIX: u8 = 24;

/// A network namespace, deleted (with every process still inside it) when dropped.
#[derive(Debug)]
pub struct Namespace {
    name: String,
}

impl Namespace {
    /// Creates a namespace with a name no other test (or run) uses, with `lo` up.
    pub fn create() -> io::Result<Self> {
        static NEXT: AtomicU32 = AtomicU32::new(0);
        let name = format!(
            "enip-t{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        Self::add(name)
    }

    /// Creates the namespace `name` (a fixed name, for a command a person runs), first
    /// deleting a stale one of that name with everything still running in it.
    pub fn create_named(name: &str) -> io::Result<Self> {
        drop(Namespace {
            name: name.to_string(),
        });
        Self::add(name.to_string())
    }

    fn add(name: String) -> io::Result<Self> {
        ip(&["netns", "add", &name])?;
        let ns = Namespace { name };
        ns.exec_checked("ip", &["link", "set", "lo", "up"])?;
        Ok(ns)
    }

    /// The namespace's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// A command that runs `program` inside the namespace.
    pub fn command(&self, program: impl AsRef<OsStr>) -> Command {
        let mut c = Command::new("ip");
        c.args(["netns", "exec", &self.name]).arg(program);
        c
    }

    /// Runs `program args` inside the namespace (bounded) and fails unless it succeeds.
    pub fn exec_checked(&self, program: &str, args: &[&str]) -> io::Result<()> {
        let mut c = self.command(program);
        c.args(args);
        check(run_bounded(c, None, IP_TIMEOUT)?, program, args)
    }

    /// Runs `f` on a thread that has joined the namespace; sockets it opens live there.
    pub fn inside<T: Send>(&self, f: impl FnOnce() -> T + Send) -> io::Result<T> {
        let file = File::open(format!("/run/netns/{}", self.name))?;
        std::thread::scope(|s| {
            s.spawn(|| {
                // Only this (scoped, short-lived) thread changes its network namespace.
                move_into_link_name_space(file.as_fd(), Some(LinkNameSpaceType::Network))?;
                Ok(f())
            })
            .join()
            .map_err(|_| io::Error::other("thread inside the namespace panicked"))?
        })
    }

    /// Process ids of everything running inside the namespace.
    fn pids(&self) -> Vec<i32> {
        let mut c = Command::new("ip");
        c.args(["netns", "pids", &self.name]);
        run_bounded(c, None, IP_TIMEOUT)
            .map(|o| {
                String::from_utf8_lossy(&o.stdout)
                    .split_whitespace()
                    .filter_map(|p| p.parse().ok())
                    .collect()
            })
            .unwrap_or_default()
    }
}

impl Drop for Namespace {
    fn drop(&mut self) {
        // Only its owner started processes in the namespace; none may outlive it.
        for pid in self.pids() {
            signal(pid, SIGKILL);
        }
        if Path::new("/run/netns").join(&self.name).exists() {
            if let Err(e) = ip(&["netns", "delete", &self.name]) {
                eprintln!("warning: could not delete namespace {}: {e}", self.name);
            }
        }
    }
}

/// A namespace holding the link a board attaches to, up at [`HOST_IP`]/[`PREFIX`]: a TAP
/// device, or one end of a veth pair whose other end, at [`BOARD_IP`], is in a namespace of
/// the board's own (a board on the kernel's sockets). Deleted, with everything in it, when
/// dropped.
#[derive(Debug)]
pub struct Lab {
    /// The link device's name inside the namespace (the TAP, or the peers' veth end).
    pub tap: String,
    ns: Namespace,
    /// The board's own namespace, with the other veth end (none on a TAP); deleted last.
    board_ns: Option<Namespace>,
}

/// The board's end of the veth pair, in its own namespace.
pub const BOARD_VETH: &str = "enipb0";
/// The TAP's queue length toward the board, in frames: a MAC's receive ring.
const TAP_RING: &str = "64";

impl Lab {
    /// Creates the namespace `name` (replacing a stale one) with the TAP `tap`.
    pub fn create(name: &str, tap: &str) -> io::Result<Self> {
        Self::with_tap(Namespace::create_named(name)?, tap)
    }

    /// Creates a namespace with a name of its own (see [`Namespace::create`]) with the TAP
    /// `tap`.
    pub fn create_unique(tap: &str) -> io::Result<Self> {
        Self::with_tap(Namespace::create()?, tap)
    }

    fn with_tap(ns: Namespace, tap: &str) -> io::Result<Self> {
        ns.exec_checked("ip", &["tuntap", "add", "dev", tap, "mode", "tap"])?;
        // The frames the kernel holds for the board: a MAC's receive ring (64), not the
        // TAP's default 500, so a flood past what the board reads is dropped there, as on
        // hardware, instead of queuing for tens of milliseconds ahead of the O->T data.
        ns.exec_checked("ip", &["link", "set", tap, "txqueuelen", TAP_RING])?;
        let host = format!("{HOST_IP}/{PREFIX}");
        ns.exec_checked("ip", &["addr", "add", &host, "dev", tap])?;
        ns.exec_checked("ip", &["link", "set", tap, "up"])?;
        Ok(Lab {
            tap: tap.to_string(),
            ns,
            board_ns: None,
        })
    }

    /// Creates a namespace with a name of its own holding the veth end `link` at
    /// [`HOST_IP`], and the board's namespace holding the other end, [`BOARD_VETH`], at
    /// [`BOARD_IP`]: every frame crosses a link, as on a TAP.
    pub fn create_veth(link: &str) -> io::Result<Self> {
        let ns = Namespace::create()?;
        let board_ns = Namespace::create()?;
        let peer = ["peer", "name", BOARD_VETH, "netns", board_ns.name()];
        let mut add = vec!["link", "add", link, "type", "veth"];
        add.extend(peer);
        ns.exec_checked("ip", &add)?;
        for (n, dev, ip) in [(&ns, link, HOST_IP), (&board_ns, BOARD_VETH, BOARD_IP)] {
            n.exec_checked(
                "ip",
                &["addr", "add", &format!("{ip}/{PREFIX}"), "dev", dev],
            )?;
            n.exec_checked("ip", &["link", "set", dev, "up"])?;
        }
        wait_carrier(&board_ns, BOARD_VETH)?;
        Ok(Lab {
            tap: link.to_string(),
            ns,
            board_ns: Some(board_ns),
        })
    }

    /// Adds `cidrs` (addresses with their prefix, inside 198.18.0.0/15) to the board's end of
    /// the veth pair, beside [`BOARD_IP`]: the addresses of a fleet's devices on the kernel's
    /// sockets. One `ip -batch` for them all.
    pub fn add_board_addresses(&self, cidrs: &[String]) -> io::Result<()> {
        let ns = self
            .board_ns
            .as_ref()
            .ok_or_else(|| io::Error::other("a TAP lab has no kernel address of the board"))?;
        let batch: String = cidrs
            .iter()
            .map(|c| format!("addr add {c} dev {BOARD_VETH}\n"))
            .collect();
        let mut c = ns.command("ip");
        c.args(["-batch", "-"]);
        check(
            run_bounded(c, Some(batch.as_bytes()), IP_TIMEOUT)?,
            "ip",
            &["-batch", "-"],
        )
    }

    /// The namespace.
    pub fn ns(&self) -> &Namespace {
        &self.ns
    }

    /// A command that runs `program` inside the namespace.
    pub fn command(&self, program: impl AsRef<OsStr>) -> Command {
        self.ns.command(program)
    }

    /// A command that runs `program` where the board runs: its own namespace on a veth pair,
    /// else the namespace.
    pub fn board_command(&self, program: impl AsRef<OsStr>) -> Command {
        self.board_ns.as_ref().unwrap_or(&self.ns).command(program)
    }
}

/// Waits (bounded) until `dev` in `ns` is operationally up with its carrier, as a cable
/// plugged in before the board starts (the kernel reports a new veth up a moment later).
fn wait_carrier(ns: &Namespace, dev: &str) -> io::Result<()> {
    for _ in 0..CARRIER_POLLS {
        let mut c = ns.command("ip");
        c.args(["-brief", "link", "show", dev]);
        let out = run_bounded(c, None, IP_TIMEOUT)?;
        let text = String::from_utf8_lossy(&out.stdout);
        if text.split_whitespace().nth(1) == Some("UP") && !text.contains("NO-CARRIER") {
            return Ok(());
        }
        std::thread::sleep(CARRIER_POLL);
    }
    Err(io::Error::other(format!("{dev}: no carrier")))
}

/// Runs `ip args` in the test's own namespace (only `netns` management is done this way).
fn ip(args: &[&str]) -> io::Result<()> {
    let mut c = Command::new("ip");
    c.args(args);
    check(run_bounded(c, None, IP_TIMEOUT)?, "ip", args)
}

fn check(out: std::process::Output, program: &str, args: &[&str]) -> io::Result<()> {
    if out.status.success() {
        Ok(())
    } else {
        Err(io::Error::other(format!(
            "`{program} {}` failed ({}): {}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_link_addresses_agree() {
        assert_eq!(BOARD_CIDR, format!("{BOARD_IP}/{PREFIX}"));
        let net = |a: Ipv4Addr| u32::from(a) >> (32 - PREFIX);
        assert_eq!(net(HOST_IP), net(BOARD_IP));
        assert_eq!(net(BROADCAST_IP), net(BOARD_IP));
        assert_eq!(
            u32::from(BROADCAST_IP) | (u32::MAX << (32 - PREFIX)),
            u32::MAX
        );
        // Inside 198.18.0.0/15, the benchmarking range the tests may use.
        assert_eq!(
            u32::from(BOARD_IP) >> 17,
            u32::from(Ipv4Addr::new(198, 18, 0, 0)) >> 17
        );
    }
}
