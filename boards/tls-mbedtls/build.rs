//! Compiles mbedTLS (its C library, from the `mbedtls-sys-auto` package's copy of the
//! upstream source) with this crate's configuration (`c/enip_mbedtls_config.h`) and the shim
//! (`c/shim.c`) for the target, into one static library with a section per function so that
//! the linker keeps only what the TLS server path calls.
//!
//! The source directory is `ENIP_MBEDTLS_SRC` if set (an mbedTLS 2.28 tree), otherwise the
//! `vendor/` of the `mbedtls-sys-auto` package in cargo's registry cache, or where `cargo
//! metadata` fetches it (this crate declares it for a target that never matches, so it is
//! resolved and fetched, never built).

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The package whose `vendor/` directory is mbedTLS's source.
const SOURCE_PACKAGE: &str = "mbedtls-sys-auto-2.28.15";

fn main() {
    println!("cargo:rerun-if-env-changed=ENIP_MBEDTLS_SRC");
    println!("cargo:rerun-if-changed=c");
    let src = match env::var_os("ENIP_MBEDTLS_SRC") {
        Some(dir) => PathBuf::from(dir),
        None => registry()
            .or_else(vendored)
            .unwrap_or_else(|e| panic!("mbedTLS source not found: {e}")),
    };
    let library = src.join("library");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&library)
        .unwrap_or_else(|e| panic!("{}: {e}", library.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "c"))
        .collect();
    files.sort();
    let here = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let config = here.join("c").join("enip_mbedtls_config.h");
    cc::Build::new()
        .files(&files)
        .file(here.join("c").join("shim.c"))
        .include(src.join("include"))
        .include(&library)
        .include(here.join("c"))
        .define("MBEDTLS_CONFIG_FILE", Some("\"enip_mbedtls_config.h\""))
        .flag("-ffunction-sections")
        .flag("-fdata-sections")
        .flag("-fno-common")
        .opt_level_str("s")
        .warnings(false)
        .compile("enip_mbedtls");
    println!("cargo:rerun-if-changed={}", config.display());
}

/// `vendor/` of [`SOURCE_PACKAGE`] if cargo's registry cache already has it unpacked.
fn registry() -> Result<PathBuf, String> {
    let home = env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| env::var_os("HOME").map(|h| Path::new(&h).join(".cargo")))
        .ok_or("no CARGO_HOME")?;
    let src = home.join("registry").join("src");
    std::fs::read_dir(&src)
        .map_err(|e| format!("{}: {e}", src.display()))?
        .filter_map(|entry| entry.ok())
        .map(|index| index.path().join(SOURCE_PACKAGE).join("vendor"))
        .find(|vendor| vendor.join("library").join("ssl_tls.c").is_file())
        .ok_or_else(|| format!("{SOURCE_PACKAGE} not unpacked in {}", src.display()))
}

/// `vendor/` of [`SOURCE_PACKAGE`] as `cargo metadata` locates it (fetching it if needed).
fn vendored(_: String) -> Result<PathBuf, String> {
    let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let manifest = Path::new(&env::var_os("CARGO_MANIFEST_DIR").ok_or("no CARGO_MANIFEST_DIR")?)
        .join("Cargo.toml");
    let out = Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--manifest-path"])
        .arg(&manifest)
        .output()
        .map_err(|e| format!("cargo metadata: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    let json = String::from_utf8_lossy(&out.stdout);
    let needle = format!("{SOURCE_PACKAGE}/Cargo.toml");
    let end = json
        .find(&needle)
        .ok_or(format!("{SOURCE_PACKAGE} not in cargo metadata"))?;
    let start = json[..end].rfind('"').ok_or("malformed cargo metadata")? + 1;
    Ok(PathBuf::from(&json[start..end])
        .join(SOURCE_PACKAGE)
        .join("vendor"))
}
