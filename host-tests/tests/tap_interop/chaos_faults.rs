//! The faults the chaos soak injects, one call each, with the check each makes of its own
//! outcome: reconnect churn, a request of the hostile battery, a link flap, an Identity
//! Reset, a non-volatile write (TCP/IP host name, QoS DSCP), a burst of explicit requests,
//! a burst of extra Class 1 connections. Link flaps and Resets end the steady connections:
//! they replace them and return the window the I/O gap must fall in.

use std::io;
use std::net::TcpStream;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use crate::chaos_io::{Load, RPI};
use crate::common::{NAME, REPLY};
use crate::faults::{forward_open, session, triad};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::enip::{command, mr_request, path, rr_data, Client, Header};
use host_tests::netns::Namespace;
use host_tests::rig::{board_addr, TAP};
use host_tests::scanner::{Opened, Session, HEARTBEAT_O_T, INPUT_ONLY_PATH, OWNER_O_T, OWNER_PATH};

/// The steady connections: slot 0 the exclusive owner, the others input-only.
pub const STEADY: usize = 4;
/// Connections a Class 1 burst adds (slots after the steady ones).
const BURST: usize = 2;
/// Timeout multiplier code of every connection: x32.
const MULTIPLIER: u8 = 3;
/// Originator serial of this suite's connections.
const ORIGINATOR: u32 = 0xC4A0_5000;

/// The scheduler's own session (for the steady connections) and connection serials.
pub struct Control {
    session: Option<Session>,
    serial: u16,
}

/// What went wrong in a fault's own check.
pub type Outcome = Result<(), String>;

fn text(e: impl std::fmt::Display) -> String {
    e.to_string()
}

impl Control {
    /// A control without a session yet.
    pub fn new() -> Control {
        Control {
            session: None,
            serial: 0,
        }
    }

    /// The session, registered again if it was lost.
    pub fn session(&mut self) -> io::Result<&mut Session> {
        match &mut self.session {
            Some(s) => Ok(s),
            slot => Ok(slot.insert(session()?)),
        }
    }

    /// Runs `f` on the session; once more on a fresh one if the first failed on the wire.
    pub fn with<T>(&mut self, mut f: impl FnMut(&mut Session) -> io::Result<T>) -> io::Result<T> {
        if let Ok(v) = f(self.session()?) {
            return Ok(v);
        }
        self.session = None;
        f(self.session()?)
    }

    /// Opens one connection at [`RPI`] x32: the owner or an input-only one.
    pub fn open(&mut self, owner: bool) -> io::Result<Opened> {
        self.serial = self.serial.wrapping_add(1);
        let t = triad(self.serial, ORIGINATOR);
        let (path, size): (&[u8], u16) = if owner {
            (&OWNER_PATH, OWNER_O_T)
        } else {
            (&INPUT_ONLY_PATH, HEARTBEAT_O_T)
        };
        let fo = forward_open(t, path, size, MULTIPLIER, RPI.as_micros() as u32);
        let r = self
            .with(|s| s.forward_open(&fo))?
            .map_err(|e| io::Error::other(format!("Forward_Open refused: {e:?}")))?;
        Ok(Opened {
            o_t_id: r.o_t_connection_id,
            t_o_id: r.t_o_connection_id,
            triad: t,
            o_t_data: if owner { size - 6 } else { 0 },
        })
    }

    /// Closes `c`; its general status (0x01 with 0x0107 if the adapter had already ended it).
    pub fn close(&mut self, c: Opened) -> io::Result<u8> {
        self.with(|s| s.forward_close(c.triad)).map(|r| r.general)
    }

    /// Replaces every steady connection by a new one (closing the old, ended or not).
    pub fn reopen_steady(&mut self, load: &Load) -> io::Result<()> {
        for i in 0..STEADY {
            if let Some(old) = load.conn(i) {
                load.set(i, None, true);
                self.close(old)?;
            }
            let new = self.open(i == 0)?;
            load.set(i, Some(new), true);
        }
        Ok(())
    }

    /// Closes every connection of the load; the statuses that were not 0.
    pub fn close_all(&mut self, load: &Load) -> io::Result<Vec<u8>> {
        let n = load.slots.lock().unwrap_or_else(|e| e.into_inner()).len();
        let mut bad = Vec::new();
        for i in 0..n {
            if let Some(c) = load.conn(i) {
                load.set(i, None, false);
                let status = self.close(c)?;
                if status != 0 {
                    bad.push(status);
                }
            }
        }
        Ok(bad)
    }
}

