//! Certificate signing requests: the Certificate Management object's Create_CSR service
//! (0x4B at an instance), the runtime hook that makes the CSR ([`CsrSigner`]: the stack has
//! no key and no signature), and the File object instance (class 0x37) the reply's path
//! names, from which a tool uploads the CSR (Initiate_Upload, Upload_Transfer). Two more
//! File instances hold the certificates the runtime uses as Certificate Management instance
//! 1's device certificate and CA certificate, which its attributes 3 and 4 name.
//!
//! Create_CSR's request is eight SHORT_STRINGs, the subject's Common Name, Organization,
//! Organizational Unit, City/Locality, State, Country, Email and Serial Number (a ninth,
//! optional, is accepted and not used); a country is two letters or empty (0x20 otherwise).
//! Its reply is a padded EPATH with a USINT size naming [`CSR_FILE_INSTANCE`].

use super::super::serve::{serve, Object};
use super::super::Ctx;
use crate::cip::object::{AttributeDef, ClassDef, DataType};
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::Request;
use crate::device::Device;
use crate::wire::{Reader, Writer};

/// Class code of the File object.
pub const FILE_CLASS: u16 = 0x37;
/// The File object instance that holds the last CSR made.
pub const CSR_FILE_INSTANCE: u8 = 0xC8;
/// The File object instance that holds Certificate Management instance 1's device
/// certificate.
pub const DEVICE_CERT_FILE: u8 = 0xC9;
/// The File object instance that holds Certificate Management instance 1's CA certificate.
pub const CA_CERT_FILE: u8 = 0xCA;
/// Service code of Create_CSR (Certificate Management instances).
pub(crate) const CREATE_CSR: u8 = 0x4B;
/// Service codes of the File object's upload.
const INITIATE_UPLOAD: u8 = 0x4B;
const UPLOAD_TRANSFER: u8 = 0x4F;
/// Upload_Transfer packet types.
const FIRST: u8 = 0;
const MIDDLE: u8 = 1;
const LAST: u8 = 2;
const FIRST_AND_LAST: u8 = 4;
/// File object states: file empty, file loaded, upload initiated, upload in progress.
const EMPTY: u8 = 1;
const LOADED: u8 = 2;
const UPLOAD_INITIATED: u8 = 3;
const UPLOAD_IN_PROGRESS: u8 = 5;

/// The subject Create_CSR asks for, each field as the request carried it (empty: not given;
/// the runtime may take it from the device certificate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CsrSubject<'a> {
    /// CN.
    pub common_name: &'a [u8],
    /// O.
    pub organization: &'a [u8],
    /// OU.
    pub organizational_unit: &'a [u8],
    /// L.
    pub locality: &'a [u8],
    /// ST.
    pub state: &'a [u8],
    /// C: two letters, or empty.
    pub country: &'a [u8],
    /// emailAddress.
    pub email: &'a [u8],
    /// serialNumber.
    pub serial_number: &'a [u8],
}

/// What the runtime provides to make CSRs with the device key
/// ([`crate::Adapter::attach_csr_signer`]).
pub trait CsrSigner {
    /// Makes a PKCS#10 request for `subject` signed with the device key, for Certificate
    /// Management instance `instance`, replacing the last one; false if it cannot.
    fn create_csr(&mut self, instance: u8, subject: &CsrSubject<'_>) -> bool;
    /// The last request made (PEM), empty if none.
    fn csr(&self) -> &[u8];
    /// The certificate (PEM) the runtime uses as Certificate Management instance
    /// `instance`'s device certificate, or with `ca` its CA certificate; empty if none.
    fn certificate(&self, _instance: u8, _ca: bool) -> &[u8] {
        &[]
    }
}

/// The File instance holding instance `instance`'s device (or `ca`: CA) certificate, if
/// the runtime has one.
pub(crate) fn certificate_file(
    signer: Option<&(dyn CsrSigner + 'static)>,
    instance: u32,
    ca: bool,
) -> Option<u8> {
    let present = signer.is_some_and(|s| !s.certificate(1, ca).is_empty());
    (instance == 1 && present).then_some(if ca { CA_CERT_FILE } else { DEVICE_CERT_FILE })
}

/// The File object's upload in progress: its file, transfer size and next transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Upload {
    /// The File instance uploaded.
    file: u8,
    /// The transfer size agreed by Initiate_Upload (0: no upload).
    size: u8,
    /// The transfers sent so far.
    sent: u32,
}

/// Parses Create_CSR's request.
fn subject(data: &[u8]) -> CipResult<CsrSubject<'_>> {
    fn field<'a>(r: &mut Reader<'a>) -> CipResult<&'a [u8]> {
        let len = usize::from(r.u8()?);
        Ok(r.take(len)?)
    }
    let mut r = Reader::new(data);
    let s = CsrSubject {
        common_name: field(&mut r)?,
        organization: field(&mut r)?,
        organizational_unit: field(&mut r)?,
        locality: field(&mut r)?,
        state: field(&mut r)?,
        country: field(&mut r)?,
        email: field(&mut r)?,
        serial_number: field(&mut r)?,
    };
    if r.remaining() != 0 {
        field(&mut r)?;
    }
    if r.remaining() != 0 {
        return Err(General::TooMuchData.into());
    }
    if !matches!(s.country.len(), 0 | 2) {
        return Err(General::InvalidParameter.into());
    }
    Ok(s)
}

