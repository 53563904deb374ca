//! The fleet runtime's device list (`enip-host --devices FILE`): the input, if it is UTF-8 (the
//! file is read as a `String`), parsed by `enip_host::parse_device_list`. A list it accepts
//! names 1 to `MAX_DEVICES` devices at distinct addresses with every `{n}` filled in, each
//! `nv_file` taken from the list's (absolute) directory; and written back one `[[device]]`
//! table per device, every key given, it reads back as the same devices.
#![no_main]

use std::collections::HashSet;
use std::fmt::Write;
use std::path::Path;

use enip_host::{parse_device_list, DeviceEntry, MAX_DEVICES};
use libfuzzer_sys::fuzz_target;

/// The directory the list is read from.
const DIR: &str = "/plant";

/// `s` as a basic string of the list: quoted, with `"` and `\` escaped.
fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        if matches!(c, '"' | '\\') {
            out.push('\\');
        }
        out.push(c);
    }
    out.push('"');
    out
}

/// The devices as a list of one table each, every key written out.
fn written(devices: &[DeviceEntry]) -> String {
    let mut list = String::new();
    for d in devices {
        let _ = write!(
            list,
            "[[device]]\nname = {}\naddress = \"{}\"\nprofile = {}\n",
            quoted(&d.name),
            d.address,
            quoted(&d.profile)
        );
        if let Some(serial) = d.serial_number {
            let _ = writeln!(list, "serial_number = {serial}");
        }
        if let Some(name) = &d.product_name {
            let _ = writeln!(list, "product_name = {}", quoted(name));
        }
        if let Some(nv) = &d.nv_file {
            let nv = nv.to_str().expect("a path made of UTF-8 text");
            let _ = writeln!(list, "nv_file = {}", quoted(nv));
        }
    }
    list
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(devices) = parse_device_list(text, Path::new(DIR)) else {
        return;
    };
    assert!(
        (1..=MAX_DEVICES).contains(&devices.len()),
        "{} devices",
        devices.len()
    );
    let mut addresses = HashSet::new();
    for d in &devices {
        assert!(addresses.insert(d.address), "{} twice", d.address);
        let texts = [Some(d.name.as_str()), d.product_name.as_deref()];
        for s in texts.into_iter().flatten() {
            assert!(!s.contains("{n}"), "{{n}} left in {s:?}");
        }
        if let Some(nv) = &d.nv_file {
            assert!(nv.is_absolute(), "{nv:?} not from {DIR}");
            let nv = nv.to_str().expect("a path made of UTF-8 text");
            assert!(!nv.contains("{n}"), "{{n}} left in {nv:?}");
        }
    }
    let again = parse_device_list(&written(&devices), Path::new(DIR));
    assert_eq!(again.as_ref(), Ok(&devices), "the list written back");
});
