//! Command-line parsing for `enip-host`.

use core::net::Ipv4Addr;
use std::path::PathBuf;

use firmware::Profile;

/// How to invoke the program.
pub const USAGE: &str = "\
usage: enip-host --tap IFNAME --ip A.B.C.D/LEN [--gateway A.B.C.D] [--profile NAME] [--mac xx:xx:xx:xx:xx:xx] [--create-tap]
                 [--nvram FILE] [--pls-rpm RPM]

  --tap IFNAME       an existing TAP interface to attach to; create it first, typically
                     inside a network namespace: `ip tuntap add dev IFNAME mode tap` and
                     `ip link set IFNAME up` (add `user $USER` to run enip-host unprivileged)
  --ip A.B.C.D/LEN   the adapter's static address and prefix length
  --gateway A.B.C.D  default gateway (none by default)
  --profile NAME     device profile (default: generic)
  --mac MAC          the adapter's MAC address (default: 02:45:4e:49:50:01)
  --create-tap       create IFNAME if there is none (needs root or CAP_NET_ADMIN); it is
                     down, has no host address and disappears when enip-host exits
  --nvram FILE       the profile's non-volatile memory (ametek-pls: the program saved by
                     program control), read at start and rewritten at every save
  --pls-rpm RPM      ametek-pls: speed of the simulated resolver (default 0, stationary)

Logs go to stderr; set RUST_LOG to change the level (default: info).";

/// Size of a Linux interface name buffer, the terminating NUL included.
const IFNAMSIZ: usize = 16;

/// The MAC address used when `--mac` is not given (locally administered, unicast).
const DEFAULT_MAC: [u8; 6] = [0x02, 0x45, 0x4E, 0x49, 0x50, 0x01];

/// What the command line asks for.
pub enum Command {
    /// Run the adapter (boxed: a profile holds its whole device state).
    Run(Box<Args>),
    /// Print the usage and exit.
    Help,
}

/// The adapter's settings.
pub struct Args {
    /// TAP interface name.
    pub tap: String,
    /// Static address.
    pub ip: Ipv4Addr,
    /// Prefix length of the address.
    pub prefix_len: u8,
    /// Default gateway.
    pub gateway: Option<Ipv4Addr>,
    /// Device profile.
    pub profile: Profile,
    /// MAC address.
    pub mac: [u8; 6],
    /// Create the TAP interface if there is none.
    pub create_tap: bool,
    /// The profile's non-volatile memory file.
    pub nvram: Option<PathBuf>,
    /// Speed of the ametek-pls profile's simulated resolver, RPM.
    pub pls_rpm: u16,
}

/// Parses the arguments after the program name.
pub fn parse(mut args: impl Iterator<Item = String>) -> Result<Command, String> {
    let mut tap = None;
    let mut ip = None;
    let mut gateway = None;
    let mut profile = Profile::default();
    let mut mac = DEFAULT_MAC;
    let mut create_tap = false;
    let mut nvram = None;
    let mut pls_rpm = 0;
    while let Some(flag) = args.next() {
        match flag.as_str() {
            "-h" | "--help" => return Ok(Command::Help),
            "--create-tap" => {
                create_tap = true;
                continue;
            }
            _ => {}
        }
        let value = args.next().ok_or_else(|| format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--tap" => tap = Some(parse_ifname(value)?),
            "--ip" => ip = Some(parse_cidr(&value)?),
            "--gateway" => gateway = Some(parse_ip(&value)?),
            "--profile" => {
                profile = Profile::from_name(&value).ok_or_else(|| {
                    format!(
                        "unknown profile {value:?} (known: {})",
                        Profile::NAMES.join(", ")
                    )
                })?
            }
            "--mac" => mac = parse_mac(&value)?,
            "--nvram" => nvram = Some(PathBuf::from(value)),
            "--pls-rpm" => {
                pls_rpm = value
                    .parse()
                    .map_err(|_| format!("bad --pls-rpm {value:?} (0 to 65535)"))?
            }
            _ => return Err(format!("unknown option {flag:?}")),
        }
    }
    let (ip, prefix_len) = ip.ok_or("--ip is required")?;
    Ok(Command::Run(Box::new(Args {
        tap: tap.ok_or("--tap is required")?,
        ip,
        prefix_len,
        gateway,
        profile,
        mac,
        create_tap,
        nvram,
        pls_rpm,
    })))
}

/// Checks an interface name the way Linux does (`dev_valid_name`): 1 to 15 bytes, not `.`
/// or `..`, no `/`, `:`, white space or NUL.
fn parse_ifname(s: String) -> Result<String, String> {
    let valid = (1..IFNAMSIZ).contains(&s.len())
        && s != "."
        && s != ".."
        && !s
            .chars()
            .any(|c| c == '/' || c == ':' || c == '\0' || c.is_whitespace());
    if valid {
        Ok(s)
    } else {
        Err(format!(
            "bad interface name {s:?} (1 to {} bytes, no '/', ':' or white space)",
            IFNAMSIZ - 1
        ))
    }
}

