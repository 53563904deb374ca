//! Reading the one-line JSON reports of peers and the scanner (with serde_json): the first
//! value of a key, depth first (the reports are flat, or have unique keys).

use serde_json::Value;

/// The first value of `key` in the JSON document `json` (or, for a program's output, its
/// last line that is one), depth first.
pub fn find(json: &str, key: &str) -> Option<Value> {
    let doc: Value = serde_json::from_str(json.trim()).ok().or_else(|| {
        json.lines()
            .rev()
            .find_map(|l| serde_json::from_str(l.trim()).ok())
    })?;
    first(&doc, key).cloned()
}

fn first<'a>(v: &'a Value, key: &str) -> Option<&'a Value> {
    match v {
        Value::Object(map) => map
            .get(key)
            .or_else(|| map.values().find_map(|child| first(child, key))),
        Value::Array(items) => items.iter().find_map(|child| first(child, key)),
        _ => None,
    }
}

/// The value of `key` as an unsigned number.
pub fn number(json: &str, key: &str) -> Option<u64> {
    find(json, key)?.as_u64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_and_booleans() {
        let j = r#"{"connections":[{"lost":0,"p50_us":1000}],"sent": 10000, "ok": true}"#;
        assert_eq!(number(j, "p50_us"), Some(1000));
        assert_eq!(number(j, "sent"), Some(10000));
        assert_eq!(find(j, "ok"), Some(Value::Bool(true)));
        assert_eq!(find(j, "missing"), None);
        assert_eq!(number(&format!("a warning\n{j}\n"), "sent"), Some(10000));
    }
}
