//! Just enough of the root `Cargo.toml` to tell host crates from cross-only crates.

use std::fs;
use std::path::Path;

use crate::util::{self, Result};

/// The strings of the array `key = [ ... ]` in `toml` (single- or multi-line), in order.
pub fn string_array(toml: &str, key: &str) -> Vec<String> {
    let Some(start) = toml
        .lines()
        .scan(0usize, |at, line| {
            let here = *at;
            *at += line.len() + 1;
            Some((here, line))
        })
        .find(|(_, l)| {
            l.trim_start()
                .strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .map(|(at, _)| at)
    else {
        return Vec::new();
    };
    let rest = &toml[start..];
    let (Some(open), Some(close)) = (rest.find('['), rest.find(']')) else {
        return Vec::new();
    };
    if close < open {
        return Vec::new();
    }
    rest[open + 1..close]
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(|l| l.split(','))
        .map(|s| s.trim().trim_matches('"').to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

/// The `name` of the `[package]` in `dir/Cargo.toml`.
pub fn package_name(dir: &Path) -> Option<String> {
    let text = fs::read_to_string(dir.join("Cargo.toml")).ok()?;
    let mut in_package = false;
    for line in text.lines() {
        let l = line.trim();
        if l.starts_with('[') {
            in_package = l == "[package]";
        } else if in_package {
            if let Some(v) = l.strip_prefix("name") {
                let v = v.trim_start().strip_prefix('=')?;
                return Some(v.trim().trim_matches('"').to_string());
            }
        }
    }
    None
}

/// Package names of the workspace members that are not default members: the crates that
/// build only for the embedded target (the boards).
pub fn cross_only_packages() -> Result<Vec<String>> {
    let root = util::root();
    let toml = fs::read_to_string(root.join("Cargo.toml"))?;
    let members = string_array(&toml, "members");
    let defaults = string_array(&toml, "default-members");
    if defaults.is_empty() {
        return Ok(Vec::new());
    }
    Ok(members
        .iter()
        .filter(|m| !defaults.contains(m))
        .filter_map(|m| package_name(&root.join(m)))
        .collect())
}

/// The workspace's `rust-version` (`[workspace.package]`), as a toolchain name
/// (`1.95` -> `1.95.0`).
pub fn rust_version_toolchain() -> Result<String> {
    let toml = fs::read_to_string(util::root().join("Cargo.toml"))?;
    let version = toml
        .lines()
        .find_map(|l| l.trim().strip_prefix("rust-version = "))
        .map(|v| v.trim_matches('"').to_string())
        .ok_or_else(|| util::Error("no rust-version in Cargo.toml".into()))?;
    Ok(match version.split('.').count() {
        2 => format!("{version}.0"),
        _ => version,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_arrays() {
        let toml = "[workspace]\nmembers = [\n    \"stack\",\n    \"boards/a\", # x\n]\n\
                    default-members = [\"stack\"]\nexclude = [\"fuzz\"]\n";
        assert_eq!(string_array(toml, "members"), ["stack", "boards/a"]);
        assert_eq!(string_array(toml, "default-members"), ["stack"]);
        assert_eq!(string_array(toml, "exclude"), ["fuzz"]);
        assert!(string_array(toml, "nothing").is_empty());
    }

    #[test]
    fn reads_this_workspace() {
        assert_eq!(
            package_name(&util::root().join("stack")).as_deref(),
            Some("enip-stack")
        );
        assert!(cross_only_packages().is_ok());
    }
}
