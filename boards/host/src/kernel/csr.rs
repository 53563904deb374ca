//! Certificate signing requests with the device key (Certificate Management Create_CSR):
//! the stack parses the request and serves the result, this makes the PKCS#10 request with
//! OpenSSL ([`Signer`], handed to the adapter with `Adapter::attach_csr_signer`).

use enip_stack::objects::security::{CsrSigner, CsrSubject};
use openssl::hash::MessageDigest;
use openssl::nid::Nid;
use openssl::pkey::{PKey, Private};
use openssl::x509::{X509NameBuilder, X509Req, X509};

/// Makes CSRs with the device key (fields a request leaves empty come from the device
/// certificate's subject), and holds the certificates in use as Certificate Management
/// instance 1's, for the File object instances its attributes 3 and 4 name.
pub struct Signer {
    key: PKey<Private>,
    cert: X509,
    csr: Vec<u8>,
    /// The device certificate (PEM).
    device_pem: Vec<u8>,
    /// The trusted CA certificates (PEM, concatenated; empty without `--tls-ca`).
    ca_pem: Vec<u8>,
}

/// The subject's fields in the request's order, with their OIDs.
const FIELDS: [Nid; 8] = [
    Nid::COMMONNAME,
    Nid::ORGANIZATIONNAME,
    Nid::ORGANIZATIONALUNITNAME,
    Nid::LOCALITYNAME,
    Nid::STATEORPROVINCENAME,
    Nid::COUNTRYNAME,
    Nid::PKCS9_EMAILADDRESS,
    Nid::SERIALNUMBER,
];

impl Signer {
    /// A signer with the device certificate `cert`, its key `key` and the trusted CA
    /// certificates `ca`.
    pub fn new(cert: X509, key: PKey<Private>, ca: &[X509]) -> Result<Self, String> {
        let pem = |c: &X509| c.to_pem().map_err(|e| e.to_string());
        let mut ca_pem = Vec::new();
        for c in ca {
            ca_pem.extend(pem(c)?);
        }
        Ok(Signer {
            key,
            device_pem: pem(&cert)?,
            cert,
            csr: Vec::new(),
            ca_pem,
        })
    }

    /// The PEM request for `subject`.
    fn make(&self, subject: &CsrSubject<'_>) -> Result<Vec<u8>, String> {
        let e = |e: openssl::error::ErrorStack| e.to_string();
        let given = [
            subject.common_name,
            subject.organization,
            subject.organizational_unit,
            subject.locality,
            subject.state,
            subject.country,
            subject.email,
            subject.serial_number,
        ];
        let mut name = X509NameBuilder::new().map_err(e)?;
        for (nid, value) in FIELDS.iter().zip(given) {
            if value.is_empty() {
                let from_cert = self.cert.subject_name().entries_by_nid(*nid).next();
                if let Some(entry) = from_cert {
                    let v = entry.data().to_string().map_err(e)?;
                    name.append_entry_by_nid(*nid, &v).map_err(e)?;
                }
                continue;
            }
            let v = std::str::from_utf8(value).map_err(|_| format!("{nid:?}: not UTF-8"))?;
            name.append_entry_by_nid(*nid, v).map_err(e)?;
        }
        let mut req = X509Req::builder().map_err(e)?;
        req.set_version(0).map_err(e)?;
        req.set_subject_name(&name.build()).map_err(e)?;
        req.set_pubkey(&self.key).map_err(e)?;
        req.sign(&self.key, MessageDigest::sha256()).map_err(e)?;
        req.build().to_pem().map_err(e)
    }
}

impl CsrSigner for Signer {
    fn create_csr(&mut self, instance: u8, subject: &CsrSubject<'_>) -> bool {
        match self.make(subject) {
            Ok(pem) => {
                log::info!("CSR made for certificate instance {instance}");
                self.csr = pem;
                true
            }
            Err(err) => {
                log::warn!("CSR for certificate instance {instance}: {err}");
                false
            }
        }
    }
    fn csr(&self) -> &[u8] {
        &self.csr
    }
    fn certificate(&self, instance: u8, ca: bool) -> &[u8] {
        match (instance, ca) {
            (1, false) => &self.device_pem,
            (1, true) => &self.ca_pem,
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use openssl::ec::{EcGroup, EcKey};
    use openssl::x509::X509Builder;

    fn device() -> (X509, PKey<Private>) {
        let group = EcGroup::from_curve_name(Nid::X9_62_PRIME256V1).unwrap();
        let key = PKey::from_ec_key(EcKey::generate(&group).unwrap()).unwrap();
        let mut n = X509NameBuilder::new().unwrap();
        n.append_entry_by_nid(Nid::COMMONNAME, "factory").unwrap();
        n.append_entry_by_nid(Nid::ORGANIZATIONNAME, "Maker")
            .unwrap();
        let n = n.build();
        let mut b = X509Builder::new().unwrap();
        b.set_subject_name(&n).unwrap();
        b.set_issuer_name(&n).unwrap();
        b.set_pubkey(&key).unwrap();
        b.sign(&key, MessageDigest::sha256()).unwrap();
        (b.build(), key)
    }

    #[test]
    fn the_request_carries_the_subject_and_the_device_key_and_verifies() {
        let (cert, key) = device();
        let mut s = Signer::new(cert.clone(), key.clone(), &[]).unwrap();
        assert_eq!(s.certificate(1, false), cert.to_pem().unwrap());
        assert!(s.certificate(1, true).is_empty() && s.certificate(2, false).is_empty());
        let subject = CsrSubject {
            common_name: b"dev1",
            country: b"DE",
            serial_number: b"42",
            ..CsrSubject::default()
        };
        assert!(s.create_csr(2, &subject));
        let req = X509Req::from_pem(s.csr()).unwrap();
        assert!(req.verify(&key).unwrap());
        assert!(req.public_key().unwrap().public_eq(&key));
        let text = |nid| {
            let mut e = req.subject_name().entries_by_nid(nid);
            e.next().map(|e| e.data().to_string().unwrap())
        };
        assert_eq!(text(Nid::COMMONNAME).as_deref(), Some("dev1"));
        assert_eq!(text(Nid::COUNTRYNAME).as_deref(), Some("DE"));
        assert_eq!(text(Nid::SERIALNUMBER).as_deref(), Some("42"));
        // Not given: the device certificate's.
        assert_eq!(text(Nid::ORGANIZATIONNAME).as_deref(), Some("Maker"));
        assert_eq!(text(Nid::LOCALITYNAME), None);
        // A subject OpenSSL refuses (a three-letter country): false, the last CSR kept.
        let bad = CsrSubject {
            common_name: b"x",
            country: b"DEU",
            ..CsrSubject::default()
        };
        let before = s.csr().to_vec();
        assert!(!s.create_csr(2, &bad));
        assert_eq!(s.csr(), before);
    }
}
