//! The workspace as cargo describes it (`cargo metadata`, read with serde_json): which crates
//! build only for the embedded target, the published crates' `rust-version`, and a package's
//! features (the device profiles are features of the profiles crate).

use serde_json::Value;

use crate::util::{self, Error, Result};

/// The workspace's own packages, from `cargo metadata --no-deps`.
#[derive(Debug)]
pub struct Metadata(Value);

impl Metadata {
    /// Asks cargo about the workspace.
    pub fn read() -> Result<Metadata> {
        Self::read_manifest(None)
    }

    /// Asks cargo about the package or workspace of `manifest` (a `Cargo.toml` relative to
    /// the root; `None` for the workspace).
    pub fn read_manifest(manifest: Option<&str>) -> Result<Metadata> {
        let mut cargo = util::cargo();
        cargo.args(["metadata", "--format-version", "1", "--no-deps"]);
        if let Some(m) = manifest {
            cargo.args(["--manifest-path", m]);
        }
        let out = util::output(&mut cargo).ok_or_else(|| Error("cargo metadata failed".into()))?;
        serde_json::from_str(&out)
            .map(Metadata)
            .map_err(|e| Error(format!("cargo metadata: {e}")))
    }

    fn packages(&self) -> impl Iterator<Item = &Value> {
        self.0["packages"].as_array().into_iter().flatten()
    }

    fn package(&self, name: &str) -> Result<&Value> {
        self.packages()
            .find(|p| p["name"] == name)
            .ok_or_else(|| Error(format!("no package {name} in the workspace")))
    }

    /// Package names of the workspace members that are not default members: the crates that
    /// build only for the embedded target (the boards).
    pub fn cross_only_packages(&self) -> Vec<String> {
        let ids =
            |key: &str| -> Vec<&Value> { self.0[key].as_array().into_iter().flatten().collect() };
        let defaults = ids("workspace_default_members");
        let members = ids("workspace_members");
        self.packages()
            .filter(|p| members.contains(&&p["id"]) && !defaults.contains(&&p["id"]))
            .filter_map(|p| p["name"].as_str().map(str::to_string))
            .collect()
    }

    /// The `rust-version` of `package`, as a toolchain name (`1.95` -> `1.95.0`).
    pub fn rust_version_toolchain(&self, package: &str) -> Result<String> {
        let version = self.package(package)?["rust_version"]
            .as_str()
            .ok_or_else(|| Error(format!("{package} has no rust-version")))?;
        Ok(match version.split('.').count() {
            2 => format!("{version}.0"),
            _ => version.to_string(),
        })
    }

    /// The features `package` declares, sorted.
    pub fn features(&self, package: &str) -> Result<Vec<String>> {
        let features = self.package(package)?["features"].as_object();
        Ok(features
            .into_iter()
            .flatten()
            .map(|(k, _)| k.clone())
            .collect())
    }

    /// The names of the binaries of every package read.
    #[cfg(test)]
    pub fn bins(&self) -> Vec<(String, String)> {
        self.packages()
            .flat_map(|p| p["targets"].as_array().into_iter().flatten())
            .filter(|t| {
                t["kind"]
                    .as_array()
                    .is_some_and(|k| k.contains(&"bin".into()))
            })
            .filter_map(|t| Some((t["name"].as_str()?.into(), t["src_path"].as_str()?.into())))
            .collect()
    }

    /// What the feature `feature` of `package` enables (`None` if it has no such feature).
    pub fn feature(&self, package: &str, feature: &str) -> Result<Option<Vec<String>>> {
        let enables = self.package(package)?["features"][feature].as_array();
        Ok(enables.map(|list| {
            list.iter()
                .filter_map(|f| f.as_str().map(str::to_string))
                .collect()
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_this_workspace() {
        let m = Metadata::read().unwrap();
        let cross = m.cross_only_packages();
        assert!(cross.contains(&"enip-qemu-mps2".to_string()), "{cross:?}");
        assert!(!cross.contains(&"enip-stack".to_string()), "{cross:?}");
        let toolchain = m.rust_version_toolchain("enip-stack").unwrap();
        assert_eq!(toolchain.split('.').count(), 3, "{toolchain}");
        assert!(m
            .features("enip-profiles")
            .unwrap()
            .contains(&"generic".to_string()));
        assert_eq!(
            m.feature("enip-stack", "log").unwrap(),
            Some(vec!["dep:log".to_string()])
        );
        assert_eq!(m.feature("enip-stack", "nothing").unwrap(), None);
        assert!(m.package("no-such-crate").is_err());
    }
}
