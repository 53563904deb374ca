//! EtherNet/IP over TLS (CIP Security, the EtherNet/IP Confidentiality profile) on TCP 2221:
//! the device's certificate material ([`Material`]: `--tls-cert`/`--tls-key`, or a factory
//! self-signed ECDSA P-256 certificate made at first start and kept beside `--nv-file`), and
//! the OpenSSL server context built from the EtherNet/IP Security object's settings in use
//! ([`context`]): TLS 1.2 only, the allowed cipher suites, client verification against the
//! trusted CA (`--tls-ca`, Certificate Management instance 1's CA certificate) when attribute
//! 9 asks for it, expiry checked as attribute 11 says, no renegotiation.
//!
//! The stack sees the plaintext encapsulation frames, exactly as on 44818.

use std::path::Path;

use enip_stack::objects::security::{suite, CertStatus, SecurityState};
use enip_stack::{Adapter, Device};
use openssl::asn1::Asn1Time;
use openssl::bn::{BigNum, MsbOption};
use openssl::ec::{EcGroup, EcKey};
use openssl::hash::MessageDigest;
use openssl::nid::Nid;
use openssl::pkey::{PKey, Private};
use openssl::ssl::{
    SslContext, SslContextBuilder, SslMethod, SslOptions, SslVerifyMode, SslVersion,
};
use openssl::x509::store::X509StoreBuilder;
use openssl::x509::verify::X509VerifyFlags;
use openssl::x509::{X509NameBuilder, X509};

use crate::options::TlsOptions;

/// The IANA suites of the EtherNet/IP Security object and their OpenSSL names.
const SUITE_NAMES: [(u16, &str); 4] = [
    (
        suite::ECDHE_ECDSA_AES_128_CBC_SHA256,
        "ECDHE-ECDSA-AES128-SHA256",
    ),
    (
        suite::ECDHE_ECDSA_AES_256_CBC_SHA384,
        "ECDHE-ECDSA-AES256-SHA384",
    ),
    (
        suite::ECDHE_ECDSA_AES_128_GCM_SHA256,
        "ECDHE-ECDSA-AES128-GCM-SHA256",
    ),
    (
        suite::ECDHE_ECDSA_AES_256_GCM_SHA384,
        "ECDHE-ECDSA-AES256-GCM-SHA384",
    ),
];

/// The TLS session id context of the server's sessions (what they may be resumed for).
const SESSION_ID_CONTEXT: &[u8] = b"enip-rs EtherNet/IP over TLS";

/// Days the factory certificate is valid.
const FACTORY_DAYS: u32 = 20 * 365;

/// The device's certificate, key and trusted CA (Certificate Management instance 1).
pub struct Material {
    cert: X509,
    chain: Vec<X509>,
    key: PKey<Private>,
    ca: Vec<X509>,
}

impl Material {
    /// Loads the files `options` names; without `--tls-cert`, the factory certificate kept
    /// at `factory` (made there if absent; made anew each start if `None`).
    pub fn load(options: &TlsOptions, factory: Option<&Path>, cn: &str) -> Result<Self, String> {
        let read = |p: &Path| std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()));
        let (cert, chain, key) = match (&options.cert, &options.key) {
            (Some(c), Some(k)) => {
                let mut certs =
                    X509::stack_from_pem(&read(c)?).map_err(|e| format!("{}: {e}", c.display()))?;
                if certs.is_empty() {
                    return Err(format!("{}: no certificate", c.display()));
                }
                let cert = certs.remove(0);
                let key = PKey::private_key_from_pem(&read(k)?)
                    .map_err(|e| format!("{}: {e}", k.display()))?;
                (cert, certs, key)
            }
            (None, None) => {
                let (cert, key) = factory_certificate(factory, cn)?;
                (cert, Vec::new(), key)
            }
            _ => return Err("--tls-cert and --tls-key go together".into()),
        };
        let ca = match &options.ca {
            Some(p) => {
                X509::stack_from_pem(&read(p)?).map_err(|e| format!("{}: {e}", p.display()))?
            }
            None => Vec::new(),
        };
        Ok(Material {
            cert,
            chain,
            key,
            ca,
        })
    }

    /// A maker of CSRs with the device key, for Certificate Management Create_CSR, holding
    /// the certificates in use for the File instances instance 1's attributes 3 and 4 name.
    pub fn csr_signer(&self) -> Result<super::csr::Signer, String> {
        super::csr::Signer::new(self.cert.clone(), self.key.clone(), &self.ca)
    }

    /// Tells the adapter what was found: instance 1's device certificate (and its CA).
    pub fn report<D: Device>(&self, adapter: &mut Adapter<D>) {
        let matches = self.cert.public_key().is_ok_and(|k| k.public_eq(&self.key));
        let device = if matches {
            CertStatus::Verified
        } else {
            CertStatus::Invalid
        };
        let ca = if self.ca.is_empty() {
            CertStatus::NotVerified
        } else {
            CertStatus::Verified
        };
        adapter.set_certificate_status(1, device, ca);
    }
}

