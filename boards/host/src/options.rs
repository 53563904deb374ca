//! [`Options`]: the settings of a host adapter, and their command line.

use core::net::Ipv4Addr;
use std::path::PathBuf;

/// The options every host adapter understands, for a program's usage text.
pub const OPTIONS_USAGE: &str =
    "  --tap IFNAME       an existing TAP interface to attach to; create it first, typically
                     inside a network namespace: `ip tuntap add dev IFNAME mode tap` and
                     `ip link set IFNAME up` (add `user $USER` to run unprivileged)
  --ip A.B.C.D/LEN   the adapter's static address and prefix length
  --gateway A.B.C.D  default gateway (none by default)
  --mac MAC          the adapter's MAC address (default: 02:45:4e:49:50:01)
  --nv-file PATH     keep the settings that survive a power cycle (TCP/IP attributes 3, 5,
                     6, 8, 9 and 13; the profile's saved settings) in PATH (created if
                     absent); a static interface configuration
                     stored there replaces --ip and --gateway at start (default: in RAM,
                     lost at exit)
  --acd on|off       Address Conflict Detection of the address at start (RFC 5227: about 7
                     to 9 s of ARP probes and announcements before the first IP packet);
                     `off` skips it in this run whatever TCP/IP attribute 10 says, storing
                     nothing (default: on, as attribute 10 says)
  --create-tap       create IFNAME if there is none (needs root or CAP_NET_ADMIN); it is
                     down, has no host address and disappears when the program exits
  --bind A.B.C.D     instead of a TAP: serve on the kernel's TCP/IP stack at this local
                     address (TCP and UDP 44818, UDP 2222), on the interface that holds it;
                     the kernel owns ARP there, so the adapter does no conflict detection
                     (TCP/IP attribute 2 bit 7 clear)
  --tls              with --bind: EtherNet/IP over TLS 1.2 on TCP 2221 too (CIP Security,
                     the Confidentiality profile), and the CIP Security objects (0x5D, 0x5E,
                     0x5F) and ListIdentity item; the device certificate is a factory
                     self-signed one made at first start (kept in PATH.device-cert.pem
                     beside --nv-file PATH; made anew each start without it)
  --tls-cert FILE    the device certificate (PEM; more certificates after it are its
                     chain) instead of the factory one; with --tls-key FILE, its key
  --tls-ca FILE      the CA certificate(s) (PEM) client certificates are checked against
                     once the EtherNet/IP Security object asks for it (attribute 9)

Logs go to stderr; set RUST_LOG to change the level (default: info).";

/// Size of a Linux interface name buffer, the terminating NUL included.
const IFNAMSIZ: usize = 16;

/// The MAC address used when `--mac` is not given (locally administered, unicast).
pub const DEFAULT_MAC: [u8; 6] = [0x02, 0x45, 0x4E, 0x49, 0x50, 0x01];

/// What a command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Parsed {
    /// Run the adapter with these options.
    Run(Options),
    /// Print the usage and exit.
    Help,
}

/// How a host adapter attaches to the network, and where it keeps its settings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// The network it attaches to.
    pub link: Link,
    /// `--nv-file`: the file of the non-volatile store (none: in RAM).
    pub nv_file: Option<PathBuf>,
    /// `--tls`: EtherNet/IP over TLS on 2221 (kernel sockets only).
    pub tls: Option<TlsOptions>,
}

/// EtherNet/IP over TLS: where the certificates come from.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TlsOptions {
    /// `--tls-cert`: the device certificate (and chain), PEM.
    pub cert: Option<PathBuf>,
    /// `--tls-key`: its private key, PEM.
    pub key: Option<PathBuf>,
    /// `--tls-ca`: the trusted CA certificates, PEM.
    pub ca: Option<PathBuf>,
    /// Where the factory certificate is kept (beside `--nv-file`).
    pub factory_cert: Option<PathBuf>,
}

/// The network a host adapter attaches to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Link {
    /// A TAP device, with the adapter's own TCP/IP stack (`--tap`).
    Tap(TapOptions),
    /// The kernel's TCP/IP stack, on the interface holding this address (`--bind`).
    Kernel(Ipv4Addr),
}

/// The adapter on a TAP device, with its own address.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TapOptions {
    /// TAP interface name.
    pub name: String,
    /// Static address.
    pub ip: Ipv4Addr,
    /// Prefix length of the address.
    pub prefix_len: u8,
    /// Default gateway.
    pub gateway: Option<Ipv4Addr>,
    /// MAC address.
    pub mac: [u8; 6],
    /// Create the TAP interface if there is none.
    pub create: bool,
    /// Address Conflict Detection at start, unless attribute 10 turns it off (`--acd`).
    pub acd: bool,
}

