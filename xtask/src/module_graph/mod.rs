//! The module check of `cargo xtask test`: inside the stack crate the top-level modules form
//! a one-way graph (wire -> cip -> device -> io -> objects -> encap -> adapter, read
//! bottom-up), and inside the profiles crate so do the profiles and, within each profile,
//! its files. A module depends on another when its code names it (`use crate::...`,
//! `super::...`, or a path in an expression); comments, doc links and strings do not count.
//! The module that declares a scope's children (its `lib.rs` or `mod.rs`) is left out of
//! that scope's graph: it declares and re-exports them. Test code (`#[cfg(test)]` modules,
//! inline or in files of their own) is left out too: nothing depends on it.

mod source;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use crate::util::{self, Result};

/// The crates and scopes checked: (crate source directory, check each top-level directory
/// module as a scope of its own too).
const CHECKED: [(&str, bool); 2] = [("stack/src", false), ("profiles/src", true)];

/// Checks every crate in [`CHECKED`]; an error lists each cycle found.
pub fn check() -> Result {
    let mut cycles = Vec::new();
    for (dir, per_child) in CHECKED {
        let root = util::root().join(dir);
        let graph = CrateGraph::read(&root)?;
        let mut scopes = vec![Vec::new()];
        if per_child {
            scopes.extend(graph.directory_modules());
        }
        for scope in &scopes {
            let edges = graph.edges_in(scope);
            let found = cycles_of(&edges);
            let nodes: BTreeSet<&String> = edges
                .keys()
                .chain(edges.values().flatten().map(|(n, _)| n))
                .collect();
            println!(
                "{dir}{}: {} modules, {} dependencies, {} cycles",
                scope.iter().map(|s| format!("::{s}")).collect::<String>(),
                nodes.len(),
                edges.values().map(BTreeMap::len).sum::<usize>(),
                found.len()
            );
            for cycle in found {
                cycles.push(describe(dir, scope, &cycle, &edges));
            }
        }
    }
    if cycles.is_empty() {
        Ok(())
    } else {
        util::err(format!("module cycles:\n{}", cycles.join("\n")))
    }
}

/// One crate's modules (by path from the crate root) and what each file names.
struct CrateGraph {
    /// Module path -> the file that defines it.
    files: BTreeMap<Vec<String>, PathBuf>,
    /// The modules declared `#[cfg(test)]` in files of their own.
    tests: BTreeSet<Vec<String>>,
}

/// Dependencies inside one scope: child -> (child it depends on -> a file that says so).
type Edges = BTreeMap<String, BTreeMap<String, String>>;

impl CrateGraph {
    fn read(root: &Path) -> Result<Self> {
        let mut files = BTreeMap::new();
        let mut stack = vec![root.to_path_buf()];
        while let Some(dir) = stack.pop() {
            let entries =
                fs::read_dir(&dir).map_err(|e| util::Error(format!("{}: {e}", dir.display())))?;
            for entry in entries.flatten() {
                let path = entry.path();
                if path.is_dir() {
                    stack.push(path);
                } else if path.extension().is_some_and(|e| e == "rs") {
                    files.insert(module_path(root, &path), path);
                }
            }
        }
        let mut tests = BTreeSet::new();
        for (module, file) in &files {
            let text = fs::read_to_string(file)
                .map_err(|e| util::Error(format!("{}: {e}", file.display())))?;
            for child in source::test_children(&source::code_only(&text)) {
                let mut path = module.clone();
                path.push(child);
                tests.insert(path);
            }
        }
        Ok(CrateGraph { files, tests })
    }

    /// The modules that are directories (`a/mod.rs`) directly under the crate root.
    fn directory_modules(&self) -> Vec<Vec<String>> {
        self.files
            .iter()
            .filter(|(m, f)| m.len() == 1 && f.ends_with("mod.rs"))
            .map(|(m, _)| m.clone())
            .collect()
    }

    /// The dependencies between the children of `scope`, each file counted under the child
    /// it belongs to; the scope's own module is left out.
    fn edges_in(&self, scope: &[String]) -> Edges {
        let child = |m: &[String]| -> Option<String> {
            m.strip_prefix(scope).and_then(|rest| rest.first().cloned())
        };
        let mut edges = Edges::new();
        for (module, file) in &self.files {
            let Some(from) = child(module) else { continue };
            if self.tests.iter().any(|t| module.starts_with(t)) {
                continue;
            }
            let Ok(text) = fs::read_to_string(file) else {
                continue;
            };
            let mentions = source::mentions(&source::code_only(&text));
            for mention in mentions.into_iter().filter(|m| !m.in_test) {
                let Some(target) = self.resolve(module, &mention) else {
                    continue;
                };
                let Some(to) = child(&target) else { continue };
                if to != from {
                    let shown = file.file_name().map(|n| n.to_string_lossy().into_owned());
                    let shown = format!(
                        "{} ({})",
                        shown.unwrap_or_default(),
                        mention.segments.join("::")
                    );
                    edges
                        .entry(from.clone())
                        .or_default()
                        .entry(to)
                        .or_insert(shown);
                }
            }
        }
        edges
    }

