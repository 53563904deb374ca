//! Certificate Management Create_CSR (feature `cip-security`): the subject the request
//! carries reaches the runtime's signer, the reply names the File object instance holding
//! the CSR, and a tool uploads it whole (Initiate_Upload, Upload_Transfer) with its checksum;
//! the device certificate the runtime uses is named by Certificate Management instance 1's
//! attribute 3 and uploaded the same way.
#![cfg(feature = "cip-security")]

mod common;

use common::*;
use enip_stack::objects::security::{
    CertStatus, CsrSigner, CsrSubject, CSR_FILE_INSTANCE, DEVICE_CERT_FILE, FILE_CLASS,
};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use std::sync::{Arc, Mutex};

/// A signer that writes the subject it was given as its "CSR" (`len` bytes, repeated).
struct Fake {
    seen: Arc<Mutex<Vec<(u8, String)>>>,
    csr: Vec<u8>,
    len: usize,
}

impl CsrSigner for Fake {
    fn create_csr(&mut self, instance: u8, s: &CsrSubject<'_>) -> bool {
        let text = format!(
            "CN={} O={} C={} serial={}",
            String::from_utf8_lossy(s.common_name),
            String::from_utf8_lossy(s.organization),
            String::from_utf8_lossy(s.country),
            String::from_utf8_lossy(s.serial_number)
        );
        self.csr = text.bytes().cycle().take(self.len).collect();
        self.seen.lock().unwrap().push((instance, text));
        !s.common_name.is_empty()
    }
    fn csr(&self) -> &[u8] {
        &self.csr
    }
    fn certificate(&self, instance: u8, ca: bool) -> &[u8] {
        match (instance, ca) {
            (1, false) => b"-----BEGIN CERTIFICATE----- device",
            _ => &[],
        }
    }
}

fn call(h: &mut Harness, service: u8, class: u32, instance: u32, data: &[u8]) -> (u8, Vec<u8>) {
    let path = [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
    ];
    let (g, _, d) = status(&h.request(service, &path, data));
    (g, d)
}

fn subject(fields: [&str; 8]) -> Vec<u8> {
    let mut v = Vec::new();
    for f in fields {
        v.push(f.len() as u8);
        v.extend_from_slice(f.as_bytes());
    }
    v
}

/// Uploads File instance `file` in transfers of `size` bytes: the bytes and the packet
/// types.
fn upload_file(h: &mut Harness, file: u32, size: u8) -> (Vec<u8>, Vec<u8>) {
    let (g, d) = call(h, 0x4B, u32::from(FILE_CLASS), file, &[size]);
    assert_eq!((g, d.len()), (0, 5));
    let total = u32::from_le_bytes(d[..4].try_into().unwrap()) as usize;
    assert_eq!(d[4], size);
    let (mut bytes, mut kinds) = (Vec::new(), Vec::new());
    for n in 0..=255u8 {
        let (g, d) = call(h, 0x4F, u32::from(FILE_CLASS), file, &[n]);
        assert_eq!((g, d[0]), (0, n));
        kinds.push(d[1]);
        if matches!(d[1], 2 | 4) {
            let (data, sum) = d[2..].split_at(d.len() - 4);
            bytes.extend_from_slice(data);
            let total_sum = bytes
                .iter()
                .fold(0u16, |s, b| s.wrapping_add(u16::from(*b)));
            assert_eq!(
                total_sum.wrapping_add(u16::from_le_bytes([sum[0], sum[1]])),
                0
            );
            break;
        }
        bytes.extend_from_slice(&d[2..]);
    }
    assert_eq!(bytes.len(), total);
    (bytes, kinds)
}

/// Uploads the CSR.
fn upload(h: &mut Harness, size: u8) -> (Vec<u8>, Vec<u8>) {
    upload_file(h, u32::from(CSR_FILE_INSTANCE), size)
}

fn get(h: &mut Harness, class: u32, instance: u32, attribute: u32) -> (u8, Vec<u8>) {
    let path = [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, instance),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ];
    let (g, _, d) = status(&h.request(0x0E, &path, &[]));
    (g, d)
}

