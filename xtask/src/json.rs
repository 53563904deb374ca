//! Just enough JSON reading for the one-line reports of peers and the scanner: the raw value
//! of the first `"key":` (the reports are flat, or have unique keys).

/// The value of the first `"key":` in `json`: a number, `true`/`false`/`null`, or a string
/// (without its quotes; escapes are not undone).
pub fn value<'a>(json: &'a str, key: &str) -> Option<&'a str> {
    let pattern = format!("\"{key}\"");
    let at = json.find(&pattern)? + pattern.len();
    let rest = json[at..].trim_start().strip_prefix(':')?.trim_start();
    if let Some(s) = rest.strip_prefix('"') {
        return s.find('"').map(|end| &s[..end]);
    }
    let end = rest.find([',', '}', ']']).unwrap_or(rest.len());
    Some(rest[..end].trim())
}

/// The value of `key` as an unsigned number.
pub fn number(json: &str, key: &str) -> Option<u64> {
    value(json, key)?.parse().ok()
}

/// One line of the scanner's single-connection figures from its `--json` report: packets
/// sent and received (of those expected), lost, and the interval percentiles.
pub fn scanner_figures(report: &str) -> String {
    let n = |k| number(report, k).unwrap_or(0);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_numbers_booleans_and_strings() {
        let j = r#"{"connections":[{"lost":0,"p50_us":1000}],"sent": 10000, "ok": true, "name": "enip-rs generic"}"#;
        assert_eq!(number(j, "p50_us"), Some(1000));
        assert_eq!(number(j, "sent"), Some(10000));
        assert_eq!(value(j, "ok"), Some("true"));
        assert_eq!(value(j, "name"), Some("enip-rs generic"));
        assert_eq!(value(j, "missing"), None);
    }
}