    /// The longest known module `mention` (written in `module`) names.
    fn resolve(&self, module: &[String], mention: &source::Mention) -> Option<Vec<String>> {
        let mut base: Vec<String> = module.to_vec();
        base.extend(mention.inline.iter().cloned());
        let mut segments = mention.segments.iter();
        let mut path = match segments.next()?.as_str() {
            "crate" => Vec::new(),
            "self" => base,
            _ => {
                base.pop()?;
                base
            }
        };
        for s in segments {
            if s == "super" {
                path.pop()?;
            } else {
                path.push(s.clone());
            }
        }
        while !path.is_empty() && !self.files.contains_key(&path) {
            path.pop();
        }
        Some(path)
    }
}

/// The module path of `file` under the crate root `root`.
fn module_path(root: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(root).unwrap_or(file).with_extension("");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The strongly connected components of more than one node (Tarjan), each sorted.
fn cycles_of(edges: &Edges) -> Vec<Vec<String>> {
    struct Walk<'a> {
        edges: &'a Edges,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, v: &'a str) {
            let n = self.index.len();
            self.index.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            for w in self.edges.get(v).into_iter().flat_map(BTreeMap::keys) {
                let w = w.as_str();
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    self.low.entry(v).and_modify(|l| *l = (*l).min(lw));
                } else if self.stack.contains(&w) {
                    let iw = self.index[w];
                    self.low.entry(v).and_modify(|l| *l = (*l).min(iw));
                }
            }
            if self.low[v] == self.index[v] {
                let at = self.stack.iter().rposition(|x| *x == v).unwrap_or(0);
                let mut component: Vec<String> =
                    self.stack.drain(at..).map(str::to_string).collect();
                if component.len() > 1 {
                    component.sort();
                    self.found.push(component);
                }
            }
        }
    }
    let mut walk = Walk {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in edges.keys() {
        if !walk.index.contains_key(v.as_str()) {
            walk.visit(v);
        }
    }
    walk.found
}

/// A cycle and the dependencies that make it, one line each.
fn describe(dir: &str, scope: &[String], cycle: &[String], edges: &Edges) -> String {
    let mut lines = vec![format!(
        "  in {dir} {}: {}",
        scope.join("::"),
        cycle.join(", ")
    )];
    for from in cycle {
        for (to, why) in edges.get(from).into_iter().flatten() {
            if cycle.contains(to) {
                lines.push(format!("    {from} -> {to}: {why}"));
            }
        }
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edges(pairs: &[(&str, &str)]) -> Edges {
        let mut e = Edges::new();
        for (a, b) in pairs {
            e.entry(a.to_string())
                .or_default()
                .insert(b.to_string(), String::new());
        }
        e
    }

    #[test]
    fn a_one_way_graph_has_no_cycle_and_a_loop_is_found() {
        assert!(cycles_of(&edges(&[
            ("io", "device"),
            ("device", "wire"),
            ("io", "wire")
        ]))
        .is_empty());
        let found = cycles_of(&edges(&[("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]));
        assert_eq!(found, [vec!["a".to_string(), "b".into(), "c".into()]]);
    }

    #[test]
    fn the_real_tree_is_read() {
        // A file of this crate written as a crate of its own: module paths and resolution.
        let root = util::root().join("xtask/src");
        let graph = CrateGraph::read(&root).unwrap();
        let this = vec!["module_graph".to_string()];
        assert!(graph.files.contains_key(&this));
        let mention = source::Mention {
            inline: vec![],
            segments: vec!["super".into(), "source".into(), "mentions".into()],
            in_test: false,
        };
        let child = vec!["module_graph".to_string(), "source".to_string()];
        assert_eq!(
            graph.resolve(&child, &mention),
            Some(vec!["module_graph".to_string(), "source".to_string()])
        );
        let inline = source::Mention {
            inline: vec!["tests".into()],
            segments: vec!["super".into(), "cycles_of".into()],
            in_test: true,
        };
        assert_eq!(graph.resolve(&this, &inline), Some(this.clone()));
    }
}