/// The factory certificate and key kept at `path` (`.pem`: certificate then key), made and
/// saved there if absent.
fn factory_certificate(path: Option<&Path>, cn: &str) -> Result<(X509, PKey<Private>), String> {
    if let Some(p) = path.filter(|p| p.exists()) {
        let pem = std::fs::read(p).map_err(|e| format!("{}: {e}", p.display()))?;
        let cert = X509::from_pem(&pem).map_err(|e| format!("{}: {e}", p.display()))?;
        let key = PKey::private_key_from_pem(&pem).map_err(|e| format!("{}: {e}", p.display()))?;
        return Ok((cert, key));
    }
    let (cert, key) = self_signed(cn).map_err(|e| format!("factory certificate: {e}"))?;
    if let Some(p) = path {
        let mut pem = cert.to_pem().map_err(|e| e.to_string())?;
        pem.extend(key.private_key_to_pem_pkcs8().map_err(|e| e.to_string())?);
        write_private(p, &pem).map_err(|e| format!("{}: {e}", p.display()))?;
        log::info!("factory device certificate made: {}", p.display());
    }
    Ok((cert, key))
}

/// Writes `bytes` to a new file readable by its owner only.
fn write_private(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    use std::os::unix::fs::OpenOptionsExt;
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .mode(0o600)
        .open(path)?;
    f.write_all(bytes)
}

/// A self-signed ECDSA P-256 certificate for `cn`.
fn self_signed(cn: &str) -> Result<(X509, PKey<Private>), openssl::error::ErrorStack> {
    let group = EcGroup::from_curve_name(Nid::X9_62_PRIME256V1)?;
    let key = PKey::from_ec_key(EcKey::generate(&group)?)?;
    let mut name = X509NameBuilder::new()?;
    name.append_entry_by_nid(Nid::COMMONNAME, cn)?;
    let name = name.build();
    let mut b = X509::builder()?;
    b.set_version(2)?;
    let mut serial = BigNum::new()?;
    serial.rand(64, MsbOption::MAYBE_ZERO, false)?;
    let serial = serial.to_asn1_integer()?;
    b.set_serial_number(&serial)?;
    b.set_subject_name(&name)?;
    b.set_issuer_name(&name)?;
    b.set_pubkey(&key)?;
    let (from, until) = (
        Asn1Time::days_from_now(0)?,
        Asn1Time::days_from_now(FACTORY_DAYS)?,
    );
    b.set_not_before(&from)?;
    b.set_not_after(&until)?;
    b.sign(&key, MessageDigest::sha256())?;
    Ok((b.build(), key))
}

/// The OpenSSL cipher list of the allowed suites.
pub fn cipher_list(allowed: &[u16]) -> String {
    let names = allowed.iter().filter_map(|s| {
        SUITE_NAMES
            .iter()
            .find(|(id, _)| id == s)
            .map(|(_, name)| *name)
    });
    names.collect::<Vec<_>>().join(":")
}

/// The server context for the settings in use of `st`.
pub fn context(st: &SecurityState, m: &Material) -> Result<SslContext, String> {
    let a = &st.active;
    if a.active_cert != Some(1) {
        return Err(format!(
            "device certificate instance {:?}: only instance 1 has a certificate here",
            a.active_cert
        ));
    }
    if a.psk.is_some() {
        log::warn!("a pre-shared key is configured (EtherNet/IP Security attribute 5): stored, not used (no PSK cipher suite is offered)");
    }
    let e = |e: openssl::error::ErrorStack| e.to_string();
    let mut b = SslContextBuilder::new(SslMethod::tls_server()).map_err(e)?;
    b.set_min_proto_version(Some(SslVersion::TLS1_2))
        .map_err(e)?;
    b.set_max_proto_version(Some(SslVersion::TLS1_2))
        .map_err(e)?;
    b.set_cipher_list(&cipher_list(&a.allowed)).map_err(e)?;
    b.set_options(SslOptions::NO_RENEGOTIATION | SslOptions::CIPHER_SERVER_PREFERENCE);
    // Sessions are resumed (from this context's cache or tickets: a new configuration makes
    // a new context, whose sessions start anew). Without a session id context a verifying
    // server fails a client's resumption outright instead of a full handshake.
    b.set_session_id_context(SESSION_ID_CONTEXT).map_err(e)?;
    b.set_certificate(&m.cert).map_err(e)?;
    b.set_private_key(&m.key).map_err(e)?;
    b.check_private_key().map_err(e)?;
    if a.send_chain {
        for c in &m.chain {
            b.add_extra_chain_cert(c.clone()).map_err(e)?;
        }
    }
    if a.verify_client {
        let mut store = X509StoreBuilder::new().map_err(e)?;
        if a.trusted_ca == Some(1) {
            for c in &m.ca {
                store.add_cert(c.clone()).map_err(e)?;
            }
        } else {
            log::warn!("trusted CA instance {:?} holds no certificate here: every client certificate is refused", a.trusted_ca);
        }
        if !a.check_expiration {
            store.set_flags(X509VerifyFlags::NO_CHECK_TIME).map_err(e)?;
        }
        b.set_cert_store(store.build());
        b.set_verify(SslVerifyMode::PEER | SslVerifyMode::FAIL_IF_NO_PEER_CERT);
    }
    Ok(b.build())
}