fn parse_ip(s: &str) -> Result<Ipv4Addr, String> {
    s.parse().map_err(|_| format!("bad IPv4 address {s:?}"))
}

fn parse_cidr(s: &str) -> Result<(Ipv4Addr, u8), String> {
    let (ip, len) = s
        .split_once('/')
        .ok_or_else(|| format!("--ip {s:?} needs a prefix length, e.g. 198.18.0.2/24"))?;
    let len: u8 = len
        .parse()
        .ok()
        .filter(|l| *l <= 32)
        .ok_or_else(|| format!("bad prefix length in {s:?}"))?;
    Ok((parse_ip(ip)?, len))
}

fn parse_mac(s: &str) -> Result<[u8; 6], String> {
    let bad = || format!("bad MAC address {s:?}");
    let mut mac = [0u8; 6];
    let mut parts = s.split(':');
    for byte in &mut mac {
        let part = parts.next().filter(|p| p.len() == 2).ok_or_else(bad)?;
        *byte = u8::from_str_radix(part, 16).map_err(|_| bad())?;
    }
    if parts.next().is_some() {
        return Err(bad());
    }
    if mac[0] & 1 != 0 {
        return Err(format!("MAC address {s:?} is a multicast address"));
    }
    Ok(mac)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(args: &[&str]) -> Result<Args, String> {
        match parse(args.iter().map(|s| s.to_string()))? {
            Command::Run(a) => Ok(*a),
            Command::Help => Err("help".into()),
        }
    }

    #[test]
    fn parses_a_full_command_line() {
        let a = run(&[
            "--tap",
            "tap0",
            "--ip",
            "198.18.0.2/24",
            "--gateway",
            "198.18.0.1",
            "--profile",
            "generic",
            "--mac",
            "02:00:00:00:00:2a",
        ])
        .unwrap();
        assert_eq!(a.tap, "tap0");
        assert_eq!((a.ip, a.prefix_len), (Ipv4Addr::new(198, 18, 0, 2), 24));
        assert_eq!(a.gateway, Some(Ipv4Addr::new(198, 18, 0, 1)));
        assert_eq!(a.profile.name(), "generic");
        assert_eq!(a.mac, [2, 0, 0, 0, 0, 0x2a]);
        assert!(!a.create_tap);
        let a = run(&["--create-tap", "--tap", "tap0", "--ip", "198.18.0.2/24"]).unwrap();
        assert!(a.create_tap);
        assert_eq!((a.nvram, a.pls_rpm), (None, 0));
        let a = run(&[
            "--tap",
            "t",
            "--ip",
            "198.18.0.2/24",
            "--nvram",
            "/tmp/x",
            "--pls-rpm",
            "600",
        ])
        .unwrap();
        assert_eq!((a.nvram, a.pls_rpm), (Some(PathBuf::from("/tmp/x")), 600));
        assert!(run(&["--tap", "t", "--ip", "198.18.0.2/24", "--pls-rpm", "-1"]).is_err());
    }

    #[test]
    fn interface_names() {
        let tap = |name: &str| run(&["--tap", name, "--ip", "198.18.0.2/24"]).map(|a| a.tap);
        assert_eq!(tap("enip0").as_deref(), Ok("enip0"));
        assert_eq!(tap("a23456789012345").as_deref(), Ok("a23456789012345"));
        for bad in [
            "",
            ".",
            "..",
            "a234567890123456",
            "a/b",
            "a:1",
            "a b",
            "a\0",
        ] {
            assert!(tap(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn defaults_and_errors() {
        let a = run(&["--tap", "t", "--ip", "198.18.0.2/24"]).unwrap();
        assert_eq!((a.gateway, a.mac), (None, DEFAULT_MAC));
        assert!(run(&["--ip", "198.18.0.2/24"]).is_err());
        assert!(run(&["--tap", "t", "--ip", "198.18.0.2"]).is_err());
        assert!(run(&["--tap", "t", "--ip", "198.18.0.2/33"]).is_err());
        assert!(run(&["--tap", "t", "--ip", "198.18.0.2/24", "--profile", "x"]).is_err());
        assert!(run(&[
            "--tap",
            "t",
            "--ip",
            "198.18.0.2/24",
            "--mac",
            "01:00:00:00:00:00"
        ])
        .is_err());
        assert!(run(&[
            "--tap",
            "t",
            "--ip",
            "198.18.0.2/24",
            "--mac",
            "02:00:00:00:00"
        ])
        .is_err());
        assert!(run(&["--tap"]).is_err());
        assert!(run(&["--bogus", "x"]).is_err());
        assert_eq!(run(&["--help"]).err().as_deref(), Some("help"));
    }
}
