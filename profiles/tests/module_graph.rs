//! The files of each profile import each other one way: no cycle in the graph of the paths
//! (`use` trees and paths in code: `super::`, `self::`, `crate::`, a child module's name)
//! from one file of a profile directory to another. Test code is left out: nothing imports
//! it. A file that names an item of another file depends on it; a module's declaration of
//! its children (`mod x;`) does not count, so a profile's `mod.rs` may declare every file
//! while a helper file must not reach back into it.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

/// A module path inside the crate (`["kollmorgen_akd", "device"]`).
type ModPath = Vec<String>;

/// Every `.rs` file below `dir`.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module a file (relative to `src`) is.
fn module_of(rel: &Path) -> ModPath {
    let mut parts: ModPath = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// Test code: a `tests` module or a `*_tests` file.
fn is_test(module: &ModPath) -> bool {
    module.iter().any(|p| p == "tests" || p.ends_with("_tests"))
}

/// The code of a file: comments and string literals blanked, an inline `#[cfg(test)] mod`
/// and everything after it cut.
fn code(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '/' if chars.peek() == Some(&'/') => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            '"' => {
                let mut escaped = false;
                for c in chars.by_ref() {
                    if !escaped && c == '"' {
                        break;
                    }
                    escaped = !escaped && c == '\\';
                }
                out.push_str("\"\"");
            }
            '\'' => {
                // A char literal ('x', '\n') is blanked; a lifetime ('a) is kept as is.
                let rest: String = chars.clone().take(3).collect();
                let literal = rest.starts_with('\\')
                    || rest.chars().nth(1) == Some('\'')
                    || rest.starts_with('"');
                if literal {
                    for c in chars.by_ref() {
                        if c == '\'' {
                            break;
                        }
                    }
                    out.push_str("' '");
                } else {
                    out.push(c);
                }
            }
            _ => out.push(c),
        }
    }
    let mut cut = out.len();
    let mut at = 0;
    while let Some(i) = out[at..].find("#[cfg(test)]") {
        let after = out[at + i + "#[cfg(test)]".len()..].trim_start();
        let after = after.strip_prefix("pub(crate) ").unwrap_or(after);
        if let Some(rest) = after.strip_prefix("mod ") {
            let head: String = rest
                .chars()
                .take_while(|c| *c != ';' && *c != '{')
                .collect();
            if rest[head.len()..].starts_with('{') {
                cut = at + i;
                break;
            }
        }
        at += i + 1;
    }
    out.truncate(cut);
    out
}

/// The paths of a `use` tree (`a::{b, c::{d as e}}` -> `a::b`, `a::c::d`).
fn expand(tree: &str) -> Vec<String> {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        let path = tree.split(" as ").next().unwrap_or("").trim();
        return vec![path.to_string()];
    };
    let prefix = tree[..open].trim().trim_end_matches("::");
    let body = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
    let (mut items, mut current, mut depth) = (Vec::new(), String::new(), 0);
    for c in body.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(std::mem::take(&mut current));
                continue;
            }
            _ => {}
        }
        current.push(c);
    }
    items.push(current);
    let mut out = Vec::new();
    for item in items.iter().map(|i| i.trim()).filter(|i| !i.is_empty()) {
        for path in expand(item) {
            out.push(match path.as_str() {
                "self" => prefix.to_string(),
                _ => format!("{prefix}::{path}"),
            });
        }
    }
    out
}

/// Every path a file's code names: its `use` trees expanded, and `a::b` paths elsewhere.
fn paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = String::new();
    let mut at = 0;
    while let Some(i) = code[at..].find("use ") {
        let start = at + i;
        let word_start = start == 0
            || !code[..start]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_');
        let end = code[start..].find(';').map(|e| start + e);
        match end {
            Some(end) if word_start => {
                rest.push_str(&code[at..start]);
                out.extend(expand(&code[start + 4..end]));
                at = end + 1;
            }
            _ => {
                rest.push_str(&code[at..start + 4]);
                at = start + 4;
            }
        }
    }
    rest.push_str(&code[at..]);
    let mut path = String::new();
    let mut chars = rest.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            path.push(c);
        } else if c == ':' && chars.peek() == Some(&':') && !path.is_empty() {
            chars.next();
            path.push_str("::");
        } else {
            if path.contains("::") {
                out.push(path.trim_end_matches("::").to_string());
            }
            path.clear();
        }
    }
    out
}

