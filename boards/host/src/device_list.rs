//! The device list of a fleet (`enip-host --devices FILE`): a small TOML file a test engineer
//! writes by hand, one `[[device]]` table per device (or per run of alike devices, with
//! `count`). This reads the subset of TOML it needs (tables `[[device]]`, `key = value` with
//! strings and integers, `#` comments) and refuses anything else with the line.
//!
//! ```toml
//! [[device]]
//! name = "press-1"               # log prefix (default: the address)
//! address = "198.18.0.10"        # one of the host's own addresses (required)
//! profile = "position-servo"     # a shipped profile (default: generic)
//! serial_number = 0x1001         # Identity attribute 6 (default: the profile's)
//! product_name = "Press 1 servo" # Identity attribute 7, at most 32 characters
//! nv_file = "nv/press-1.nv"      # non-volatile store, relative to this file (default: RAM)
//!
//! [[device]]                     # 8 drives at .20 to .27, serials 0x2001 to 0x2008
//! name = "drive-{n}"             # {n}: 1 to count, in name, product_name and nv_file
//! address = "198.18.0.20"
//! count = 8
//! profile = "kollmorgen-akd"
//! serial_number = 0x2001
//! ```

use std::net::Ipv4Addr;
use std::path::{Path, PathBuf};

/// Most devices one list may name (a bound on `count`).
pub const MAX_DEVICES: usize = 4096;

/// One device of a list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceEntry {
    /// Its name in the log.
    pub name: String,
    /// The local address it serves at.
    pub address: Ipv4Addr,
    /// Its profile's name.
    pub profile: String,
    /// Identity serial number, replacing the profile's.
    pub serial_number: Option<u32>,
    /// Identity product name, replacing the profile's.
    pub product_name: Option<String>,
    /// Its non-volatile store.
    pub nv_file: Option<PathBuf>,
}

/// One `[[device]]` table as written.
#[derive(Debug, Default)]
struct Table {
    line: usize,
    name: Option<String>,
    address: Option<Ipv4Addr>,
    profile: Option<String>,
    serial_number: Option<u32>,
    product_name: Option<String>,
    nv_file: Option<String>,
    count: Option<u32>,
}

/// Reads the device list at `path`.
pub fn read(path: &Path) -> Result<Vec<DeviceEntry>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse(&text, dir).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses a device list; relative `nv_file` paths are taken from `dir`. A list it accepts
/// names 1 to [`MAX_DEVICES`] devices at distinct addresses, a run of `count` at consecutive
/// ones, with every `{n}` filled in.
pub fn parse(text: &str, dir: &Path) -> Result<Vec<DeviceEntry>, String> {
    let mut tables: Vec<Table> = Vec::new();
    for (number, raw) in (1..).zip(text.lines()) {
        let at = |e: String| format!("line {number}: {e}");
        let line = strip_comment(raw).trim();
        if line.is_empty() {
            continue;
        }
        if line == "[[device]]" {
            tables.push(Table {
                line: number,
                ..Table::default()
            });
            continue;
        }
        let table = tables
            .last_mut()
            .ok_or_else(|| at("expected [[device]] before any key".into()))?;
        let (key, value) = line.split_once('=').ok_or_else(|| {
            at(format!(
                "expected `key = value` or [[device]], not {line:?}"
            ))
        })?;
        table.set(key.trim(), value.trim()).map_err(at)?;
    }
    let mut devices = Vec::new();
    for table in tables {
        table
            .expand(dir, &mut devices)
            .map_err(|e| format!("device at line {}: {e}", table.line))?;
    }
    if devices.is_empty() {
        return Err("no [[device]] in the list".into());
    }
    for (i, d) in devices.iter().enumerate() {
        if let Some(twin) = devices.iter().skip(i + 1).find(|o| o.address == d.address) {
            return Err(format!(
                "devices {:?} and {:?} share the address {}",
                d.name, twin.name, d.address
            ));
        }
    }
    Ok(devices)
}

impl Table {
    /// Takes `key = value`.
    fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        let field = match key {
            "name" => string(value).map(|v| self.name = Some(v)),
            "address" => string(value).and_then(|v| {
                let ip = v.parse().map_err(|_| format!("bad IPv4 address {v:?}"))?;
                self.address = Some(ip);
                Ok(())
            }),
            "profile" => string(value).map(|v| self.profile = Some(v)),
            "serial_number" => integer(value).map(|v| self.serial_number = Some(v)),
            "product_name" => string(value).map(|v| self.product_name = Some(v)),
            "nv_file" => string(value).map(|v| self.nv_file = Some(v)),
            "count" => integer(value).map(|v| self.count = Some(v)),
            _ => {
                return Err(format!(
                    "unknown key {key:?} (known: name, address, profile, serial_number, \
                     product_name, nv_file, count)"
                ))
            }
        };
        field.map_err(|e| format!("{key}: {e}"))
    }

    /// The devices this table names, appended to `out`.
    fn expand(&self, dir: &Path, out: &mut Vec<DeviceEntry>) -> Result<(), String> {
        let first = self.address.ok_or("no address")?;
        let count = self.count.unwrap_or(1);
        if count == 0 || out.len() + count as usize > MAX_DEVICES {
            return Err(format!("count {count}: 1 to {MAX_DEVICES} devices in all"));
        }
        let numbered = |s: &Option<String>| s.as_ref().is_some_and(|s| s.contains("{n}"));
        if count > 1 && self.nv_file.is_some() && !numbered(&self.nv_file) {
            return Err("devices of a count need their own nv_file: put {n} in it".into());
        }
        for n in 0..count {
            let address = u32::from(first)
                .checked_add(n)
                .map(Ipv4Addr::from)
                .ok_or("the addresses of count run past 255.255.255.255")?;
            let fill = |s: &str| s.replace("{n}", &(n + 1).to_string());
            out.push(DeviceEntry {
                name: self
                    .name
                    .as_deref()
                    .map_or_else(|| address.to_string(), fill),
                address,
                profile: self.profile.clone().unwrap_or_else(|| "generic".into()),
                serial_number: self.serial_number.map(|s| s.wrapping_add(n)),
                product_name: self.product_name.as_deref().map(fill),
                nv_file: self.nv_file.as_deref().map(|p| dir.join(fill(p))),
            });
        }
        Ok(())
    }
}