/// Create_CSR on Certificate Management instance `instance`: 0x08 without a signer, 0x0C on
/// instance 1 (the factory instance, as the open reference stack's development branch
/// answers) or if the signer fails; else the path to the CSR's File instance.
pub(crate) fn create_csr<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    instance: u32,
    data: &[u8],
    w: &mut Writer<'_>,
) -> CipResult {
    let Some(signer) = ctx.csr.as_deref_mut() else {
        return Err(General::ServiceNotSupported.into());
    };
    if instance == 1 {
        return Err(General::ObjectStateConflict.into());
    }
    let subject = subject(data)?;
    let i = u8::try_from(instance).map_err(|_| CipError::new(General::ObjectDoesNotExist))?;
    if !signer.create_csr(i, &subject) {
        return Err(General::ObjectStateConflict.into());
    }
    let st = &mut ctx.state.security;
    st.upload = Upload::default();
    if let Some(c) = st.certs.get_mut(usize::from(i).saturating_sub(1)) {
        c.configuring = true;
    }
    super::cert_mgmt::emit_path(w, FILE_CLASS as u8, CSR_FILE_INSTANCE)
}

/// The File class as far as the certificates need it: instances [`CSR_FILE_INSTANCE`],
/// [`DEVICE_CERT_FILE`] and [`CA_CERT_FILE`], read only.
pub const CLASS: ClassDef = ClassDef {
    id: FILE_CLASS,
    name: "File",
    revision: 1,
    max_instance: CA_CERT_FILE as u32,
    attributes: &[
        AttributeDef::get(1, DataType::Usint, "State"),
        AttributeDef::get(6, DataType::Udint, "File Size"),
        AttributeDef::get(7, DataType::Int, "File Checksum"),
        AttributeDef::get(10, DataType::Usint, "File Type"),
    ],
    get_all: &[1, 6, 7, 10],
    optional_attributes: &[],
};

/// The two's complement of the 16-bit sum of the bytes.
fn checksum(bytes: &[u8]) -> i16 {
    let sum = bytes
        .iter()
        .fold(0u16, |s, b| s.wrapping_add(u16::from(*b)));
    0i16.wrapping_sub(sum as i16)
}

struct File<'c, 'a, D: Device, const C: usize>(&'c mut Ctx<'a, D, C>);

impl<D: Device, const C: usize> File<'_, '_, D, C> {
    fn bytes(&self, instance: u32) -> &[u8] {
        let Some(s) = self.0.csr.as_deref() else {
            return &[];
        };
        match u8::try_from(instance) {
            Ok(CSR_FILE_INSTANCE) => s.csr(),
            Ok(DEVICE_CERT_FILE) => s.certificate(1, false),
            Ok(CA_CERT_FILE) => s.certificate(1, true),
            _ => &[],
        }
    }

    fn state(&self, instance: u32) -> u8 {
        let up = self.0.state.security.upload;
        let size = if u32::from(up.file) == instance {
            up.size
        } else {
            0
        };
        match (self.bytes(instance).is_empty(), size, up.sent) {
            (true, _, _) => EMPTY,
            (false, 0, _) => LOADED,
            (false, _, 0) => UPLOAD_INITIATED,
            _ => UPLOAD_IN_PROGRESS,
        }
    }

    /// Initiate_Upload: the largest transfer the client takes (USINT); replies the file
    /// size (UDINT) and the transfer size (USINT). 0x0C with no CSR.
    fn initiate(&mut self, instance: u32, data: &[u8], w: &mut Writer<'_>) -> CipResult {
        let max = match *data {
            [m] => m,
            [] => return Err(General::NotEnoughData.into()),
            _ => return Err(General::TooMuchData.into()),
        };
        let len = self.bytes(instance).len();
        if len == 0 {
            return Err(General::ObjectStateConflict.into());
        }
        if max == 0 {
            return Err(General::InvalidParameter.into());
        }
        self.0.state.security.upload = Upload {
            file: instance as u8,
            size: max,
            sent: 0,
        };
        w.u32(len as u32)?;
        w.u8(max)?;
        Ok(())
    }

