//! Builders for valid frames, requests and scripts: the seed corpus and its self-check.

use enip_stack::wire::cpf::item_type;
use enip_stack::wire::encap::command;
use enip_stack::wire::forward_open::{ForwardCloseRepr, ForwardOpenRepr, NetworkParams, Triad};
use enip_stack::wire::io_datagram::{self, IoDatagramRepr};
use enip_stack::wire::Writer;
use enip_stack::{AssemblyRole, Device};

use crate::script::{TCP_ACCEPT, TCP_CLOSE, TCP_DATA16, UDP_BROADCAST, UDP_TICK, UDP_UNICAST};
use crate::{io_script, script};

/// The sender context every seed uses (bytes 0-1: ListIdentity maximum delay, 250 ms).
pub const CONTEXT: [u8; 8] = [0xFA, 0x00, b'f', b'u', b'z', b'z', 0, 1];

/// An encapsulation frame: header with `cmd`, `session`, [`CONTEXT`], then `data`.
pub fn encap(cmd: u16, session: u32, data: &[u8]) -> Vec<u8> {
    let mut f = Vec::with_capacity(24 + data.len());
    f.extend_from_slice(&cmd.to_le_bytes());
    f.extend_from_slice(&(data.len() as u16).to_le_bytes());
    f.extend_from_slice(&session.to_le_bytes());
    f.extend_from_slice(&0u32.to_le_bytes());
    f.extend_from_slice(&CONTEXT);
    f.extend_from_slice(&0u32.to_le_bytes());
    f.extend_from_slice(data);
    f
}

/// RegisterSession data: protocol version 1, no options.
pub const REGISTER_DATA: [u8; 4] = [1, 0, 0, 0];

/// A RegisterSession frame.
pub fn register_session() -> Vec<u8> {
    encap(command::REGISTER_SESSION, 0, &REGISTER_DATA)
}

/// An UnRegisterSession frame.
pub fn unregister_session(session: u32) -> Vec<u8> {
    encap(command::UNREGISTER_SESSION, session, &[])
}

/// A ListIdentity request.
pub fn list_identity() -> Vec<u8> {
    encap(command::LIST_IDENTITY, 0, &[])
}

/// A ListServices request.
pub fn list_services() -> Vec<u8> {
    encap(command::LIST_SERVICES, 0, &[])
}

/// A CPF with a null address item and an unconnected data item carrying `request`.
pub fn unconnected_cpf(request: &[u8]) -> Vec<u8> {
    let mut c = Vec::new();
    c.extend_from_slice(&2u16.to_le_bytes());
    c.extend_from_slice(&item_type::NULL_ADDRESS.to_le_bytes());
    c.extend_from_slice(&0u16.to_le_bytes());
    c.extend_from_slice(&item_type::UNCONNECTED_DATA.to_le_bytes());
    c.extend_from_slice(&(request.len() as u16).to_le_bytes());
    c.extend_from_slice(request);
    c
}

/// A SendRRData frame on `session` carrying the Message Router request `request`.
pub fn send_rr_data(session: u32, request: &[u8]) -> Vec<u8> {
    let mut d = Vec::new();
    d.extend_from_slice(&0u32.to_le_bytes()); // interface handle
    d.extend_from_slice(&5u16.to_le_bytes()); // timeout
    d.extend_from_slice(&unconnected_cpf(request));
    encap(command::SEND_RR_DATA, session, &d)
}