impl Options {
    /// The adapter on TAP `tap` at `ip`/`prefix_len`, with the defaults for the rest.
    pub fn new(tap: &str, ip: Ipv4Addr, prefix_len: u8) -> Self {
        Options {
            link: Link::Tap(TapOptions {
                name: tap.into(),
                ip,
                prefix_len,
                gateway: None,
                mac: DEFAULT_MAC,
                create: false,
                acd: true,
            }),
            nv_file: None,
            tls: None,
        }
    }

    /// The adapter on the kernel's sockets, at the local address `ip`.
    pub fn bind(ip: Ipv4Addr) -> Self {
        Options {
            link: Link::Kernel(ip),
            nv_file: None,
            tls: None,
        }
    }

    /// Parses the arguments after the program name. `extra` sees every option this does
    /// not know, with its value, and says whether it took it (e.g. `--profile NAME`).
    pub fn parse(
        mut args: impl Iterator<Item = String>,
        mut extra: impl FnMut(&str, String) -> Result<bool, String>,
    ) -> Result<Parsed, String> {
        let mut tap = None;
        let mut ip = None;
        let mut gateway = None;
        let mut mac = None;
        let mut create = false;
        let mut bind = None;
        let mut nv_file = None;
        let mut acd = None;
        let mut tls = false;
        let mut tls_files = TlsOptions::default();
        while let Some(flag) = args.next() {
            match flag.as_str() {
                "-h" | "--help" => return Ok(Parsed::Help),
                "--create-tap" => {
                    create = true;
                    continue;
                }
                "--tls" => {
                    tls = true;
                    continue;
                }
                _ => {}
            }
            let value = args.next().ok_or_else(|| format!("{flag} needs a value"))?;
            match flag.as_str() {
                "--tap" => tap = Some(parse_ifname(value)?),
                "--ip" => ip = Some(parse_cidr(&value)?),
                "--gateway" => gateway = Some(parse_ip(&value)?),
                "--mac" => mac = Some(parse_mac(&value)?),
                "--bind" => bind = Some(parse_ip(&value)?),
                "--nv-file" => nv_file = Some(PathBuf::from(value)),
                "--tls-cert" => tls_files.cert = Some(PathBuf::from(value)),
                "--tls-key" => tls_files.key = Some(PathBuf::from(value)),
                "--tls-ca" => tls_files.ca = Some(PathBuf::from(value)),
                "--acd" => {
                    acd = Some(match value.as_str() {
                        "on" => true,
                        "off" => false,
                        _ => return Err(format!("--acd takes on or off, not {value:?}")),
                    })
                }
                _ if extra(&flag, value)? => {}
                _ => return Err(format!("unknown option {flag:?}")),
            }
        }
        let link = match bind {
            Some(_) if tap.is_some() || ip.is_some() || gateway.is_some() => {
                return Err(
                    "--bind uses the kernel's interface and address: no --tap, --ip \
                            or --gateway with it"
                        .into(),
                )
            }
            Some(_) if mac.is_some() || create || acd.is_some() => {
                return Err(
                    "--mac, --acd and --create-tap are for a TAP, not --bind (the \
                            kernel owns ARP)"
                        .into(),
                )
            }
            Some(addr) => Link::Kernel(addr),
            None => {
                let (ip, prefix_len) = ip.ok_or("--ip is required (or --bind)")?;
                Link::Tap(TapOptions {
                    name: tap.ok_or("--tap is required (or --bind)")?,
                    ip,
                    prefix_len,
                    gateway,
                    mac: mac.unwrap_or(DEFAULT_MAC),
                    create,
                    acd: acd.unwrap_or(true),
                })
            }
        };
        let files = tls_files != TlsOptions::default();
        let tls = match (tls, &link) {
            (false, _) if files => {
                return Err("--tls-cert, --tls-key and --tls-ca go with --tls".into())
            }
            (false, _) => None,
            (true, Link::Tap(_)) => return Err("--tls needs --bind (the kernel's sockets)".into()),
            (true, Link::Kernel(_)) => Some(TlsOptions {
                factory_cert: nv_file.as_ref().map(|p| {
                    let mut s = p.as_os_str().to_owned();
                    s.push(".device-cert.pem");
                    PathBuf::from(s)
                }),
                ..tls_files
            }),
        };
        Ok(Parsed::Run(Options { link, nv_file, tls }))
    }