    /// Upload_Transfer: the transfer number (USINT, the next one, or the last again to
    /// resend it); replies the number, the packet type, the bytes and, with the last, the
    /// file checksum (INT). 0x0C without an upload initiated, 0x20 for another number.
    fn transfer(&mut self, instance: u32, data: &[u8], w: &mut Writer<'_>) -> CipResult {
        let number = match *data {
            [n] => n,
            [] => return Err(General::NotEnoughData.into()),
            _ => return Err(General::TooMuchData.into()),
        };
        let up = self.0.state.security.upload;
        if up.size == 0 || u32::from(up.file) != instance {
            return Err(General::ObjectStateConflict.into());
        }
        let index = if number == up.sent as u8 {
            up.sent
        } else if up.sent > 0 && number == up.sent.wrapping_sub(1) as u8 {
            up.sent.wrapping_sub(1)
        } else {
            return Err(General::InvalidParameter.into());
        };
        let bytes = self.bytes(instance);
        let size = usize::from(up.size);
        let start = (index as usize).saturating_mul(size);
        let Some(rest) = bytes.get(start..) else {
            return Err(General::InvalidParameter.into());
        };
        let chunk = rest.get(..size).unwrap_or(rest);
        let last = start.saturating_add(size) >= bytes.len();
        let kind = match (index == 0, last) {
            (true, true) => FIRST_AND_LAST,
            (true, false) => FIRST,
            (false, true) => LAST,
            (false, false) => MIDDLE,
        };
        w.u8(number)?;
        w.u8(kind)?;
        w.bytes(chunk)?;
        if last {
            w.i16(checksum(bytes))?;
        }
        let sent = index.saturating_add(1);
        self.0.state.security.upload = if last {
            Upload::default()
        } else {
            Upload { sent, ..up }
        };
        Ok(())
    }
}

impl<D: Device, const C: usize> Object for File<'_, '_, D, C> {
    fn class(&self) -> &ClassDef {
        &CLASS
    }
    fn has_instance(&self, instance: u32) -> bool {
        (u32::from(CSR_FILE_INSTANCE)..=u32::from(CA_CERT_FILE)).contains(&instance)
    }
    fn instance_count(&self) -> u32 {
        3
    }
    fn get(&mut self, instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        match attr.id {
            1 => w.u8(self.state(instance))?,
            6 => w.u32(self.bytes(instance).len() as u32)?,
            7 => w.i16(checksum(self.bytes(instance)))?,
            // 1: read only.
            _ => w.u8(1)?,
        }
        Ok(())
    }
    fn service(
        &mut self,
        instance: u32,
        req: &Request<'_>,
        w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        match (instance, req.service) {
            (0, _) => None,
            (_, INITIATE_UPLOAD) => Some(self.initiate(instance, req.data, w)),
            (_, UPLOAD_TRANSFER) => Some(self.transfer(instance, req.data, w)),
            _ => None,
        }
    }
}

/// Handles a request to the File class or its instances.
pub(crate) fn handle<D: Device, const C: usize>(
    ctx: &mut Ctx<'_, D, C>,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    serve(&mut File(ctx), req, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subjects_parse_with_an_optional_ninth_field_and_a_two_letter_country() {
        let mut req = [0u8; 64];
        let mut w = Writer::new(&mut req);
        for f in [&b"dev"[..], b"Plant", b"", b"", b"", b"DE", b"", b"42"] {
            short_string(&mut w, f);
        }
        let n = w.len();
        let s = subject(&req[..n]).unwrap();
        assert_eq!(
            (s.common_name, s.country, s.serial_number),
            (&b"dev"[..], &b"DE"[..], &b"42"[..])
        );
        assert!(subject(&req[..n - 1]).is_err());
        let mut longer = req;
        longer[n] = 1;
        longer[n + 1] = b'x';
        assert!(subject(&longer[..n + 2]).is_ok());
        assert!(subject(&longer[..n + 3]).is_err());
        // "D" as a country: 0x20.
        let bad = [3, b'd', b'e', b'v', 0, 0, 0, 0, 1, b'D', 0, 0];
        assert_eq!(subject(&bad).unwrap_err(), General::InvalidParameter.into());
    }

    fn short_string(w: &mut Writer<'_>, s: &[u8]) {
        crate::cip::encoding::short_string(w, s).unwrap();
    }

    #[test]
    fn the_checksum_makes_the_sum_zero() {
        let bytes = b"-----BEGIN CERTIFICATE REQUEST-----";
        let sum = bytes
            .iter()
            .fold(0u16, |s, b| s.wrapping_add(u16::from(*b)));
        assert_eq!(sum.wrapping_add(checksum(bytes) as u16), 0);
    }
}
