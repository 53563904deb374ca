//! CIP Security (CIP Vol 8) as far as public sources establish it, behind the `cip-security`
//! feature: the CIP Security object (0x5D, `cip_security`), the EtherNet/IP Security
//! object (0x5E, `eip_security`) and the Certificate Management object (0x5F,
//! `cert_mgmt`), their shared state ([`SecurityState`]), its record in the non-volatile
//! store ([`crate::nv::key::SECURITY`]) and the ListIdentity CIP Security item (0x86).
//!
//! The stack holds the settings only: TLS, the certificates' bytes and their checks belong to
//! the runtime beside its TCP sockets, which reads the settings in use
//! ([`crate::Adapter::security`]) when it sets a TLS session up and tells the stack what it
//! found ([`crate::Adapter::set_certificate_status`]). Nothing here is served until the
//! runtime turns the objects on ([`crate::Adapter::enable_security`]): a device built with the
//! feature and not turned on answers exactly as one built without it.

pub(crate) mod cert_mgmt;
pub(crate) mod cip_security;
pub(crate) mod csr;
pub(crate) mod eip_security;
mod port_admin;
mod record;

use core::net::Ipv4Addr;

use crate::time::{Duration, Instant};

pub use cert_mgmt::{CertInstance, CertStatus, MAX_CERTS, MAX_CERT_NAME};
pub use csr::{
    CsrSigner, CsrSubject, CA_CERT_FILE, CSR_FILE_INSTANCE, DEVICE_CERT_FILE, FILE_CLASS,
};

/// Class code of the CIP Security object.
pub const CIP_SECURITY_CLASS: u16 = 0x5D;
/// Class code of the EtherNet/IP Security object.
pub const EIP_SECURITY_CLASS: u16 = 0x5E;
/// Class code of the Certificate Management object.
pub const CERT_MGMT_CLASS: u16 = 0x5F;

/// Security Profiles bit 1: the EtherNet/IP Confidentiality Profile (bit 0, the Integrity
/// Profile, is obsolete).
pub const PROFILE_CONFIDENTIALITY: u16 = 1 << 1;

/// The TLS 1.2 cipher suites this device can use (IANA numbers), EtherNet/IP Security
/// attribute 3: the Confidentiality profile's ECDHE-ECDSA suites with AES-CBC (the two the
/// open reference stack's development branch allows by default) and their AES-GCM (AEAD)
/// counterparts, which are available but allowed only when a configuration allows them.
pub const AVAILABLE_SUITES: [u16; 4] = [
    suite::ECDHE_ECDSA_AES_128_CBC_SHA256,
    suite::ECDHE_ECDSA_AES_256_CBC_SHA384,
    suite::ECDHE_ECDSA_AES_128_GCM_SHA256,
    suite::ECDHE_ECDSA_AES_256_GCM_SHA384,
];

/// The cipher suites allowed in the factory default configuration.
pub const DEFAULT_ALLOWED: [u16; 2] = [
    suite::ECDHE_ECDSA_AES_128_CBC_SHA256,
    suite::ECDHE_ECDSA_AES_256_CBC_SHA384,
];

/// IANA TLS cipher suite numbers.
pub mod suite {
    /// TLS_ECDHE_ECDSA_WITH_AES_128_CBC_SHA256.
    pub const ECDHE_ECDSA_AES_128_CBC_SHA256: u16 = 0xC023;
    /// TLS_ECDHE_ECDSA_WITH_AES_256_CBC_SHA384.
    pub const ECDHE_ECDSA_AES_256_CBC_SHA384: u16 = 0xC024;
    /// TLS_ECDHE_ECDSA_WITH_AES_128_GCM_SHA256.
    pub const ECDHE_ECDSA_AES_128_GCM_SHA256: u16 = 0xC02B;
    /// TLS_ECDHE_ECDSA_WITH_AES_256_GCM_SHA384.
    pub const ECDHE_ECDSA_AES_256_GCM_SHA384: u16 = 0xC02C;
}

/// How long a configuration session lasts without a Kick_Timer.
pub const CONFIG_SESSION: Duration = Duration::from_secs(10);

/// The state of the CIP Security and EtherNet/IP Security objects (attribute 1 of each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ObjectMode {
    /// 0: Factory Default Configuration.
    FactoryDefault = 0,
    /// 1: Configuration In Progress.
    InProgress = 1,
    /// 2: Configured.
    Configured = 2,
    /// 3 (CIP Security object only): Incomplete Configuration, End_Config with the
    /// EtherNet/IP Security object not configured.
    Incomplete = 3,
}

/// Most bytes of a pre-shared key's identity.
pub const MAX_PSK_IDENTITY: usize = 32;
/// Most bytes of a pre-shared key (256 bits).
pub const MAX_PSK: usize = 32;

