//! Reading one Rust source file for the module check: its code without comments, string
//! and character literals, and the module paths it names (`use` trees and paths written in
//! expressions), each relative to the module it was written in.

/// One path the source names: where it was written (inline modules of the file, outermost
/// first) and its segments as written (`crate`, `super`, `self` or a name first).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mention {
    /// The inline modules (`mod tests { ... }`) around the mention, outermost first.
    pub inline: Vec<String>,
    /// The path's segments, e.g. `["super", "state", "Machine"]`.
    pub segments: Vec<String>,
    /// True inside a `#[cfg(test)]` inline module.
    pub in_test: bool,
}

/// `text` with comments removed and every string or character literal emptied, so that
/// neither a doc link nor a string that looks like a path counts as a dependency.
pub fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == b'/' && next == Some(b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && next == Some(b'*') {
            let mut depth = 0usize;
            while i < b.len() {
                if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if c == b'r' && (next == Some(b'"') || next == Some(b'#')) && raw_start(b, i) {
            let hashes = b[i + 1..].iter().take_while(|&&h| h == b'#').count();
            let mut close = String::from("\"");
            close.push_str(&"#".repeat(hashes));
            let body = i + 2 + hashes;
            i = text[body..]
                .find(&close)
                .map_or(b.len(), |at| body + at + close.len());
            out.push_str("\"\"");
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == b'\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime ('a): only the former
            // is skipped.
            if next == Some(b'\\') {
                i += 2;
                while i < b.len() && b[i] != b'\'' {
                    i += 1;
                }
                i += 1;
                out.push_str("' '");
            } else if b.get(i + 2) == Some(&b'\'') {
                i += 3;
                out.push_str("' '");
            } else {
                out.push('\'');
                i += 1;
            }
        } else {
            let len = text[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&text[i..i + len]);
            i += len;
        }
    }
    out
}

/// True if the `r` at `at` starts a raw string rather than ending an identifier.
fn raw_start(b: &[u8], at: usize) -> bool {
    let after = b[at + 1..].iter().find(|&&h| h != b'#');
    let before = at.checked_sub(1).map(|p| b[p]);
    after == Some(&b'"') && !before.is_some_and(|p| p.is_ascii_alphanumeric() || p == b'_')
}

