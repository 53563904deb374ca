//! Shared test fixtures: a device with many assemblies and a scanner-side harness driving
//! one adapter through its public entry points in virtual time.
#![allow(dead_code)]

use std::net::{Ipv4Addr, SocketAddrV4};

use enip_stack::cip::{CipError, CipResult, General};
use enip_stack::config;
use enip_stack::device::Trigger;
use enip_stack::device::{
    AssemblyInfo, AssemblyRole, ConnectionEvent, Device, IdentityInfo, Multicast, OpenRequest,
};
use enip_stack::nv::{key, NvStore};
use enip_stack::originator::{self, Reply};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use enip_stack::wire::forward_open::{
    ForwardCloseRepr, ForwardOpenReplyRepr, ForwardOpenRepr, NetworkParams, Triad,
};
use enip_stack::wire::Writer;
use enip_stack::{Adapter, Instant, NetworkConfig, SocketId};

pub const IDENTITY: IdentityInfo = IdentityInfo {
    vendor_id: 1,
    device_type: 12,
    product_code: 65001,
    revision: (1, 2),
    serial_number: 0x1234_5678,
    product_name: "test device",
};

/// Inputs 100..=109, outputs 110..=119 (32 bytes each, outputs with run/idle), config 151,
/// heartbeats 152 (input only) and 153 (listen only), explicit 154.
pub struct TestDevice {
    pub assemblies: Vec<AssemblyInfo>,
    pub data: std::collections::HashMap<u16, Vec<u8>>,
    /// Ownership and run/idle events.
    pub events: Vec<ConnectionEvent>,
    /// Opened and closed events.
    pub lifecycle: Vec<ConnectionEvent>,
    pub writes: Vec<(u16, Vec<u8>)>,
    /// TCP/IP attributes 8/9 kept by the device (`None`: the stack keeps them).
    pub multicast: Option<Multicast>,
    /// Whether change-of-state connections are accepted.
    pub change_of_state: bool,
    /// The error an Identity Reset gets (`None`: accepted).
    pub reset_refusal: Option<CipError>,
    /// The device's own saved settings: this store's record [`key::PROFILE_BASE`], which an
    /// Identity Reset type 1 removes.
    pub settings: Option<Box<dyn NvStore>>,
}

impl TestDevice {
    pub fn new() -> Self {
        let mut assemblies = Vec::new();
        let mut data = std::collections::HashMap::new();
        for i in 0..10u16 {
            assemblies.push(AssemblyInfo {
                instance: 100 + i,
                role: AssemblyRole::Input,
                size: 32,
                run_idle_header: false,
            });
            assemblies.push(AssemblyInfo {
                instance: 110 + i,
                role: AssemblyRole::Output,
                size: 32,
                run_idle_header: true,
            });
            data.insert(100 + i, vec![i as u8; 32]);
            data.insert(110 + i, vec![0; 32]);
        }
        assemblies.push(AssemblyInfo {
            instance: 151,
            role: AssemblyRole::Config,
            size: 10,
            run_idle_header: false,
        });
        assemblies.push(AssemblyInfo {
            instance: 152,
            role: AssemblyRole::InputOnlyHeartbeat,
            size: 0,
            run_idle_header: false,
        });
        assemblies.push(AssemblyInfo {
            instance: 153,
            role: AssemblyRole::ListenOnlyHeartbeat,
            size: 0,
            run_idle_header: false,
        });
        assemblies.push(AssemblyInfo {
            instance: 154,
            role: AssemblyRole::Explicit,
            size: 32,
            run_idle_header: false,
        });
        data.insert(151, vec![0; 10]);
        data.insert(154, vec![0; 32]);
        TestDevice {
            assemblies,
            data,
            events: Vec::new(),
            lifecycle: Vec::new(),
            writes: Vec::new(),
            multicast: None,
            change_of_state: true,
            reset_refusal: None,
            settings: None,
        }
    }
}

impl Device for TestDevice {
    fn identity(&self) -> &IdentityInfo {
        &IDENTITY
    }
    /// Type 1 removes the device's settings, then the refusal (if any) is the answer.
    fn reset(&mut self, kind: u8) -> CipResult {
        if let Some(store) = self.settings.as_mut().filter(|_| kind == 1) {
            store
                .remove(key::PROFILE_BASE)
                .map_err(|_| General::StoreOperationFailure)?;
        }
        self.reset_refusal.map_or(Ok(()), Err)
    }
    fn assemblies(&self) -> &[AssemblyInfo] {
        &self.assemblies
    }
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
        let d = self.data.get(&instance).map(Vec::as_slice).unwrap_or(&[]);
        let n = d.len().min(out.len());
        out[..n].copy_from_slice(&d[..n]);
        Ok(n)
    }
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
        self.writes.push((instance, data.to_vec()));
        self.data.insert(instance, data.to_vec());
        Ok(())
    }
    fn connection_event(&mut self, event: ConnectionEvent) {
        match event {
            ConnectionEvent::Opened(_) | ConnectionEvent::Closed(..) => self.lifecycle.push(event),
            _ => self.events.push(event),
        }
    }
    fn multicast(&self) -> Option<Multicast> {
        self.multicast
    }
    fn set_multicast(&mut self, m: Multicast) -> CipResult {
        if m.config.num_mcast > 1 {
            return Err(enip_stack::cip::General::InvalidAttributeValue.into());
        }
        self.multicast = Some(m);
        Ok(())
    }
    fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        if request.trigger == Trigger::ChangeOfState && !self.change_of_state {
            return Err(CipError::connection(0x0103));
        }
        Ok(())
    }
}