#[cfg(test)]
mod tests {
    use super::*;
    use enip_stack::objects::security::{AVAILABLE_SUITES, DEFAULT_ALLOWED};

    #[test]
    fn every_available_suite_has_its_openssl_name_in_the_order_allowed() {
        assert_eq!(
            cipher_list(&DEFAULT_ALLOWED),
            "ECDHE-ECDSA-AES128-SHA256:ECDHE-ECDSA-AES256-SHA384"
        );
        let all = cipher_list(&AVAILABLE_SUITES);
        assert_eq!(all.split(':').count(), AVAILABLE_SUITES.len());
        assert_eq!(
            cipher_list(&[0xC02C, 0x003C]),
            "ECDHE-ECDSA-AES256-GCM-SHA384"
        );
        // OpenSSL knows every name (a list of which it knows none is refused).
        let mut b = SslContextBuilder::new(SslMethod::tls_server()).unwrap();
        for name in all.split(':') {
            b.set_cipher_list(name).unwrap();
        }
        assert!(b.set_cipher_list("NO-SUCH-SUITE").is_err());
    }

    #[test]
    fn the_factory_certificate_is_made_once_and_kept() {
        let path = std::env::temp_dir().join(format!("enip-factory-{}.pem", std::process::id()));
        let _ = std::fs::remove_file(&path);
        let (cert, key) = factory_certificate(Some(&path), "enip-rs generic").unwrap();
        assert!(cert.public_key().unwrap().public_eq(&key));
        let (again, _) = factory_certificate(Some(&path), "other").unwrap();
        assert_eq!(again.to_der().unwrap(), cert.to_der().unwrap());
        std::fs::remove_file(&path).unwrap();
    }

    /// A TLS 1.2 handshake over a socket pair between a session of `server` and one of
    /// `client` (resuming `resume` if given): the client's session and whether it was
    /// resumed, or the server's error.
    fn handshake(
        server: &SslContext,
        client: &SslContext,
        resume: Option<&openssl::ssl::SslSessionRef>,
    ) -> Result<(openssl::ssl::SslSession, bool), String> {
        use openssl::ssl::Ssl;
        let (a, b) = std::os::unix::net::UnixStream::pair().unwrap();
        std::thread::scope(|scope| {
            // Each side sends its close_notify: OpenSSL forgets the session of a
            // connection that ends without one.
            let accepted = scope.spawn(move || {
                let mut s = Ssl::new(server).unwrap().accept(a);
                s.as_mut()
                    .map(|s| drop(s.shutdown()))
                    .map_err(|e| e.to_string())
            });
            let mut ssl = Ssl::new(client).unwrap();
            if let Some(s) = resume {
                // SAFETY: the session comes from a context with the same settings (the
                // client's), as `set_session` requires.
                unsafe { ssl.set_session(s).unwrap() };
            }
            let connected = ssl.connect(b);
            accepted.join().unwrap()?;
            let mut stream = connected.map_err(|e| e.to_string())?;
            let _ = stream.shutdown();
            let session = stream.ssl().session().unwrap().to_owned();
            Ok((session, stream.ssl().session_reused()))
        })
    }

    #[test]
    fn a_client_resumes_its_session_while_client_certificates_are_verified() {
        let (cert, key) = self_signed("device").unwrap();
        let (client_cert, client_key) = self_signed("scanner").unwrap();
        // The scanner's self-signed certificate is the trusted CA.
        let material = Material {
            cert,
            chain: Vec::new(),
            key,
            ca: vec![client_cert.clone()],
        };
        let mut st = SecurityState::new();
        st.active.verify_client = true;
        st.active.trusted_ca = Some(1);
        let server = context(&st, &material).unwrap();
        let mut b = SslContextBuilder::new(SslMethod::tls_client()).unwrap();
        b.set_certificate(&client_cert).unwrap();
        b.set_private_key(&client_key).unwrap();
        b.set_verify(SslVerifyMode::NONE);
        let client = b.build();
        let (session, resumed) = handshake(&server, &client, None).unwrap();
        assert!(!resumed);
        // OpenSSL fails a resumption outright (session id context uninitialized) on a
        // verifying server without a session id context, instead of a full handshake.
        let (_, resumed) = handshake(&server, &client, Some(&session)).unwrap();
        assert!(resumed);
    }
}
