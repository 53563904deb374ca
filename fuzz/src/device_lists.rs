//! Seeds of the `device_list` target: device lists of the fleet runtime that it accepts, from
//! the README's plant, the fleet test's five runs of profiles and the parser's own test.

use std::path::Path;

/// The README's plant: a press and a run of 40 drives, every key used.
const PLANT: &str = r#"[[device]]
name = "press-1"               # log prefix (default: the address)
address = "192.168.10.11"      # one of the host's own addresses (required)
profile = "position-servo"     # generic, position-servo, parker-ipa, ametek-pls, kollmorgen-akd
serial_number = 0x00A10001     # Identity attribute 6 (default: the profile's)
product_name = "Press 1 servo" # Identity attribute 7, at most 32 characters
nv_file = "nv/press-1.nv"      # its non-volatile store, relative to this file (default: RAM)

[[device]]                     # 40 drives at .20 to .59, serial numbers 0x00A20001 onwards
name = "drive-{n}"             # {n} is 1 to count, in name, product_name and nv_file
address = "192.168.10.20"
count = 40
profile = "kollmorgen-akd"
serial_number = 0x00A20001
product_name = "Line drive {n}"
nv_file = "nv/drive-{n}.nv"
"#;

/// The fleet test's list (`host-tests/tests/tap_interop/fleet.rs`): 16 devices, one run per
/// profile, the generic ones with stores.
const FLEET: &str = r#"
[[device]]
name = "generic-{n}"
address = "198.18.0.10"
profile = "generic"
count = 4
serial_number = 0xf10001
product_name = "plant generic {n}"
nv_file = "/tmp/fleet/nv-{n}"

[[device]]
name = "position-servo-{n}"
address = "198.18.0.14"
profile = "position-servo"
count = 3
serial_number = 0xf20001
product_name = "plant position-servo {n}"

[[device]]
name = "parker-ipa-{n}"
address = "198.18.0.17"
profile = "parker-ipa"
count = 3
serial_number = 0xf30001
product_name = "plant parker-ipa {n}"

[[device]]
name = "ametek-pls-{n}"
address = "198.18.0.20"
profile = "ametek-pls"
count = 3
serial_number = 0xf40001
product_name = "plant ametek-pls {n}"

[[device]]
name = "kollmorgen-akd-{n}"
address = "198.18.0.23"
profile = "kollmorgen-akd"
count = 3
serial_number = 0xf50001
product_name = "plant kollmorgen-akd {n}"
"#;

/// The parser's test: comments, escapes, `_` in a number, a run across a byte of the address.
const ESCAPES: &str = r#"
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

/// One device, everything else its defaults.
const LONE: &str = "[[device]]\naddress = \"198.18.0.2\"\n";

/// The seeds, each a name and the list; each must parse (with its number of devices).
pub fn seeds() -> Vec<(&'static str, Vec<u8>)> {
    let lists = [
        ("plant", PLANT, 41),
        ("fleet", FLEET, 16),
        ("escapes", ESCAPES, 4),
        ("lone", LONE, 1),
    ];
    lists
        .into_iter()
        .map(|(name, text, devices)| {
            let parsed = enip_host::parse_device_list(text, Path::new("/plant"));
            assert_eq!(parsed.map(|d| d.len()), Ok(devices), "seed {name}");
            (name, text.as_bytes().to_vec())
        })
        .collect()
}