/// `cycles` of connect / register / Forward_Open (input-only) / Forward_Close / close.
pub fn churn(ctl: &mut Control, cycles: u64) -> Outcome {
    for _ in 0..cycles {
        let mut s = session().map_err(text)?;
        ctl.serial = ctl.serial.wrapping_add(1);
        let t = triad(ctl.serial, ORIGINATOR + 1);
        let fo = forward_open(t, &INPUT_ONLY_PATH, HEARTBEAT_O_T, 0, 100_000);
        s.forward_open(&fo)
            .map_err(text)?
            .map_err(|e| format!("churn Forward_Open refused: {e:?}"))?;
        let r = s.forward_close(t).map_err(text)?;
        if r.general != 0 {
            return Err(format!("churn Forward_Close: {r:?}"));
        }
    }
    Ok(())
}

/// A registered raw client (retrying a connect refused while a socket listens again).
fn raw_client() -> io::Result<Client> {
    let mut tries = 0;
    let stream = loop {
        match TcpStream::connect_timeout(&board_addr(), REPLY) {
            Err(e) if e.kind() == io::ErrorKind::ConnectionRefused && tries < 100 => {
                tries += 1;
                std::thread::sleep(Duration::from_millis(10));
            }
            other => break other?,
        }
    };
    stream.set_nodelay(true)?;
    let mut c = Client::from_stream(stream);
    c.register(REPLY)?;
    Ok(c)
}

/// Hostile cases: (name, encapsulation command, data, expected encapsulation status, expected
/// Message Router general status if the reply carries one).
fn hostile_case(which: u64) -> (&'static str, u16, Vec<u8>, u32, Option<u8>) {
    let get = mr_request(0x0E, &path(1, 1, Some(1)), &[]);
    let cpf = |count: u16, len: u16| {
        let mut c = count.to_le_bytes().to_vec();
        c.extend_from_slice(&[0, 0, 0, 0, 0xB2, 0]);
        c.extend_from_slice(&len.to_le_bytes());
        c.extend_from_slice(&get);
        rr_data(&c)
    };
    let mr = |r: &[u8]| {
        let mut c = vec![2, 0, 0, 0, 0, 0, 0xB2, 0];
        c.extend_from_slice(&(r.len() as u16).to_le_bytes());
        c.extend_from_slice(r);
        rr_data(&c)
    };
    let forty: Vec<u8> = (0..40).flat_map(|_| [0x20, 0x01]).collect();
    let rr = command::SEND_RR_DATA;
    match which % 10 {
        0 => (
            "CPF count 200",
            rr,
            cpf(200, get.len() as u16),
            0x0003,
            None,
        ),
        1 => ("CPF item beyond data", rr, cpf(2, 50), 0x0003, None),
        2 => ("CPF prefix short", rr, vec![0, 0, 0], 0x0065, None),
        3 => ("unknown command", 0x00FF, vec![], 0x0001, None),
        4 => (
            "path size beyond request",
            rr,
            mr(&[0x0E, 10, 0x20, 0x01, 0x24, 0x01]),
            0,
            Some(0x26),
        ),
        5 => (
            "reserved logical format",
            rr,
            mr(&[0x0E, 3, 0x23, 1, 0x24, 1, 0x30, 1]),
            0,
            Some(0x04),
        ),
        6 => (
            "40 segments",
            rr,
            mr(&mr_request(0x0E, &forty, &[])),
            0,
            Some(0x04),
        ),
        7 => ("service byte only", rr, mr(&[0x0E]), 0, Some(0x13)),
        8 => (
            "unknown class",
            rr,
            mr(&mr_request(0x0E, &path(0x66, 1, Some(1)), &[])),
            0,
            Some(0x05),
        ),
        _ => ("length beyond capacity", rr, vec![0; 16], 0x0065, None),
    }
}

/// One request of the hostile battery on a fresh session: the exact status, then the same
/// session answers a valid request.
pub fn hostile(which: u64) -> Outcome {
    let (name, cmd, data, status, general) = hostile_case(which);
    let mut c = raw_client().map_err(text)?;
    let mut h = Header {
        session: c.session,
        ..Header::new(cmd)
    };
    let reply = if name == "length beyond capacity" {
        h.length = 0xF000;
        c.send(&h.bytes()).map_err(text)?;
        c.send(&data).map_err(text)?;
        let reply = c.recv(REPLY).map_err(text)?;
        // The rest of its data, skipped as it arrives.
        c.send(&vec![0; usize::from(h.length) - data.len()])
            .map_err(text)?;
        reply
    } else {
        c.exchange(h, &data, REPLY).map_err(text)?
    };
    let got_general = (reply.header.status == 0)
        .then(|| host_tests::enip::MrReply::from_rr_data(&reply.data).map(|r| r.general))
        .flatten();
    if reply.header.status != status || got_general != general {
        return Err(format!(
            "{name}: status {:#x} general {got_general:?}, expected {status:#x} {general:?}",
            reply.header.status
        ));
    }
    let r = c
        .request(&mr_request(0x0E, &path(1, 1, Some(7)), &[]), REPLY)
        .map_err(|e| format!("{name}: session after it: {e}"))?;
    if r.general != 0 || r.data.get(1..) != Some(NAME.as_bytes()) {
        return Err(format!("{name}: identity after it: {r:?}"));
    }
    Ok(())
}