/// The file module `path` (named in module `from`) lands in: the longest prefix of the
/// resolved path that is a file's module. `None` outside the crate's own modules.
fn resolve(from: &ModPath, path: &str, modules: &BTreeMap<ModPath, String>) -> Option<ModPath> {
    let segments: Vec<&str> = path.split("::").map(str::trim).collect();
    let mut full: ModPath = match segments.first()? {
        &"crate" => Vec::new(),
        &"super" | &"self" => from.clone(),
        first => {
            let mut child = from.clone();
            child.push(first.to_string());
            if !modules.contains_key(&child) {
                return None;
            }
            from.clone()
        }
    };
    let mut rest = segments.as_slice();
    if rest.first() == Some(&"crate") {
        rest = &rest[1..];
    }
    while let Some(&s) = rest.first() {
        match s {
            "super" => {
                full.pop();
            }
            "self" => {}
            _ => break,
        }
        rest = &rest[1..];
    }
    full.extend(rest.iter().map(|s| s.to_string()));
    (0..=full.len())
        .rev()
        .map(|n| full[..n].to_vec())
        .find(|m| modules.contains_key(m))
}

#[test]
fn no_import_cycle_inside_a_profile() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let modules: BTreeMap<ModPath, String> = files
        .iter()
        .map(|f| {
            let rel = f.strip_prefix(&src).unwrap();
            (module_of(rel), rel.display().to_string())
        })
        .collect();
    let mut edges: BTreeMap<ModPath, Vec<ModPath>> = BTreeMap::new();
    for (module, file) in &modules {
        if is_test(module) {
            continue;
        }
        let text = fs::read_to_string(src.join(file)).unwrap();
        let mut to: Vec<ModPath> = paths(&code(&text))
            .iter()
            .filter_map(|p| resolve(module, p, &modules))
            .filter(|m| m != module && !is_test(m))
            .collect();
        to.sort();
        to.dedup();
        edges.insert(module.clone(), to);
    }
    let profiles: Vec<&ModPath> = modules
        .keys()
        .filter(|m| m.len() == 1 && modules[*m].ends_with("mod.rs"))
        .collect();
    assert!(profiles.len() >= 5, "profiles found: {profiles:?}");
    // Depth-first search for a back edge within each profile's files.
    let mut cycles = Vec::new();
    for profile in profiles {
        let inside = |m: &ModPath| m.first() == profile.first();
        let mut state: BTreeMap<&ModPath, u8> = BTreeMap::new();
        fn visit<'a>(
            m: &'a ModPath,
            edges: &'a BTreeMap<ModPath, Vec<ModPath>>,
            inside: &dyn Fn(&ModPath) -> bool,
            state: &mut BTreeMap<&'a ModPath, u8>,
            stack: &mut Vec<&'a ModPath>,
            cycles: &mut Vec<String>,
        ) {
            state.insert(m, 1);
            stack.push(m);
            for next in edges.get(m).into_iter().flatten().filter(|n| inside(n)) {
                match state.get(next) {
                    Some(1) => {
                        let from = stack.iter().position(|s| *s == next).unwrap_or(0);
                        let names: Vec<String> =
                            stack[from..].iter().map(|s| s.join("/")).collect();
                        cycles.push(format!("{} -> {}", names.join(" -> "), next.join("/")));
                    }
                    Some(_) => {}
                    None => visit(next, edges, inside, state, stack, cycles),
                }
            }
            stack.pop();
            state.insert(m, 2);
        }
        for m in edges.keys().filter(|m| inside(m)) {
            if !state.contains_key(m) {
                visit(m, &edges, &inside, &mut state, &mut Vec::new(), &mut cycles);
            }
        }
    }
    assert!(cycles.is_empty(), "import cycles:\n{}", cycles.join("\n"));
}

/// The paths of a file as the check reads them (comments, strings and inline test modules
/// left out), and where they resolve.
#[test]
fn finds_the_paths_of_a_file() {
    let text = "use super::a::{b, c::{D as E}};\n\
                use crate::x::Y; // use super::commented;\n\
                fn f() { let s = \"super::quoted::X\"; super::d::g(); h::i(); }\n\
                #[cfg(test)]\nmod tests { use super::super::z; }";
    let found = paths(&code(text));
    for p in [
        "super::a::b",
        "super::a::c::D",
        "crate::x::Y",
        "super::d::g",
        "h::i",
    ] {
        assert!(found.iter().any(|f| f == p), "{p} not in {found:?}");
    }
    assert!(!found
        .iter()
        .any(|f| f.contains("commented") || f.contains("quoted")));
    assert!(!found.iter().any(|f| f.contains("super::super::z")));
    let modules: BTreeMap<ModPath, String> = [
        (vec!["p".to_string()], "p/mod.rs".to_string()),
        (vec!["p".to_string(), "a".to_string()], "p/a.rs".to_string()),
    ]
    .into_iter()
    .collect();
    let from = vec!["p".to_string(), "b".to_string()];
    assert_eq!(
        resolve(&from, "super::a::X", &modules),
        Some(vec!["p".into(), "a".into()])
    );
    assert_eq!(resolve(&from, "super::X", &modules), Some(vec!["p".into()]));
    let top = vec!["p".to_string()];
    assert_eq!(
        resolve(&top, "a::X", &modules),
        Some(vec!["p".into(), "a".into()])
    );
    assert_eq!(resolve(&top, "core::mem::take", &modules), None);
}
