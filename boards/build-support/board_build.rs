// Build-script helpers shared by the embedded boards, `include!`d by their `build.rs`:
// the linker memory map, the build-time network settings and the chosen device profile.
// Everything is checked here, so a bad setting fails the build rather than the board.

use std::env;
use std::fs;
use std::net::Ipv4Addr;
use std::path::PathBuf;

/// Environment variable with the board's static address, `A.B.C.D/LEN`.
const IP_VAR: &str = "ENIP_IP";
/// Environment variable with the board's default gateway, `A.B.C.D` (optional).
const GATEWAY_VAR: &str = "ENIP_GATEWAY";
/// Environment variable turning Address Conflict Detection off at build time (`off`; default
/// `on`): test images that are not about it start without its seconds of probing.
const ACD_VAR: &str = "ENIP_ACD";
/// Environment variable building a test image (`on`; default `off`) whose diagnostics object
/// answers the service that faults on purpose (hang, stack overflow, panic).
const TEST_FAULTS_VAR: &str = "ENIP_TEST_FAULTS";
/// Cargo features that choose the device profile start with this.
const PROFILE_FEATURE: &str = "CARGO_FEATURE_PROFILE_";
/// The profile used when no other `profile-*` feature is enabled.
const DEFAULT_PROFILE: &str = "generic";

fn out_dir() -> PathBuf {
    PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"))
}

/// Links with cortex-m-rt's `link.x` and the workspace's top-level `memory.x`.
///
/// The linker runs in the workspace root, where `INCLUDE memory.x` finds that file first.
#[allow(dead_code)] // each board uses one of the two link set-ups
fn link_with_top_level_memory_map() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let memory_x = manifest.join("../../memory.x");
    assert!(memory_x.exists(), "{} is missing", memory_x.display());
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}

/// Links with the board's own memory map `memory_x` (relative to the crate) instead of the
/// top-level one.
///
/// cortex-m-rt's `link.x` says `INCLUDE memory.x`, which the linker resolves in its working
/// directory (the workspace root, holding the STM32 map) before any search path. So this
/// writes `OUT_DIR/board-link.x`: the board's map followed by cortex-m-rt's `link.x` without
/// that line. cortex-m-rt's build script has run before this one (it declares `links`).
#[allow(dead_code)] // each board uses one of the two link set-ups
fn link_with_own_memory_map(memory_x: &str) {
    link_with_map(memory_x, false);
}

/// [`link_with_own_memory_map`] for a board whose peripheral access crate gives cortex-m-rt
/// its `device.x` (the interrupt vectors): cortex-m-rt's `link.x` built with that feature.
/// `board-link.x` is in this crate's `OUT_DIR`, on the link search path of every firmware
/// built on the board, which links with `-Tboard-link.x` too.
#[allow(dead_code)] // each board uses one of the link set-ups
fn link_with_own_device_memory_map(memory_x: &str) {
    link_with_map(memory_x, true);
}

/// Writes and links `board-link.x`: `memory_x` then cortex-m-rt's `link.x`, the one built
/// with the `device` feature if `device`.
fn link_with_map(memory_x: &str, device: bool) {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let source = manifest.join(memory_x);
    let map = fs::read_to_string(&source).unwrap_or_else(|e| panic!("{}: {e}", source.display()));
    let rt_link = cortex_m_rt_link_x(device);
    let rt = fs::read_to_string(&rt_link).unwrap_or_else(|e| panic!("{}: {e}", rt_link.display()));
    let body: Vec<&str> = rt.lines().filter(|l| l.trim() != "INCLUDE memory.x").collect();
    assert!(body.len() < rt.lines().count(), "{}: no INCLUDE memory.x", rt_link.display());
    let script = format!("{map}\n/* {} */\n{}\n", rt_link.display(), body.join("\n"));
    fs::write(out_dir().join("board-link.x"), script).expect("OUT_DIR is writable");
    println!("cargo:rerun-if-changed={}", source.display());
    println!("cargo:rerun-if-changed={}", rt_link.display());
    println!("cargo:rustc-link-search={}", out_dir().display());
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tboard-link.x");
}

/// The newest `link.x` written by a cortex-m-rt build script next to this one, among those
/// built with the `device` feature if `device`, else without it (the STM32 boards' builds
/// have it, the emulated board's does not).
fn cortex_m_rt_link_x(device: bool) -> PathBuf {
    let out = out_dir();
    let build = out
        .parent()
        .and_then(|p| p.parent())
        .expect("OUT_DIR is build/<crate>-<hash>/out");
    let entries = fs::read_dir(build).unwrap_or_else(|e| panic!("{}: {e}", build.display()));
    entries
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().starts_with("cortex-m-rt-"))
        .map(|e| e.path().join("out/link.x"))
        .filter(|p| fs::read_to_string(p).is_ok_and(|s| s.contains("INCLUDE device.x") == device))
        .filter_map(|p| Some((fs::metadata(&p).ok()?.modified().ok()?, p)))
        .max()
        .map(|(_, p)| p)
        .expect("cortex-m-rt's build script wrote no link.x")
}