    /// The options of this process's command line (`extra` as in [`Options::parse`]); on
    /// `--help` prints `usage` and exits 0, on an error prints it with `usage` and exits 2.
    pub fn from_env_args(
        usage: &str,
        extra: impl FnMut(&str, String) -> Result<bool, String>,
    ) -> Options {
        match Options::parse(std::env::args().skip(1), extra) {
            Ok(Parsed::Run(options)) => options,
            Ok(Parsed::Help) => {
                println!("{usage}");
                std::process::exit(0);
            }
            Err(e) => {
                eprintln!("{}: {e}\n\n{usage}", crate::program_name());
                std::process::exit(2);
            }
        }
    }
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

    /// Parses `args`, taking `--profile NAME` for "generic" only.
    fn run(args: &[&str]) -> Result<Options, String> {
        let profile = |flag: &str, value: String| match (flag, value.as_str()) {
            ("--profile", "generic") => Ok(true),
            ("--profile", _) => Err(format!("unknown profile {value:?}")),
            _ => Ok(false),
        };
        match Options::parse(args.iter().map(|s| s.to_string()), profile)? {
            Parsed::Run(a) => Ok(a),
            Parsed::Help => Err("help".into()),
        }
    }

    /// Parses `args`, which must ask for a TAP.
    fn tap(args: &[&str]) -> Result<TapOptions, String> {
        match run(args)?.link {
            Link::Tap(t) => Ok(t),
            Link::Kernel(_) => Err("kernel".into()),
        }
    }

    #[test]
    fn parses_a_full_command_line() {
        let a = tap(&[
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
        assert_eq!(a.name, "tap0");
        assert_eq!((a.ip, a.prefix_len), (Ipv4Addr::new(198, 18, 0, 2), 24));
        assert_eq!(a.gateway, Some(Ipv4Addr::new(198, 18, 0, 1)));
        assert_eq!(a.mac, [2, 0, 0, 0, 0, 0x2a]);
        assert!(!a.create);
        assert!(a.acd);
        let a = tap(&["--create-tap", "--tap", "tap0", "--ip", "198.18.0.2/24"]).unwrap();
        assert!(a.create);
        let off = [
            "--tap",
            "t",
            "--ip",
            "198.18.0.2/24",
            "--acd",
            "off",
            "--acd",
        ];
        assert!(tap(&[&off[..], &["on"]].concat()).unwrap().acd);
        assert!(!tap(&off[..6]).unwrap().acd);
        assert!(tap(&[&off[..], &["maybe"]].concat()).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--acd", "off"]).is_err());
        let a = run(&["--tap", "t", "--ip", "198.18.0.2/24", "--nv-file", "/x/nv"]).unwrap();
        assert_eq!(a.nv_file, Some(PathBuf::from("/x/nv")));
    }

    #[test]
    fn bind_takes_the_kernel_interface() {
        let a = run(&[
            "--bind",
            "198.18.0.2",
            "--nv-file",
            "/x/nv",
            "--profile",
            "generic",
        ]);
        assert_eq!(
            a,
            Ok(Options {
                link: Link::Kernel(Ipv4Addr::new(198, 18, 0, 2)),
                nv_file: Some(PathBuf::from("/x/nv")),
                tls: None,
            })
        );
        assert!(run(&["--bind", "198.18.0.2/24"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--tap", "t"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--ip", "198.18.0.2/24"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--gateway", "198.18.0.1"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--mac", "02:00:00:00:00:01"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--create-tap"]).is_err());
    }

    #[test]
    fn tls_goes_with_bind_and_keeps_its_factory_certificate_beside_the_store() {
        let a = run(&[
            "--bind",
            "198.18.0.2",
            "--tls",
            "--nv-file",
            "/x/nv",
            "--tls-ca",
            "/x/ca.pem",
        ]);
        let tls = a.unwrap().tls.unwrap();
        assert_eq!(
            tls.factory_cert,
            Some(PathBuf::from("/x/nv.device-cert.pem"))
        );
        assert_eq!(tls.ca, Some(PathBuf::from("/x/ca.pem")));
        assert_eq!(
            run(&["--bind", "198.18.0.2", "--tls"])
                .unwrap()
                .tls
                .unwrap()
                .factory_cert,
            None
        );
        assert!(run(&["--tap", "t", "--ip", "198.18.0.2/24", "--tls"]).is_err());
        assert!(run(&["--bind", "198.18.0.2", "--tls-ca", "/x/ca.pem"]).is_err());
    }

    #[test]
    fn interface_names() {
        let tap = |name: &str| tap(&["--tap", name, "--ip", "198.18.0.2/24"]).map(|a| a.name);
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
        let a = tap(&["--tap", "t", "--ip", "198.18.0.2/24"]).unwrap();
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