/// A pre-shared key (EtherNet/IP Security attribute 5): written, stored, never shown.
#[derive(Clone, PartialEq, Eq)]
pub struct Psk {
    /// Its identity (1 to [`MAX_PSK_IDENTITY`] bytes).
    pub identity: heapless::Vec<u8, MAX_PSK_IDENTITY>,
    /// The key (1 to [`MAX_PSK`] bytes).
    pub key: heapless::Vec<u8, MAX_PSK>,
    /// Its usage (USINT, as written).
    pub usage: u8,
}

impl core::fmt::Debug for Psk {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Psk")
            .field("identity", &self.identity)
            .field("key", &"<hidden>")
            .field("usage", &self.usage)
            .finish()
    }
}

/// The EtherNet/IP Security object's settable attributes: what TLS sessions use.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TlsSettings {
    /// Attribute 4: the allowed cipher suites, a subset of [`AVAILABLE_SUITES`].
    pub allowed: heapless::Vec<u16, { AVAILABLE_SUITES.len() }>,
    /// Attribute 6: the Certificate Management instance holding the device certificate.
    pub active_cert: Option<u8>,
    /// Attribute 7: the Certificate Management instance holding the trusted CA.
    pub trusted_ca: Option<u8>,
    /// Attribute 9: clients must present a certificate the trusted CA signed.
    pub verify_client: bool,
    /// Attribute 10: send the certificate chain, not only the device certificate.
    pub send_chain: bool,
    /// Attribute 11: refuse expired certificates.
    pub check_expiration: bool,
    /// Attribute 5: the pre-shared key, if one is configured (at most one).
    pub psk: Option<Psk>,
}

impl TlsSettings {
    /// The factory default settings: the default suites, the factory device certificate
    /// (instance 1), no client verification.
    pub fn factory() -> Self {
        TlsSettings {
            allowed: heapless::Vec::from_slice(&DEFAULT_ALLOWED).unwrap_or_default(),
            active_cert: Some(1),
            trusted_ca: None,
            verify_client: false,
            send_chain: false,
            check_expiration: false,
            psk: None,
        }
    }
}

/// An open configuration session: who began it and when it lapses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ConfigSession {
    /// The client that began it: its address (`None`: a local request), and whether it
    /// came over TLS (then only requests over TLS act in the session).
    owner: Requester,
    /// When it lapses without a Kick_Timer.
    until: Instant,
    /// The state to return to if it is aborted or lapses.
    before: ObjectMode,
}

/// Everything the three objects keep.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SecurityState {
    /// The runtime turned the objects on ([`crate::Adapter::enable_security`]).
    pub enabled: bool,
    /// The runtime listens for TLS on TCP 2221.
    pub tls_port_open: bool,
    /// CIP Security attribute 1.
    pub cip_mode: ObjectMode,
    /// CIP Security attribute 3: the profiles configured (set by End_Config).
    pub profiles_configured: u16,
    cip_session: Option<ConfigSession>,
    /// EtherNet/IP Security attribute 1.
    pub eip_mode: ObjectMode,
    eip_session: Option<ConfigSession>,
    /// The TLS settings in use (applied by Apply_Config, or the factory's).
    pub active: TlsSettings,
    /// The settings under configuration, between Begin_Config and Apply_Config.
    pending: TlsSettings,
    /// The Certificate Management instances (index 0 is instance 1, the factory one).
    pub certs: [CertInstance; MAX_CERTS],
    /// Counts applied changes, for the runtime to notice new settings.
    pub generation: u32,
    /// TCP/IP attribute 14: 44818/tcp closed to explicit messaging (Set_Port_Admin_State;
    /// the runtime stops listening there, and serves TLS on 2221 only).
    pub plain_tcp_closed: bool,
    /// The sockets whose session runs over TLS, one bit per socket index
    /// ([`crate::Adapter::set_session_secure`]).
    secure_sockets: u64,
    /// The CSR's upload through the File object.
    pub(crate) upload: csr::Upload,
}

impl SecurityState {
    /// Factory defaults, turned off.
    pub fn new() -> Self {
        SecurityState {
            enabled: false,
            tls_port_open: false,
            cip_mode: ObjectMode::FactoryDefault,
            profiles_configured: 0,
            cip_session: None,
            eip_mode: ObjectMode::FactoryDefault,
            eip_session: None,
            active: TlsSettings::factory(),
            pending: TlsSettings::factory(),
            certs: cert_mgmt::factory_instances(),
            generation: 0,
            plain_tcp_closed: false,
            secure_sockets: 0,
            upload: csr::Upload::default(),
        }
    }

    /// The settings stored in `store`, as a start finds them (turned off); `None` if there
    /// are none or they are unreadable (the factory defaults hold).
    pub fn stored(
        store: &mut dyn crate::nv::NvStore,
    ) -> Result<Option<SecurityState>, crate::nv::NvError> {
        let mut st = SecurityState::new();
        Ok(record::load(&mut st, store).then_some(st))
    }

    /// Stores the configured settings (a configuration in progress is not stored).
    pub fn save(&self, store: &mut dyn crate::nv::NvStore) -> Result<(), crate::nv::NvError> {
        record::save(self, store)
    }