/// Writes `OUT_DIR/network.rs` with the static address from `ENIP_IP` (default
/// `default_cidr`) and the gateway from `ENIP_GATEWAY` (default none), as constants
/// `ADDRESS: [u8; 4]`, `PREFIX_LEN: u8` and `GATEWAY: Option<[u8; 4]>`.
fn network_settings(default_cidr: &str) {
    println!("cargo:rerun-if-env-changed={IP_VAR}");
    println!("cargo:rerun-if-env-changed={GATEWAY_VAR}");
    let cidr = env::var(IP_VAR).unwrap_or_else(|_| default_cidr.to_string());
    let (ip, len) = cidr
        .split_once('/')
        .unwrap_or_else(|| panic!("{IP_VAR}={cidr:?}: expected A.B.C.D/LEN"));
    let ip: Ipv4Addr = ip
        .parse()
        .unwrap_or_else(|_| panic!("{IP_VAR}={cidr:?}: bad address"));
    let len: u8 = len
        .parse()
        .ok()
        .filter(|l| (1..=32).contains(l))
        .unwrap_or_else(|| panic!("{IP_VAR}={cidr:?}: prefix length must be 1..=32"));
    let gateway = match env::var(GATEWAY_VAR) {
        Ok(g) if !g.is_empty() => {
            let g: Ipv4Addr = g
                .parse()
                .unwrap_or_else(|_| panic!("{GATEWAY_VAR}={g:?}: bad address"));
            format!("Some({:?})", g.octets())
        }
        _ => "None".to_string(),
    };
    let code = format!(
        "/// The static address (`{IP_VAR}` at build time).\n\
         pub const ADDRESS: [u8; 4] = {:?};\n\
         /// Its prefix length.\n\
         pub const PREFIX_LEN: u8 = {len};\n\
         /// The default gateway (`{GATEWAY_VAR}` at build time).\n\
         pub const GATEWAY: Option<[u8; 4]> = {gateway};\n",
        ip.octets()
    );
    fs::write(out_dir().join("network.rs"), code).expect("OUT_DIR is writable");
}

/// Writes `OUT_DIR/acd.rs` with `ACD: bool` from `ENIP_ACD` (`on`, the default, or `off`):
/// whether the board detects address conflicts at start whatever TCP/IP attribute 10 says.
#[allow(dead_code)] // the emulated board's only
fn acd_setting() {
    let doc = "Address Conflict Detection at start (attribute 10 still turns it off)";
    switch_setting(ACD_VAR, true, "acd.rs", "ACD", doc);
}

/// Writes `OUT_DIR/test_faults.rs` with `TEST_FAULTS: bool` from `ENIP_TEST_FAULTS` (`off`,
/// the default, or `on`): whether the image can be made to fault on purpose over CIP.
#[allow(dead_code)] // the emulated board's only
fn test_faults_setting() {
    let doc = "A test image, which faults on purpose when asked";
    switch_setting(TEST_FAULTS_VAR, false, "test_faults.rs", "TEST_FAULTS", doc);
}

/// Writes `OUT_DIR/<file>` with `pub const <name>: bool` from the variable `var` (`on` or
/// `off`; `default` when unset), documented as `doc`.
#[allow(dead_code)] // the emulated board's only
fn switch_setting(var: &str, default: bool, file: &str, name: &str, doc: &str) {
    println!("cargo:rerun-if-env-changed={var}");
    let on = match env::var(var).as_deref() {
        Err(_) => default,
        Ok("on") => true,
        Ok("off") => false,
        Ok(v) => panic!("{var}={v:?}: expected on or off"),
    };
    let code = format!("/// {doc} (`{var}` at build time).\npub const {name}: bool = {on};\n");
    fs::write(out_dir().join(file), code).expect("OUT_DIR is writable");
}

/// Writes `OUT_DIR/profile.rs` for the profile chosen by a `profile-NAME` feature
/// (`profile-generic` when no other is enabled; two others are an error): the constant
/// `NAME` and the type alias `Chosen` for `enip_profiles::<Name in CamelCase>`, which
/// has a `new()` power-up constructor. The board links that one profile only (the run-time
/// `enip_profiles::Profile` would link them all).
fn profile_from_features() {
    let mut chosen: Vec<String> = env::vars()
        .filter_map(|(k, _)| k.strip_prefix(PROFILE_FEATURE).map(str::to_string))
        .map(|f| f.to_lowercase().replace('_', "-"))
        .filter(|p| p != DEFAULT_PROFILE)
        .collect();
    let name = match chosen.len() {
        0 => DEFAULT_PROFILE.to_string(),
        1 => chosen.remove(0),
        _ => panic!("enable one profile-* feature, not {chosen:?}"),
    };
    let camel: String = name
        .split('-')
        .map(|w| {
            let mut c = w.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect();
    let code = format!(
        "/// The device profile's name (feature `profile-{name}`).\n\
         pub const NAME: &str = \"{name}\";\n\
         /// The device profile.\n\
         pub type Chosen = enip_profiles::{camel};\n"
    );
    fs::write(out_dir().join("profile.rs"), code).expect("OUT_DIR is writable");
}
