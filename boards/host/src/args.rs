//! Command-line parsing for `enip-host`.

use core::net::Ipv4Addr;

use firmware::Profile;

/// How to invoke the program.
pub const USAGE: &str = "\
usage: enip-host --tap IFNAME --ip A.B.C.D/LEN [--gateway A.B.C.D] [--profile NAME] [--mac xx:xx:xx:xx:xx:xx]

  --tap IFNAME       an existing TAP interface to attach to
  --ip A.B.C.D/LEN   the adapter's static address and prefix length
  --gateway A.B.C.D  default gateway (none by default)
  --profile NAME     device profile (default: generic)
  --mac MAC          the adapter's MAC address (default: 02:45:4e:49:50:01)

Logs go to stderr; set RUST_LOG to change the level (default: info).";

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
}

/// Parses the arguments after the program name.
pub fn parse(mut args: impl Iterator<Item = String>) -> Result<Command, String> {
    let mut tap = None;
    let mut ip = None;
    let mut gateway = None;
    let mut profile = Profile::default();
    let mut mac = DEFAULT_MAC;
    while let Some(flag) = args.next() {
        if flag == "-h" || flag == "--help" {
            return Ok(Command::Help);
        }
        let value = args.next().ok_or_else(|| format!("{flag} needs a value"))?;
        match flag.as_str() {
            "--tap" => tap = Some(value),
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
    })))
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
