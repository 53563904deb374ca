//! The embedded boards' diagnostics object (vendor class 0x3A0, instance 1, served by
//! `enip_firmware::diagnostics`) read over TCP: the call stack's size, painted part and
//! high-water mark, which the rig reads from an emulated board before stopping it.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::time::Duration;

use enip_stack::config::MAX_ENCAP_FRAME;
use enip_stack::originator::{self, parse_reply};
use enip_stack::wire::encap::{EncapRepr, HEADER_LEN};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};

use crate::netns::Namespace;
use crate::rig::board_addr;

/// The diagnostics class.
pub const CLASS: u32 = 0x3A0;
/// Get_Attribute_Single.
const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;
/// How long each exchange may take.
const WAIT: Duration = Duration::from_secs(2);
/// The file `ENIP_STACK_MARKS` names collects one JSON line per reading.
pub const MARKS_ENV: &str = "ENIP_STACK_MARKS";

/// The stack as the board reports it, in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StackUse {
    /// The stack region.
    pub size: u32,
    /// Painted at boot (the deepest use the board can see).
    pub painted: u32,
    /// The high-water mark.
    pub deepest: u32,
}

/// Reads the board's stack figures over one new TCP session inside `ns`.
pub fn stack_use(ns: &Namespace) -> io::Result<StackUse> {
    ns.inside(|| -> io::Result<StackUse> {
        let mut s = TcpStream::connect_timeout(&board_addr(), WAIT)?;
        s.set_read_timeout(Some(WAIT))?;
        let mut frame = [0u8; 128];
        let n = originator::register_session(&mut frame).map_err(io::Error::other)?;
        let reply = exchange(&mut s, &frame[..n])?;
        let session = EncapRepr::parse_header(&reply)
            .map_err(io::Error::other)?
            .session_handle;
        let mut get = |attribute| read_u32(&mut s, session, attribute);
        Ok(StackUse {
            size: get(1)?,
            painted: get(2)?,
            deepest: get(3)?,
        })
    })?
}

/// Reads attribute `attribute` of instance 1 (a UDINT) in session `session`.
fn read_u32(s: &mut TcpStream, session: u32, attribute: u32) -> io::Result<u32> {
    let path = [
        SegmentRepr::Logical(LogicalType::Class, CLASS),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attribute),
    ];
    let mut frame = [0u8; 128];
    let n = originator::send_rr_data(&mut frame, session, None, |w| {
        originator::request(w, GET_ATTRIBUTE_SINGLE, &path, &[])
    })
    .map_err(io::Error::other)?;
    let reply = exchange(s, &frame[..n])?;
    let response = parse_reply(&reply)
        .map_err(io::Error::other)?
        .response
        .ok_or_else(|| io::Error::other("no Message Router response"))?;
    match (response.general_status, response.data) {
        (0, [a, b, c, d]) => Ok(u32::from_le_bytes([*a, *b, *c, *d])),
        (status, data) => Err(io::Error::other(format!(
            "attribute {attribute}: status {status:#04x}, data {data:02x?}"
        ))),
    }
}

/// Sends `frame` and returns the encapsulation reply.
fn exchange(s: &mut TcpStream, frame: &[u8]) -> io::Result<Vec<u8>> {
    s.write_all(frame)?;
    let mut reply = vec![0u8; HEADER_LEN];
    s.read_exact(&mut reply)?;
    let len = usize::from(u16::from_le_bytes([reply[2], reply[3]]));
    if HEADER_LEN + len > MAX_ENCAP_FRAME {
        return Err(io::Error::other(format!("reply of {len} bytes")));
    }
    reply.resize(HEADER_LEN + len, 0);
    s.read_exact(&mut reply[HEADER_LEN..])?;
    Ok(reply)
}

/// Reads the stack figures of the emulated board running `elf` inside `ns`, prints them, and
/// appends them as a JSON line to the file [`MARKS_ENV`] names (if set), with `test` (the
/// current thread's name: the test). A board that does not answer is only reported.
pub fn report_stack_use(ns: &Namespace, elf: &Path) {
    let test = std::thread::current().name().unwrap_or("?").to_string();
    match stack_use(ns) {
        Ok(u) => {
            println!(
                "stack high-water mark: {} of {} painted bytes (region {}), {test} on {}",
                u.deepest,
                u.painted,
                u.size,
                elf.display()
            );
            if let Some(path) = std::env::var_os(MARKS_ENV) {
                let line = serde_json::json!({
                    "test": test, "elf": elf, "size": u.size,
                    "painted": u.painted, "deepest": u.deepest,
                });
                let appended = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(&path)
                    .and_then(|mut f| writeln!(f, "{line}"));
                if let Err(e) = appended {
                    println!("stack high-water mark not recorded in {path:?}: {e}");
                }
            }
        }
        Err(e) => println!("stack high-water mark not read ({test}): {e}"),
    }
}