/// The TCP/IP link down for `outage`, then up; returns (down, up) instants.
pub fn link_flap(ns: &Namespace, outage: Duration) -> Result<(Instant, Instant), String> {
    let down = Instant::now();
    ns.exec_checked("ip", &["link", "set", TAP, "down"])
        .map_err(text)?;
    std::thread::sleep(outage.saturating_sub(down.elapsed()));
    ns.exec_checked("ip", &["link", "set", TAP, "up"])
        .map_err(text)?;
    Ok((down, Instant::now()))
}

/// Identity Reset of type `kind` (0 or 1) on a fresh session: status 0.
pub fn identity_reset(kind: u8) -> Outcome {
    let mut s = session().map_err(text)?;
    let identity = [
        SegmentRepr::Logical(LogicalType::Class, 1),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    let r = s.request(0x05, &identity, &[kind]).map_err(text)?;
    if r.general != 0 {
        return Err(format!("Reset type {kind}: {r:?}"));
    }
    Ok(())
}

/// A value stored in the non-volatile store, set and read back on a fresh session: the
/// TCP/IP host name (attribute 6) or a QoS DSCP (attributes 4-8), chosen by `which`.
pub fn nv_write(which: u64) -> Outcome {
    let mut s = session().map_err(text)?;
    let (class, attr, value) = if which.is_multiple_of(2) {
        let name = format!("chaos-{:04x}", (which >> 8) as u16);
        let mut v = (name.len() as u16).to_le_bytes().to_vec();
        v.extend_from_slice(name.as_bytes());
        (0xF5, 6, v)
    } else {
        (0x48, 4 + (which >> 8) % 5, vec![((which >> 16) % 64) as u8])
    };
    let p = [
        SegmentRepr::Logical(LogicalType::Class, class),
        SegmentRepr::Logical(LogicalType::Instance, 1),
        SegmentRepr::Logical(LogicalType::Attribute, attr as u32),
    ];
    let r = s.request(0x10, &p, &value).map_err(text)?;
    if r.general != 0 {
        return Err(format!("set {class:#x}/1/{attr}: {r:?}"));
    }
    let back = s.request(0x0E, &p, &[]).map_err(text)?;
    if back.general != 0 || back.data.get(..value.len()) != Some(&value[..]) {
        return Err(format!(
            "{class:#x}/1/{attr} read back {back:?}, set {value:02x?}"
        ));
    }
    Ok(())
}

/// `n` back-to-back Identity reads on a fresh session, every one answered with status 0.
pub fn explicit_burst(n: u64) -> Outcome {
    let mut s = session().map_err(text)?;
    let p = [
        SegmentRepr::Logical(LogicalType::Class, 1),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ];
    for i in 0..n {
        let r = s.request(0x01, &p, &[]).map_err(text)?;
        if r.general != 0 {
            return Err(format!("read {i} of the burst: {r:?}"));
        }
    }
    Ok(())
}

/// [`BURST`] more input-only connections at [`RPI`] for `hold`, then closed: each still
/// open (status 0) at the close.
pub fn class1_burst(ctl: &mut Control, load: &Load, hold: Duration) -> Outcome {
    let mut opened = Vec::new();
    for k in 0..BURST {
        let c = ctl.open(false).map_err(text)?;
        load.set(STEADY + k, Some(c), false);
        opened.push(c);
    }
    let t_o_before = load.t_o.load(Ordering::Relaxed);
    std::thread::sleep(hold);
    let t_o = load.t_o.load(Ordering::Relaxed) - t_o_before;
    for (k, c) in opened.into_iter().enumerate() {
        load.set(STEADY + k, None, false);
        let status = ctl.close(c).map_err(text)?;
        if status != 0 {
            return Err(format!(
                "burst connection {k} ended before its close ({status:#x})"
            ));
        }
    }
    if t_o == 0 {
        return Err("no T->O during the burst".into());
    }
    Ok(())
}