/// True in the `large` test crate (`tests/large.rs`), which includes every suite again: the
/// same tests, with the adapter built at the large capacities below.
pub const LARGE: bool = same(env!("CARGO_CRATE_NAME").as_bytes(), b"large");
/// The adapter's TCP sessions: the default (3), or 16.
pub const SESSIONS: usize = if LARGE { 16 } else { config::MAX_SESSIONS };
/// The adapter's connection slots: the default (10), or 64.
pub const CONNECTIONS: usize = if LARGE { 64 } else { config::MAX_CONNECTIONS };
/// The adapter's largest encapsulation frame: the default (1 048), or the header plus a
/// 1 500-byte Ethernet payload (room for a 1 448-byte assembly read explicitly).
pub const FRAME: usize = if LARGE {
    enip_stack::wire::encap::HEADER_LEN + 1500
} else {
    config::MAX_ENCAP_FRAME
};
/// Delayed ListIdentity replies: the default (4), or 16.
pub const LIST_IDENTITY: usize = if LARGE {
    16
} else {
    config::MAX_PENDING_LIST_IDENTITY
};
/// The adapter the suites drive.
pub type TestAdapter<D> = Adapter<D, SESSIONS, CONNECTIONS, FRAME, LIST_IDENTITY>;

/// `a == b`, at compile time.
const fn same(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

pub const ADAPTER_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
pub const SCANNER_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);

/// One adapter and a scanner with a registered session on socket 0.
pub struct Harness<D: Device = TestDevice> {
    pub adapter: TestAdapter<D>,
    pub session: u32,
    pub now: Instant,
}

impl Harness {
    pub fn new() -> Self {
        Harness::with_device(TestDevice::new())
    }
}

impl<D: Device> Harness<D> {
    /// An adapter for `device` with a scanner's session on socket 0.
    pub fn with_device(device: D) -> Self {
        let net = NetworkConfig::new_static(
            ADAPTER_IP,
            Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 2],
        );
        let adapter = TestAdapter::with_capacities(device, net, 42);
        let mut h = Harness {
            adapter,
            session: 0,
            now: Instant(0),
        };
        h.session = h.open_session(0, 50000);
        h
    }

    /// Accepts a TCP connection from the scanner's `port` on `socket` and registers a
    /// session there; returns its handle.
    pub fn open_session(&mut self, socket: u8, port: u16) -> u32 {
        self.adapter.tcp_accept(
            SocketId(socket),
            SocketAddrV4::new(SCANNER_IP, port),
            self.now,
        );
        let mut buf = [0u8; 64];
        let n = originator::register_session(&mut buf).unwrap();
        let reply = self.tcp_on(socket, &buf[..n]);
        let handle = u32::from_le_bytes(reply[4..8].try_into().unwrap());
        assert_ne!(handle, 0);
        handle
    }

    /// Feeds `frame` on socket 0 and returns the reply bytes.
    pub fn tcp(&mut self, frame: &[u8]) -> Vec<u8> {
        self.tcp_on(0, frame)
    }

    /// Feeds `frame` on `socket` and returns the reply bytes.
    pub fn tcp_on(&mut self, socket: u8, frame: &[u8]) -> Vec<u8> {
        let mut reply = vec![0u8; FRAME];
        let out = self
            .adapter
            .tcp_receive(SocketId(socket), frame, self.now, &mut reply);
        assert_eq!(out.consumed, frame.len());
        reply.truncate(out.reply_len);
        reply
    }

    /// Sends a request through SendRRData and returns the raw reply frame.
    pub fn request(&mut self, service: u8, path: &[SegmentRepr<'_>], data: &[u8]) -> Vec<u8> {
        let mut buf = vec![0u8; FRAME];
        let session = self.session;
        let n = originator::send_rr_data(&mut buf, session, None, |w| {
            originator::request(w, service, path, data)
        })
        .unwrap();
        self.tcp(&buf[..n])
    }

    /// Sends a Forward_Open (or Large) and returns the raw reply frame.
    pub fn forward_open(&mut self, fo: &ForwardOpenRepr<'_>) -> Vec<u8> {
        let mut data = [0u8; 128];
        let mut w = Writer::new(&mut data);
        fo.emit(&mut w).unwrap();
        let n = w.len();
        let service = if fo.large { 0x5B } else { 0x54 };
        self.request(service, &cm_path(), &data[..n])
    }
}

