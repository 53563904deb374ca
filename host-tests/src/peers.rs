//! Independent peers (Python programs in `host-tests/peers/`) run inside the test namespace:
//! each reads a JSON request from stdin and prints one JSON document that the test asserts on.

use std::io;
use std::path::PathBuf;
use std::time::Duration;

use serde_json::Value;

use crate::netns::Namespace;
use crate::process::run_bounded;

/// The Python interpreter with the peers installed: `ENIP_PEER_PYTHON`, else `python3`.
pub fn python() -> String {
    std::env::var("ENIP_PEER_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// The path of the peer script `name`.
pub fn script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("peers")
        .join(name)
}

/// Runs the peer script `name` inside `ns` with `input` on stdin, for at most `timeout`, and
/// returns the JSON it printed last.
pub fn run(ns: &Namespace, name: &str, input: &Value, timeout: Duration) -> io::Result<Value> {
    let mut cmd = ns.command(python());
    cmd.arg(script(name));
    run_json(cmd, name, input, timeout)
}

/// Runs the Node.js peer script `name` like [`run`], with the npm peers of
/// `ENIP_PEER_NPM_DIR` (default `target/peers-npm`) on its module path.
pub fn run_node(ns: &Namespace, name: &str, input: &Value, timeout: Duration) -> io::Result<Value> {
    let npm = std::env::var_os("ENIP_PEER_NPM_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/peers-npm"));
    let mut cmd = ns.command("node");
    cmd.env("NODE_PATH", npm.join("node_modules"))
        .arg(script(name));
    run_json(cmd, name, input, timeout)
}

fn run_json(
    cmd: std::process::Command,
    name: &str,
    input: &Value,
    timeout: Duration,
) -> io::Result<Value> {
    let out = run_bounded(cmd, Some(input.to_string().as_bytes()), timeout)?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        return Err(io::Error::other(format!(
            "peer {name} failed ({}):\n{stdout}\n{stderr}",
            out.status
        )));
    }
    let last = stdout.lines().rev().find(|l| !l.trim().is_empty());
    last.and_then(|l| serde_json::from_str(l).ok())
        .ok_or_else(|| {
            io::Error::other(format!("peer {name} printed no JSON:\n{stdout}\n{stderr}"))
        })
}