    /// Notes whether the session on socket `socket` runs over TLS.
    pub fn set_session_secure(&mut self, socket: u8, secure: bool) {
        let bit = 1u64.checked_shl(u32::from(socket)).unwrap_or(0);
        if secure {
            self.secure_sockets |= bit;
        } else {
            self.secure_sockets &= !bit;
        }
    }

    /// True if a request from `origin` came over TLS, or is the device's own (no origin).
    pub(crate) fn is_secure(&self, origin: Option<&crate::io::open::Origin>) -> bool {
        origin.is_none_or(|o| {
            let bit = 1u64.checked_shl(u32::from(o.socket)).unwrap_or(0);
            self.secure_sockets & bit != 0
        })
    }

    /// Back to the factory defaults (Identity Reset type 1), still turned on as it was.
    pub fn factory_reset(&mut self) {
        *self = SecurityState {
            enabled: self.enabled,
            tls_port_open: self.tls_port_open,
            generation: self.generation.wrapping_add(1),
            secure_sockets: self.secure_sockets,
            ..SecurityState::new()
        };
    }

    /// Ends the configuration sessions that lapsed by `now`, returning to the state before.
    pub fn expire(&mut self, now: Instant) {
        if let Some(s) = self.eip_session.filter(|s| s.until <= now) {
            info!("EtherNet/IP Security configuration session lapsed");
            self.eip_session = None;
            self.eip_mode = s.before;
            self.pending = self.active.clone();
        }
        if let Some(s) = self.cip_session.filter(|s| s.until <= now) {
            info!("CIP Security configuration session lapsed");
            self.cip_session = None;
            self.cip_mode = s.before;
        }
    }

    /// The ListIdentity CIP Security item's 5 bytes: profiles supported, the two objects'
    /// states, and the IANA port state flags (TCP 44818 unless closed, UDP 44818, UDP 2222
    /// open; TCP 2221 while the runtime listens for TLS).
    pub fn list_identity_item(&self) -> [u8; 5] {
        let [p0, p1] = PROFILE_CONFIDENTIALITY.to_le_bytes();
        let plain = if self.plain_tcp_closed {
            0b0110
        } else {
            0b0111
        };
        let ports = plain | if self.tls_port_open { 1 << 3 } else { 0 };
        [p0, p1, self.cip_mode as u8, self.eip_mode as u8, ports]
    }

    /// The certificate instance `instance` (from 1), if it exists.
    pub fn cert(&self, instance: u32) -> Option<&CertInstance> {
        let i = usize::try_from(instance).ok()?.checked_sub(1)?;
        self.certs.get(i).filter(|c| c.exists)
    }
}

impl Default for SecurityState {
    fn default() -> Self {
        Self::new()
    }
}

/// Starts a configuration session in `mode` (0x0C unless factory default or configured, or
/// while another client's runs) owned by `owner`. A configured object is reconfigured only
/// over TLS (0x0F privilege violation otherwise): over plaintext anyone could undo it.
fn begin(
    mode: &mut ObjectMode,
    session: &mut Option<ConfigSession>,
    owner: Requester,
    now: Instant,
) -> crate::cip::status::CipResult {
    use crate::cip::status::General;
    if *mode == ObjectMode::Configured && !owner.secure {
        return Err(General::PrivilegeViolation.into());
    }
    if !matches!(
        *mode,
        ObjectMode::FactoryDefault | ObjectMode::Configured | ObjectMode::Incomplete
    ) {
        return Err(General::ObjectStateConflict.into());
    }
    *session = Some(ConfigSession {
        owner,
        until: now.add(CONFIG_SESSION),
        before: *mode,
    });
    *mode = ObjectMode::InProgress;
    Ok(())
}

/// The running session `who` may act in: 0x0C if none runs or another client's does, 0x0F
/// for a plaintext request in a session its address began over TLS (the rule of
/// [`begin`] would mean nothing if the rest of the session could go over plaintext).
fn owned(
    session: &mut Option<ConfigSession>,
    who: Requester,
) -> crate::cip::status::CipResult<&mut ConfigSession> {
    use crate::cip::status::General;
    match session {
        Some(s) if s.owner.addr == who.addr && s.owner.secure && !who.secure => {
            Err(General::PrivilegeViolation.into())
        }
        Some(s) if s.owner.addr == who.addr => Ok(s),
        _ => Err(General::ObjectStateConflict.into()),
    }
}

/// Who sends a request to the security objects.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Requester {
    /// Its address, which owns a configuration session it begins (`None`: a local request).
    addr: Option<Ipv4Addr>,
    /// It came over TLS (or is the device's own).
    secure: bool,
}

/// The requester of the request `ctx` serves.
fn requester<D: crate::device::Device, const C: usize>(ctx: &super::Ctx<'_, D, C>) -> Requester {
    Requester {
        addr: ctx.request.peer.map(|p| *p.ip()),
        secure: ctx.state.security.is_secure(ctx.origin.as_ref()),
    }
}

pub(crate) use port_admin::port_admin;
pub(crate) use record::{load, save};