/// Path to the Connection Manager instance 1.
pub fn cm_path() -> [SegmentRepr<'static>; 2] {
    [
        SegmentRepr::Logical(LogicalType::Class, 6),
        SegmentRepr::Logical(LogicalType::Instance, 1),
    ]
}

/// General status, additional status words and data of a reply frame.
pub fn status(frame: &[u8]) -> (u8, Vec<u16>, Vec<u8>) {
    let r: Reply<'_> = originator::parse_reply(frame).unwrap();
    let resp = r.response.expect("a message router response");
    let words = resp
        .additional_status
        .chunks(2)
        .map(|c| u16::from_le_bytes([c[0], c[1]]))
        .collect();
    (resp.general_status, words, resp.data.to_vec())
}

/// Connection path bytes: class 4, optional config instance, O->T and T->O points, data.
pub fn io_path(config: Option<u32>, o_t: u32, t_o: u32, config_data: Option<&[u8]>) -> Vec<u8> {
    let mut segs = vec![SegmentRepr::Logical(LogicalType::Class, 4)];
    if let Some(c) = config {
        segs.push(SegmentRepr::Logical(LogicalType::Instance, c));
    }
    segs.push(SegmentRepr::Logical(LogicalType::ConnectionPoint, o_t));
    segs.push(SegmentRepr::Logical(LogicalType::ConnectionPoint, t_o));
    if let Some(d) = config_data {
        segs.push(SegmentRepr::Data(d));
    }
    let mut buf = [0u8; 128];
    let mut w = Writer::new(&mut buf);
    for s in &segs {
        s.emit(&mut w).unwrap();
    }
    w.written().to_vec()
}

/// Opens a connection in every slot of the table at `rpi` µs, serials 1 to [`CONNECTIONS`]:
/// an exclusive owner of each output (110.., inputs 100..), then input-only connections
/// (heartbeat 152) to the inputs in turn. Returns their (O->T, T->O) connection IDs.
pub fn open_every_slot<D: Device>(h: &mut Harness<D>, rpi: u32) -> Vec<(u32, u32)> {
    (0..CONNECTIONS as u16)
        .map(|i| {
            let t_o = 100 + u32::from(i % 10);
            let o_t = if i < 10 { 110 + u32::from(i) } else { 152 };
            let path = io_path(None, o_t, t_o, None);
            let mut f = fo(i + 1, &path, rpi);
            if i >= 10 {
                f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
            }
            let (g, words, data) = status(&h.forward_open(&f));
            assert_eq!((g, words), (0, vec![]), "connection {i}");
            let r = ForwardOpenReplyRepr::parse(&data).unwrap();
            (r.o_t_connection_id, r.t_o_connection_id)
        })
        .collect()
}

/// A point-to-point exclusive-owner Forward_Open of 32-byte output `o_t` and input `t_o`.
pub fn fo<'a>(serial: u16, path: &'a [u8], rpi: u32) -> ForwardOpenRepr<'a> {
    ForwardOpenRepr {
        large: false,
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        o_t_connection_id: 0,
        t_o_connection_id: 0x7000_0000 + u32::from(serial),
        triad: Triad {
            connection_serial: serial,
            vendor_id: 0x1337,
            originator_serial: 0xC0FFEE,
        },
        timeout_multiplier: 0,
        o_t_rpi: rpi,
        o_t_params: NetworkParams::from_u16(0x4800 | (2 + 4 + 32)),
        t_o_rpi: rpi,
        t_o_params: NetworkParams::from_u16(0x4800 | (2 + 32)),
        transport: 0x01,
        path,
    }
}

/// Sends the Forward_Open `fo`; returns (general, additional words, data).
pub fn open<D: Device>(h: &mut Harness<D>, fo: &ForwardOpenRepr<'_>) -> (u8, Vec<u16>, Vec<u8>) {
    status(&h.forward_open(fo))
}

/// [`open`]'s general status and first additional word (the extended status).
pub fn ext_of<D: Device>(h: &mut Harness<D>, fo: &ForwardOpenRepr<'_>) -> (u8, Option<u16>) {
    let (g, words, _) = open(h, fo);
    (g, words.first().copied())
}

/// Closes the connection `fo(serial, ..)` opened; returns (general, additional words, data).
pub fn close<D: Device>(h: &mut Harness<D>, serial: u16) -> (u8, Vec<u16>, Vec<u8>) {
    let fc = ForwardCloseRepr {
        priority_tick: 0x0A,
        timeout_ticks: 0x0E,
        triad: fo(serial, &[], 1000).triad,
        path: &[],
    };
    let mut data = [0u8; 32];
    let mut w = Writer::new(&mut data);
    fc.emit(&mut w).unwrap();
    let n = w.len();
    status(&h.request(0x4E, &cm_path(), &data[..n]))
}