#[test]
fn create_csr_reaches_the_signer_and_the_file_instance_serves_it() {
    let mut h = Harness::new();
    h.adapter.enable_security(true);
    // A created instance to ask for.
    let (g, d) = call(&mut h, 0x08, 0x5F, 0, &[4, b'p', b'l', b'n', b't']);
    assert_eq!((g, d.as_slice()), (0, &[2, 0][..]));
    let req = subject(["dev1", "Plant", "", "", "", "DE", "", "42"]);
    // No signer: not supported; the File class is not there.
    assert_eq!(call(&mut h, 0x4B, 0x5F, 2, &req).0, 0x08);
    assert_eq!(
        call(&mut h, 0x4B, u32::from(FILE_CLASS), 0xC8, &[200]).0,
        0x05
    );
    let seen = Arc::new(Mutex::new(Vec::new()));
    let fake = Fake {
        seen: seen.clone(),
        csr: Vec::new(),
        len: 700,
    };
    h.adapter.attach_csr_signer(Box::leak(Box::new(fake)));
    // Nothing to upload yet.
    assert_eq!(
        call(&mut h, 0x4B, u32::from(FILE_CLASS), 0xC8, &[200]).0,
        0x0C
    );
    // The factory instance: 0x0C; a country of one letter: 0x20; a short request: 0x13.
    assert_eq!(call(&mut h, 0x4B, 0x5F, 1, &req).0, 0x0C);
    let bad = subject(["dev1", "", "", "", "", "D", "", ""]);
    assert_eq!(call(&mut h, 0x4B, 0x5F, 2, &bad).0, 0x20);
    assert_eq!(call(&mut h, 0x4B, 0x5F, 2, &req[..req.len() - 1]).0, 0x13);
    assert!(seen.lock().unwrap().is_empty());
    // The reply: a padded path with its size to File instance 0xC8.
    let (g, d) = call(&mut h, 0x4B, 0x5F, 2, &req);
    assert_eq!((g, d.as_slice()), (0, &[2, 0x20, 0x37, 0x24, 0xC8][..]));
    assert_eq!(
        seen.lock().unwrap().as_slice(),
        &[(2, "CN=dev1 O=Plant C=DE serial=42".to_string())]
    );
    // Instance 2 is Configuring (2).
    assert_eq!(get(&mut h, 0x5F, 2, 2), (0, vec![2]));
    // Upload: 700 bytes in 4 transfers of 200, then in 3 of 255.
    let (bytes, kinds) = upload(&mut h, 200);
    assert_eq!(kinds, [0, 1, 1, 2]);
    assert!(bytes.starts_with(b"CN=dev1 O=Plant C=DE serial=42CN=dev1"));
    let (again, kinds) = upload(&mut h, 255);
    assert_eq!((again, kinds), (bytes, vec![0, 1, 2]));
    // A transfer out of turn: 0x20; one before Initiate_Upload: 0x0C.
    assert_eq!(call(&mut h, 0x4F, 0x37, 0xC8, &[0]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4B, 0x37, 0xC8, &[100]).0, 0);
    assert_eq!(call(&mut h, 0x4F, 0x37, 0xC8, &[3]).0, 0x20);
    // A resend of the last transfer gives the same bytes.
    let first = call(&mut h, 0x4F, 0x37, 0xC8, &[0]);
    assert_eq!(call(&mut h, 0x4F, 0x37, 0xC8, &[0]), first);
    // A signer that fails: 0x0C.
    let empty_cn = subject(["", "", "", "", "", "", "", ""]);
    assert_eq!(call(&mut h, 0x4B, 0x5F, 2, &empty_cn).0, 0x0C);
}

#[test]
fn the_certificates_in_use_are_named_by_path_and_uploaded() {
    let mut h = Harness::new();
    h.adapter.enable_security(true);
    h.adapter
        .set_certificate_status(1, CertStatus::Verified, CertStatus::NotVerified);
    call(&mut h, 0x08, 0x5F, 0, &[1, b'x']);
    // Without the runtime's certificates: status and an empty path.
    assert_eq!(get(&mut h, 0x5F, 1, 3), (0, vec![1, 0]));
    let fake = Fake {
        seen: Arc::default(),
        csr: Vec::new(),
        len: 0,
    };
    h.adapter.attach_csr_signer(Box::leak(Box::new(fake)));
    // Instance 1's device certificate is in File instance 0xC9; it has no CA certificate.
    assert_eq!(
        get(&mut h, 0x5F, 1, 3),
        (0, vec![1, 2, 0x20, 0x37, 0x24, DEVICE_CERT_FILE])
    );
    assert_eq!(get(&mut h, 0x5F, 1, 4), (0, vec![0, 0]));
    assert_eq!(get(&mut h, 0x5F, 2, 3), (0, vec![0, 0]));
    let (all_g, all) = call(&mut h, 0x01, 0x5F, 1, &[]);
    assert_eq!(all_g, 0);
    assert!(
        all.windows(6).any(|w| w == [1, 2, 0x20, 0x37, 0x24, 0xC9]),
        "{all:x?}"
    );
    let (bytes, kinds) = upload_file(&mut h, u32::from(DEVICE_CERT_FILE), 16);
    assert_eq!(bytes, b"-----BEGIN CERTIFICATE----- device");
    assert_eq!(kinds, [0, 1, 2]);
    // File state: loaded (2) for the certificate, empty (1) for the CA and the CSR.
    let file = u32::from(FILE_CLASS);
    assert_eq!(get(&mut h, file, 0xC9, 1), (0, vec![2]));
    assert_eq!(get(&mut h, file, 0xCA, 1), (0, vec![1]));
    assert_eq!(get(&mut h, file, 0xC8, 1), (0, vec![1]));
    assert_eq!(call(&mut h, 0x4B, file, 0xCA, &[16]).0, 0x0C);
    // A transfer from another file than the one initiated: 0x0C.
    assert_eq!(call(&mut h, 0x4B, file, 0xC9, &[16]).0, 0);
    assert_eq!(call(&mut h, 0x4F, file, 0xC8, &[0]).0, 0x0C);
    assert_eq!(call(&mut h, 0x4F, file, 0xC9, &[0]).0, 0);
}
