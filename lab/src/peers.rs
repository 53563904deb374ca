//! Independent peers (the Python and Node.js programs in `host-tests/peers/`) and where
//! their interpreters and packages are installed (`cargo xtask setup` puts them there), and
//! running them inside a namespace: each reads a JSON request from stdin and prints one JSON
//! document that the caller checks.

use std::io;
use std::path::PathBuf;
use std::time::Duration;

use serde_json::Value;

use crate::netns::Namespace;
use crate::paths;
use crate::process::run_bounded;

/// The Python virtual environment holding the Python peers.
pub fn venv_dir() -> PathBuf {
    paths::target_dir().join("peers-venv")
}

/// Its interpreter.
pub fn venv_python() -> PathBuf {
    venv_dir().join("bin/python")
}

/// The npm prefix holding the npm peers: `ENIP_PEER_NPM_DIR`, else `peers-npm` in the
/// target directory.
pub fn npm_dir() -> PathBuf {
    std::env::var_os("ENIP_PEER_NPM_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| paths::target_dir().join("peers-npm"))
}

/// The Python interpreter with the peers installed: `ENIP_PEER_PYTHON`, else `python3`.
pub fn python() -> String {
    std::env::var("ENIP_PEER_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// The path of the peer script `name` (in `host-tests/peers/`).
pub fn script(name: &str) -> PathBuf {
    paths::root().join("host-tests/peers").join(name)
}

/// Runs the peer script `name` inside `ns` with `input` on stdin, for at most `timeout`, and
/// returns the JSON it printed last.
pub fn run(ns: &Namespace, name: &str, input: &Value, timeout: Duration) -> io::Result<Value> {
    let mut cmd = ns.command(python());
    cmd.arg(script(name));
    run_json(cmd, name, Some(input), timeout)
}

/// Runs the peer script `name` inside `ns` with the command-line arguments `args` (and
/// nothing on stdin), for at most `timeout`, and returns the JSON it printed last.
pub fn run_with_args(
    ns: &Namespace,
    name: &str,
    args: &[&str],
    timeout: Duration,
) -> io::Result<Value> {
    let mut cmd = ns.command(python());
    cmd.arg(script(name)).args(args);
    run_json(cmd, name, None, timeout)
}

/// Runs the Node.js peer script `name` like [`run`], with the npm peers of [`npm_dir`] on
/// its module path.
pub fn run_node(ns: &Namespace, name: &str, input: &Value, timeout: Duration) -> io::Result<Value> {
    let mut cmd = ns.command("node");
    cmd.env("NODE_PATH", npm_dir().join("node_modules"))
        .arg(script(name));
    run_json(cmd, name, Some(input), timeout)
}

fn run_json(
    cmd: std::process::Command,
    name: &str,
    input: Option<&Value>,
    timeout: Duration,
) -> io::Result<Value> {
    let input = input.map(Value::to_string);
    let out = run_bounded(cmd, input.as_ref().map(String::as_bytes), timeout)?;
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

/// One line of the project scanner's single-connection figures from its `--json` report:
/// packets sent and received (of those expected), lost, and the interval percentiles (of
/// its first connection).
pub fn scanner_figures(report: &Value) -> String {
    let n = |k: &str| {
        report
            .get(k)
            .or_else(|| report["connections"].get(0)?.get(k))
            .and_then(Value::as_u64)
            .unwrap_or(0)
    };
    format!(
        "sent {:5} O->T, received {:5} T->O of {} expected, lost {}, \
         interval p50 {:5} us, p99 {:5} us, max {:5} us",
        n("sent"),
        n("received"),
        n("expected_per_connection"),
        n("lost"),
        n("p50_us"),
        n("p99_us"),
        n("max_us")
    )
}