/// Every path in `code` (from [`code_only`]) that starts with `crate`, `super` or `self`,
/// with `use` groups expanded, and the inline modules it sits in.
pub fn mentions(code: &str) -> Vec<Mention> {
    let tokens = tokenize(code);
    let mut found = Vec::new();
    // Inline modules: (name, brace depth inside it, test only).
    let mut inline: Vec<(String, usize, bool)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < tokens.len() {
        match tokens[i].as_str() {
            "{" => depth += 1,
            "}" => {
                if inline.last().is_some_and(|(_, d, _)| *d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            "mod" if tokens.get(i + 2).is_some_and(|t| t == "{") => {
                inline.push((tokens[i + 1].clone(), depth + 1, after_cfg_test(&tokens, i)));
            }
            "crate" | "super" | "self" if tokens.get(i + 1).is_some_and(|t| t == "::") => {
                // Not the tail of a longer path (`a::self`).
                if i > 0 && tokens[i - 1] == "::" {
                    i += 1;
                    continue;
                }
                let mut paths = Vec::new();
                i = use_tree(&tokens, i, Vec::new(), &mut paths);
                let names: Vec<String> = inline.iter().map(|(n, _, _)| n.clone()).collect();
                let in_test = inline.iter().any(|(_, _, test)| *test);
                found.extend(paths.into_iter().map(|segments| Mention {
                    inline: names.clone(),
                    segments,
                    in_test,
                }));
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    found
}

/// The child modules declared test-only in a file of their own (`#[cfg(test)] mod x;`).
pub fn test_children(code: &str) -> Vec<String> {
    let tokens = tokenize(code);
    (0..tokens.len())
        .filter(|&i| tokens[i] == "mod" && tokens.get(i + 2).is_some_and(|t| t == ";"))
        .filter(|&i| after_cfg_test(&tokens, i))
        .map(|i| tokens[i + 1].clone())
        .collect()
}

/// True if the item whose keyword is at `tokens[at]` carries `#[cfg(test)]` (possibly
/// behind `pub` or `pub(crate)`).
fn after_cfg_test(tokens: &[String], at: usize) -> bool {
    const CFG_TEST: [&str; 7] = ["#", "[", "cfg", "(", "test", ")", "]"];
    (at.saturating_sub(12)..at).any(|start| {
        tokens
            .get(start..start + CFG_TEST.len())
            .is_some_and(|w| w.iter().zip(CFG_TEST).all(|(a, b)| a == b))
            && tokens[start + CFG_TEST.len()..at]
                .iter()
                .all(|t| matches!(t.as_str(), "pub" | "(" | ")" | "crate" | "super"))
    })
}

/// Reads the path (or `use` tree) starting at `tokens[i]`, appending every full path to
/// `out` with `prefix` before it; returns the index after it.
fn use_tree(
    tokens: &[String],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Vec<String>>,
) -> usize {
    loop {
        match tokens.get(i).map(String::as_str) {
            Some("{") => {
                i += 1;
                loop {
                    match tokens.get(i).map(String::as_str) {
                        Some("}") => return i + 1,
                        Some(",") => i += 1,
                        Some(_) => i = use_tree(tokens, i, prefix.clone(), out),
                        None => return i,
                    }
                }
            }
            Some(t) if is_ident(t) => {
                prefix.push(t.to_string());
                i += 1;
                if tokens.get(i).is_some_and(|t| t == "::") {
                    i += 1;
                    continue;
                }
                out.push(prefix);
                return i;
            }
            Some("*") => {
                out.push(prefix);
                return i + 1;
            }
            _ => {
                if !prefix.is_empty() {
                    out.push(prefix);
                }
                return i;
            }
        }
    }
}

fn is_ident(t: &str) -> bool {
    t.chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_')
}

/// Identifiers, `::`, and single punctuation characters.
fn tokenize(code: &str) -> Vec<String> {
    let mut tokens = Vec::new();
    let mut chars = code.char_indices().peekable();
    while let Some((at, c)) = chars.next() {
        if c.is_alphanumeric() || c == '_' {
            let mut end = at + c.len_utf8();
            while let Some(&(p, n)) = chars.peek() {
                if !(n.is_alphanumeric() || n == '_') {
                    break;
                }
                end = p + n.len_utf8();
                chars.next();
            }
            tokens.push(code[at..end].to_string());
        } else if c == ':' && chars.peek().is_some_and(|&(_, n)| n == ':') {
            chars.next();
            tokens.push("::".to_string());
        } else if !c.is_whitespace() {
            tokens.push(c.to_string());
        }
    }
    tokens
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(src: &str) -> Vec<(Vec<String>, String)> {
        mentions(&code_only(src))
            .into_iter()
            .map(|m| (m.inline, m.segments.join("::")))
            .collect()
    }

    #[test]
    fn test_modules_are_told_apart() {
        let src = "#[cfg(test)]\nmod tests { use super::a; }\nmod b { use super::c; }\n\
                   #[cfg(test)]\nmod file_tests;\npub mod d;\n#[cfg(test)] pub(crate) mod e;";
        let code = code_only(src);
        let tested: Vec<bool> = mentions(&code).iter().map(|m| m.in_test).collect();
        assert_eq!(tested, [true, false]);
        assert_eq!(test_children(&code), ["file_tests", "e"]);
    }

    #[test]
    fn comments_and_strings_name_nothing() {
        let src = "//! see [`crate::a::B`]\n/* crate::b */ let s = \"crate::c\"; let c = '\"'; \
                   fn f<'a>(x: &'a u8) { crate::d::e(x) } // crate::f\nlet r = r#\"crate::g\"#;";
        let found: Vec<String> = paths(src).into_iter().map(|(_, p)| p).collect();
        assert_eq!(found, ["crate::d::e"]);
    }

    #[test]
    fn use_groups_expand_and_inline_modules_are_kept() {
        let src = "use crate::{a::{b, c::D}, e};\nuse super::*;\n\
                   mod tests { use super::f::G; fn t() { self::h(); } }\nuse self::i::J;";
        let found = paths(src);
        let none: Vec<String> = Vec::new();
        let tests = vec!["tests".to_string()];
        assert_eq!(
            found,
            [
                (none.clone(), "crate::a::b".to_string()),
                (none.clone(), "crate::a::c::D".to_string()),
                (none.clone(), "crate::e".to_string()),
                (none.clone(), "super".to_string()),
                (tests.clone(), "super::f::G".to_string()),
                (tests, "self::h".to_string()),
                (none, "self::i::J".to_string()),
            ]
        );
    }
}
