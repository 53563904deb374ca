//! Opening the TAP interface, with start-up errors that say what to do.
//!
//! Opening `/dev/net/tun` with `TUNSETIFF` creates the interface when none has the name, so
//! a misspelled `--tap` would silently give a new interface that nothing is connected to.
//! The interface is therefore looked up first (by `if_nametoindex`, which, unlike
//! `/sys/class/net`, answers for the process's own network namespace even when `sysfs` was
//! mounted in another one) and created only when `--create-tap` asks for it.

use std::ffi::CString;
use std::io;

use crate::tap_device::TapDevice;

/// Opens the TAP interface `name`; creates it only if it does not exist and `create` is set.
pub fn open(name: &str, create: bool) -> Result<TapDevice, String> {
    if !create && !exists(name)? {
        return Err(format!(
            "there is no network interface {name:?}; create the TAP first, typically inside \
             a network namespace:\n  ip tuntap add dev {name} mode tap\n  ip link set {name} \
             up\n(or pass --create-tap to have enip-host create it)"
        ));
    }
    TapDevice::open(name).map_err(|e| open_error(name, &e))
}

/// Whether the process's network namespace has an interface called `name`.
fn exists(name: &str) -> Result<bool, String> {
    let c_name = CString::new(name).map_err(|_| format!("bad interface name {name:?}"))?;
    // SAFETY: `c_name` is a valid NUL-terminated string that outlives the call, which only
    // reads it.
    if unsafe { libc::if_nametoindex(c_name.as_ptr()) } != 0 {
        return Ok(true);
    }
    let e = io::Error::last_os_error();
    match e.raw_os_error() {
        Some(libc::ENODEV | libc::ENXIO) => Ok(false),
        _ => Err(format!("cannot look up interface {name:?}: {e}")),
    }
}

/// The message for a failed open of an existing (or, with `--create-tap`, new) interface.
fn open_error(name: &str, e: &io::Error) -> String {
    let hint = match e.raw_os_error() {
        Some(libc::EINVAL) => format!(
            "{name:?} exists but is not a TAP interface (create one with `ip tuntap add dev \
             NAME mode tap`)"
        ),
        Some(libc::EBUSY) => "another process is attached to it".into(),
        Some(libc::EACCES) => format!(
            "/dev/net/tun must be readable and writable by this user; run as root or with \
             CAP_NET_ADMIN, or give the user access to /dev/net/tun and a TAP created for \
             them: `ip tuntap add dev {name} mode tap user $USER`"
        ),
        Some(libc::EPERM) => format!(
            "run as root or with CAP_NET_ADMIN, or use a TAP created for this user: \
             `ip tuntap add dev {name} mode tap user $USER`"
        ),
        Some(libc::ENOENT) => "/dev/net/tun is missing (is the tun module loaded?)".into(),
        _ => return format!("cannot open TAP {name:?}: {e}"),
    };
    format!("cannot open TAP {name:?}: {e}: {hint}")
}