/// A padded logical path class / instance (/ attribute), 8- or 16-bit as the values need.
pub fn path(class: u16, instance: u16, attribute: Option<u16>) -> Vec<u8> {
    let mut p = Vec::new();
    for (kind, v) in [(0u8, Some(class)), (1, Some(instance)), (4, attribute)] {
        match v {
            None => {}
            Some(v) if v <= 0xFF => p.extend_from_slice(&[0x20 | (kind << 2), v as u8]),
            Some(v) => {
                p.extend_from_slice(&[0x21 | (kind << 2), 0]);
                p.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    p
}

/// A Message Router request: service, path size in words, path, data.
pub fn request(service: u8, path: &[u8], data: &[u8]) -> Vec<u8> {
    let mut r = vec![service, (path.len() / 2) as u8];
    r.extend_from_slice(path);
    r.extend_from_slice(data);
    r
}

/// Get_Attribute_Single of class/instance/attribute.
pub fn get_attribute_single(class: u16, instance: u16, attribute: u16) -> Vec<u8> {
    request(0x0E, &path(class, instance, Some(attribute)), &[])
}

/// Multiple_Service_Packet to the Message Router carrying `requests`.
pub fn multiple_service_packet(requests: &[Vec<u8>]) -> Vec<u8> {
    let mut d = Vec::new();
    d.extend_from_slice(&(requests.len() as u16).to_le_bytes());
    let mut offset = 2 + 2 * requests.len();
    for r in requests {
        d.extend_from_slice(&(offset as u16).to_le_bytes());
        offset += r.len();
    }
    for r in requests {
        d.extend_from_slice(r);
    }
    request(0x0A, &path(0x02, 1, None), &d)
}

/// The route path "port 1, link 0" (the backplane slot of a single-module device).
pub const ROUTE_PORT1_LINK0: [u8; 2] = [0x01, 0x00];

/// Unconnected_Send to the Connection Manager wrapping `inner`, routed to port 1 link 0.
pub fn unconnected_send(inner: &[u8]) -> Vec<u8> {
    let mut d = vec![0x0A, 0xF0]; // priority/time tick, timeout ticks
    d.extend_from_slice(&(inner.len() as u16).to_le_bytes());
    d.extend_from_slice(inner);
    if inner.len() % 2 == 1 {
        d.push(0);
    }
    d.push((ROUTE_PORT1_LINK0.len() / 2) as u8);
    d.push(0);
    d.extend_from_slice(&ROUTE_PORT1_LINK0);
    request(0x52, &path(0x06, 1, None), &d)
}

/// Named Message Router requests every request-level seed set contains.
pub fn requests() -> Vec<(&'static str, Vec<u8>)> {
    let identity_name = get_attribute_single(0x01, 1, 7);
    vec![
        ("get_identity_name", identity_name.clone()),
        (
            "get_attributes_all_identity",
            request(0x01, &path(0x01, 1, None), &[]),
        ),
        ("get_assembly_100_data", get_attribute_single(0x04, 100, 3)),
        (
            "set_assembly_150_data",
            request(0x10, &path(0x04, 150, Some(3)), &[0x5A; 32]),
        ),
        (
            "get_attribute_list_tcpip",
            request(0x03, &path(0xF5, 1, None), &[3, 0, 1, 0, 3, 0, 5, 0]),
        ),
        (
            "multiple_service_packet",
            multiple_service_packet(&[
                get_attribute_single(0x01, 1, 1),
                get_attribute_single(0x01, 1, 7),
                get_attribute_single(0x04, 100, 3),
            ]),
        ),
        ("unconnected_send", unconnected_send(&identity_name)),
        (
            "symbolic_echo",
            request(0x4B, &[0x91, 5, b'P', b'4', b'0', b'1', b'2', 0], &[1, 2]),
        ),
        ("vendor_echo", request(0x4B, &path(0x64, 1, None), b"echo")),
        (
            "keyed_get_identity_name",
            request(0x0E, &[&KEY[..], &path(0x01, 1, Some(7))].concat(), &[]),
        ),
    ]
}

/// The fuzzing device's electronic key (vendor 0xFFFE, device type 0x0C, product 1),
/// compatible with revision 1.1.
pub const KEY: [u8; 10] = [0x34, 4, 0xFE, 0xFF, 0x0C, 0, 1, 0, 0x81, 1];

/// Builds a TCP script (see [`crate::script`]).
#[derive(Debug, Clone)]
pub struct TcpScript(pub Vec<u8>);

/// A script for the test device.
impl Default for TcpScript {
    fn default() -> Self {
        Self::for_device("test")
    }
}

impl TcpScript {
    /// An empty script for the device called `name` ("test" or a profile name).
    pub fn for_device(name: &str) -> Self {
        Self(vec![script::device_byte(name)])
    }
    /// Accepts a connection on `socket`.
    pub fn accept(mut self, socket: u8) -> Self {
        self.0.push(TCP_ACCEPT | socket);
        self
    }
    /// Closes `socket`.
    pub fn close(mut self, socket: u8) -> Self {
        self.0.push(TCP_CLOSE | socket);
        self
    }
    /// Delivers `data` on `socket` in one segment.
    pub fn data(mut self, socket: u8, data: &[u8]) -> Self {
        self.0.push(TCP_DATA16 | socket);
        self.0.extend_from_slice(&(data.len() as u16).to_le_bytes());
        self.0.extend_from_slice(data);
        self
    }
}

/// Builds a UDP script (see [`crate::script`]).
#[derive(Debug, Clone)]
pub struct UdpScript(pub Vec<u8>);

/// A script for the test device.
impl Default for UdpScript {
    fn default() -> Self {
        Self::for_device("test")
    }
}

impl UdpScript {
    /// An empty script for the device called `name` ("test" or a profile name).
    pub fn for_device(name: &str) -> Self {
        Self(vec![script::device_byte(name)])
    }
    fn datagram(mut self, kind: u8, data: &[u8]) -> Self {
        self.0.push(kind);
        if data.len() < 0xFF {
            self.0.push(data.len() as u8);
        } else {
            self.0.push(0xFF);
            self.0.extend_from_slice(&(data.len() as u16).to_le_bytes());
        }
        self.0.extend_from_slice(data);
        self
    }
    /// A datagram to the adapter's address.
    pub fn unicast(self, data: &[u8]) -> Self {
        self.datagram(UDP_UNICAST, data)
    }
    /// A datagram to 255.255.255.255.
    pub fn broadcast(self, data: &[u8]) -> Self {
        self.datagram(UDP_BROADCAST, data)
    }
    /// Lets `steps` x 700 ms pass.
    pub fn wait(mut self, steps: usize) -> Self {
        for _ in 0..steps {
            self.0.push(UDP_TICK | (7 << 2));
        }
        self
    }
}

/// The triad of the seed Class 1 connection.
pub const TRIAD: Triad = Triad {
    connection_serial: 0x0101,
    vendor_id: 0xFFFE,
    originator_serial: 0x1234_5678,
};

/// Connection path of an exclusive owner: configuration 151, output 150, input 100.
pub const CONNECTION_PATH: [u8; 8] = [0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100];

/// The exclusive-owner connection a seed opens to a device: its connection path and data
/// sizes (from the device's first configuration, output and input assemblies).
#[derive(Debug, Clone)]
pub struct Connection {
    /// Configuration point (if the device has one), output point, input point.
    pub path: Vec<u8>,
    /// O->T output data bytes.
    pub output: usize,
    /// Whether O->T data carries the 32-bit run/idle header.
    pub run_idle: bool,
    /// T->O input data bytes.
    pub input: usize,
}

impl Connection {
    /// The test device's connection (configuration 151, output 150, input 100).
    pub fn test_device() -> Self {
        Connection {
            path: CONNECTION_PATH.to_vec(),
            output: 32,
            run_idle: true,
            input: 32,
        }
    }

    /// The exclusive-owner connection to `device`'s first configuration, output and input
    /// assemblies.
    pub fn of(device: &impl Device) -> Self {
        let find = |role: AssemblyRole| device.assemblies().iter().find(|a| a.role == role);
        let output = find(AssemblyRole::Output).expect("an output assembly");
        let input = find(AssemblyRole::Input).expect("an input assembly");
        let mut path = Vec::new();
        let mut segment = |kind: u8, v: u16| {
            if v <= 0xFF {
                path.extend_from_slice(&[kind, v as u8]);
            } else {
                path.extend_from_slice(&[kind | 1, 0]);
                path.extend_from_slice(&v.to_le_bytes());
            }
        };
        segment(0x20, 0x04);
        if let Some(c) = find(AssemblyRole::Config) {
            segment(0x24, c.instance);
        }
        segment(0x2C, output.instance);
        segment(0x2C, input.instance);
        Connection {
            path,
            output: usize::from(output.size),
            run_idle: output.run_idle_header,
            input: usize::from(input.size),
        }
    }

    /// Forward_Open (exclusive owner, cyclic, 10 ms both ways, point-to-point) as a Message
    /// Router request to the Connection Manager.
    pub fn forward_open(&self) -> Vec<u8> {
        let o_t = 2 + 4 * usize::from(self.run_idle) + self.output;
        let fo = ForwardOpenRepr {
            large: false,
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            o_t_connection_id: 0,
            t_o_connection_id: 0x2000_0001,
            triad: TRIAD,
            timeout_multiplier: 1,
            o_t_rpi: 10_000,
            // Point-to-point, scheduled, fixed, with the sequence count (and run/idle).
            o_t_params: NetworkParams::from_u16(0x4800 | o_t as u16),
            t_o_rpi: 10_000,
            t_o_params: NetworkParams::from_u16(0x4800 | (2 + self.input) as u16),
            transport: 0x01,
            path: &self.path,
        };
        let mut data = [0u8; 64];
        let mut w = Writer::new(&mut data);
        fo.emit(&mut w).expect("fits");
        let n = w.len();
        request(0x54, &path(0x06, 1, None), &data[..n])
    }

    /// Forward_Close of the connection.
    pub fn forward_close(&self) -> Vec<u8> {
        let fc = ForwardCloseRepr {
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            triad: TRIAD,
            path: &self.path,
        };
        let mut data = [0u8; 32];
        let mut w = Writer::new(&mut data);
        fc.emit(&mut w).expect("fits");
        let n = w.len();
        request(0x4E, &path(0x06, 1, None), &data[..n])
    }

    /// An O->T datagram for connection `id`: sequence, run header, `fill` as output data.
    pub fn o_t_datagram(&self, id: u32, sequence: u16, fill: &[u8]) -> Vec<u8> {
        let header = 2 + 4 * usize::from(self.run_idle);
        let connected = header + self.output;
        let mut d = vec![0u8; io_datagram::HEADER_LEN + connected];
        let mut w = Writer::new(&mut d);
        IoDatagramRepr {
            connection_id: id,
            encap_sequence: u32::from(sequence),
            connected_len: u16::try_from(connected).expect("fits"),
            sequence,
        }
        .emit(&mut w)
        .expect("fits");
        if self.run_idle {
            w.u32(1).expect("fits");
        }
        let at = w.len();
        for (b, f) in d[at..].iter_mut().zip(fill.iter().cycle()) {
            *b = *f;
        }
        d
    }
}

/// Forward_Open of the test device's seed connection.
pub fn forward_open() -> Vec<u8> {
    Connection::test_device().forward_open()
}

/// Forward_Close of the test device's seed connection.
pub fn forward_close() -> Vec<u8> {
    Connection::test_device().forward_close()
}

/// An O->T datagram to the test device for connection `id`: sequence, run header, 32 bytes
/// of output data.
pub fn o_t_datagram(id: u32, sequence: u16) -> Vec<u8> {
    Connection::test_device().o_t_datagram(id, sequence, &[sequence as u8])
}

/// Builds an I/O script (see [`crate::io_script`]).
#[derive(Debug, Clone)]
pub struct IoScript(pub Vec<u8>);

/// A script for the test device.
impl Default for IoScript {
    fn default() -> Self {
        Self::for_device("test")
    }
}

impl IoScript {
    /// An empty script for the device called `name` ("test" or a profile name).
    pub fn for_device(name: &str) -> Self {
        Self(vec![script::device_byte(name)])
    }
    fn op(mut self, kind: u8, arg: u8) -> Self {
        self.0.push(kind | (arg << 3));
        self
    }
    fn with_u16(mut self, data: &[u8]) -> Self {
        self.0.extend_from_slice(&(data.len() as u16).to_le_bytes());
        self.0.extend_from_slice(data);
        self
    }
    /// Accepts a connection on `socket`.
    pub fn accept(self, socket: u8) -> Self {
        self.op(io_script::ACCEPT, socket)
    }
    /// Closes `socket`.
    pub fn close(self, socket: u8) -> Self {
        self.op(io_script::CLOSE, socket)
    }
    /// TCP data on `socket`.
    pub fn tcp(self, socket: u8, data: &[u8]) -> Self {
        self.op(io_script::TCP_DATA, socket).with_u16(data)
    }
    /// A Class 1 datagram from sender 0 (the scanner, port 2222).
    pub fn io(self, data: &[u8]) -> Self {
        self.op(io_script::IO_DATA, 0).with_u16(data)
    }
    /// `ms` (1..=32) milliseconds pass.
    pub fn wait_ms(self, ms: u8) -> Self {
        self.op(io_script::WAIT_MS, ms.clamp(1, 32) - 1)
    }
    /// The device's first assembly (the test device's input 100) has new data.
    pub fn trigger(self) -> Self {
        self.op(io_script::TRIGGER, 0)
    }
}