/// `line` without its comment (a `#` outside a string).
fn strip_comment(line: &str) -> &str {
    let mut quoted = false;
    let mut escaped = false;
    for (i, c) in line.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if quoted => escaped = true,
            '"' => quoted = !quoted,
            '#' if !quoted => return line.get(..i).unwrap_or(line),
            _ => {}
        }
    }
    line
}

/// A basic string: `"..."` with the escapes `\"` and `\\`.
fn string(value: &str) -> Result<String, String> {
    let inner = value
        .strip_prefix('"')
        .and_then(|v| v.strip_suffix('"'))
        .ok_or_else(|| format!("expected a \"string\", not {value:?}"))?;
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        match c {
            '\\' => match chars.next() {
                Some(e @ ('"' | '\\')) => out.push(e),
                _ => return Err(format!("unsupported escape in {value:?}")),
            },
            '"' => return Err(format!("unescaped quote in {value:?}")),
            _ => out.push(c),
        }
    }
    Ok(out)
}

/// A non-negative integer: decimal or `0x` hexadecimal, `_` between digits allowed.
fn integer(value: &str) -> Result<u32, String> {
    let digits = value.replace('_', "");
    let parsed = match digits.strip_prefix("0x") {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => digits.parse(),
    };
    parsed.map_err(|_| format!("expected an integer (0 to 4294967295), not {value:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_devices_and_runs_of_devices() {
        let list = r#"
            # a plant
            [[device]]
            name = "press-1"   # the press
            address = "198.18.0.10"
            profile = "position-servo"
            serial_number = 0x1001
            product_name = "Press \"1\" # servo"
            nv_file = "nv/press.nv"

            [[device]]
            name = "drive-{n}"
            address = "198.18.0.254"
            count = 3
            serial_number = 1_000
            nv_file = "/var/nv-{n}"
        "#;
        let d = parse(list, Path::new("/plant")).unwrap();
        assert_eq!(d.len(), 4);
        assert_eq!(d[0].name, "press-1");
        assert_eq!(d[0].address, Ipv4Addr::new(198, 18, 0, 10));
        assert_eq!(d[0].profile, "position-servo");
        assert_eq!(d[0].serial_number, Some(0x1001));
        assert_eq!(d[0].product_name.as_deref(), Some("Press \"1\" # servo"));
        assert_eq!(d[0].nv_file, Some(PathBuf::from("/plant/nv/press.nv")));
        let names: Vec<_> = d[1..].iter().map(|d| d.name.as_str()).collect();
        assert_eq!(names, ["drive-1", "drive-2", "drive-3"]);
        assert_eq!(d[3].address, Ipv4Addr::new(198, 18, 1, 0));
        assert_eq!(d[3].serial_number, Some(1002));
        assert_eq!(d[3].profile, "generic");
        assert_eq!(d[3].nv_file, Some(PathBuf::from("/var/nv-3")));
    }

    #[test]
    fn refuses_what_it_does_not_know_with_the_line() {
        let bad = |text: &str| parse(text, Path::new(".")).unwrap_err();
        assert!(bad("address = \"198.18.0.1\"").starts_with("line 1:"));
        assert!(bad("[[device]]\nadress = \"198.18.0.1\"").contains("unknown key"));
        assert!(bad("[[device]]\naddress = 198.18.0.1").contains("string"));
        assert!(bad("[[device]]\naddress = \"198.18.0.300\"").contains("bad IPv4"));
        assert!(bad("[[device]]\nname = \"x\"").contains("no address"));
        assert!(bad("[device]\naddress = \"198.18.0.1\"").starts_with("line 1:"));
        assert!(bad("").contains("no [[device]]"));
        let twice = "[[device]]\naddress = \"198.18.0.1\"\ncount = 2\n[[device]]\n\
                     address = \"198.18.0.2\"";
        assert!(bad(twice).contains("share the address 198.18.0.2"));
        let shared_nv = "[[device]]\naddress = \"198.18.0.1\"\ncount = 2\nnv_file = \"nv\"";
        assert!(bad(shared_nv).contains("{n}"));
        assert!(bad("[[device]]\naddress = \"198.18.0.1\"\ncount = 0").contains("count 0"));
        let past = "[[device]]\naddress = \"255.255.255.255\"\ncount = 2";
        assert!(bad(past).contains("past"));
        assert!(
            bad("[[device]]\naddress = \"198.18.0.1\"\nserial_number = -1").contains("integer")
        );
    }
}
