//! The script the per-profile targets (`profile_<name>`) read: explicit requests run
//! unconnected through `Adapter::execute` (the profile's vendor classes, symbolic paths,
//! text/float conversion, configuration validation), Class 1 data and configuration through
//! `Device::write_assembly`, and the device's own time, with one shipped profile as the
//! device, its saved settings in an erased non-volatile store ([`crate::store`]). Also the
//! seeds: requests from each profile's manual (the byte strings of its unit tests).
//!
//! Op byte: bits 0-1 kind, bits 2-7 argument `a`:
//! 0 a request (`u16` length, then the bytes) answered into a 512-byte buffer, or a 40-byte
//! one if `a` is odd; 1 `write_assembly` of the device's assembly `a` (modulo the number of
//! assemblies, in `Device::assemblies` order; `u16` length, then the bytes); 2 time passes
//! `a + 1` ms x 10 and `Adapter::poll_device` runs; 3 every assembly is read.
//!
//! Invariants: nothing panics; every reply is a well-formed Message Router reply (service
//! with bit 7 set, reserved byte 0, the additional status inside the reply); a refused
//! Set_Attribute_Single leaves the attribute reading as before; where the profile promises
//! more, a refused Parker request to its classes or tags writes nothing at all and a refused
//! Ametek configuration Set changes no configuration attribute; an accepted Set of a
//! converting attribute (PositionServo System940, AKD parameter values) is a fixed point:
//! what it reads back, written again, is accepted and reads the same; a refused
//! `write_assembly` leaves the whole device as it was; reads fit their buffer. An Identity
//! Reset the stack accepted is performed as a runtime does (connections closed,
//! `Device::reset`).

use enip_profiles::Profile;
use enip_stack::cip::Request;
use enip_stack::device::CloseReason;
use enip_stack::{Adapter, Device, Duration, Instant};

use crate::frames::{path, request};
use crate::script::{adapter, Cursor};

/// Kind: an explicit request through `Adapter::execute`.
pub const REQUEST: u8 = 0;
/// Kind: `Device::write_assembly`.
pub const WRITE: u8 = 1;
/// Kind: time passes and the device runs.
pub const TIME: u8 = 2;
/// Kind: every assembly is read.
pub const READ: u8 = 3;

/// Reply buffer of a request.
pub const REPLY: usize = 512;
/// The small reply buffer (odd argument).
pub const SMALL_REPLY: usize = 40;

/// What a script saw, for the seed self-check: (request, general status) of every request.
pub type Statuses = Vec<(Vec<u8>, u8)>;

/// Plays a profile script against the profile called `name`. Panics on a broken invariant.
pub fn run(name: &str, script: &[u8]) -> Statuses {
    let mut device = Profile::from_name(name).expect("a compiled-in profile");
    device.attach_store(crate::store::erased());
    let mut adapter = adapter(device);
    let mut statuses = Vec::new();
    let mut now = Instant::from_micros(1_000_000);
    let _ = adapter.poll_device(now);
    let mut c = Cursor(script);
    while let Some(op) = c.u8() {
        let a = op >> 2;
        match op & 0x03 {
            REQUEST => {
                let n = c.u16().unwrap_or(0);
                let req = c.take(usize::from(n));
                let limit = if a & 1 == 1 { SMALL_REPLY } else { REPLY };
                let status = execute(&mut adapter, req, now, limit);
                statuses.push((req.to_vec(), status));
            }
            WRITE => {
                let n = c.u16().unwrap_or(0);
                let data = c.take(usize::from(n));
                let infos = adapter.device().assemblies();
                let instance = infos[usize::from(a) % infos.len()].instance;
                let before = adapter.device().clone();
                if adapter.device_mut().write_assembly(instance, data).is_err() {
                    assert!(
                        *adapter.device() == before,
                        "a refused write of assembly {instance} changed the device"
                    );
                }
            }
            TIME => {
                now = now.add(Duration::from_millis(10 * (u64::from(a) + 1)));
                let _ = adapter.poll_device(now);
            }
            _ => {
                let mut out = [0u8; REPLY];
                let instances: Vec<u16> = adapter
                    .device()
                    .assemblies()
                    .iter()
                    .map(|i| i.instance)
                    .collect();
                for instance in instances {
                    if let Ok(n) = adapter.device_mut().read_assembly(instance, &mut out) {
                        assert!(n <= out.len(), "read of {instance} longer than its buffer");
                    }
                }
            }
        }
    }
    statuses
}

/// Runs `req` unconnected into a `limit`-byte buffer, checks the reply and the refused-Set
/// rule, performs an accepted Reset; returns the general status.
fn execute(adapter: &mut Adapter<Profile>, req: &[u8], now: Instant, limit: usize) -> u8 {
    let mut reply = [0u8; REPLY];
    // A Set's target as read before it: the same path with Get_Attribute_Single.
    let get = match Request::parse(req) {
        Ok(r) if r.service == 0x10 && r.path.symbol.is_none() => {
            let mut g = vec![0x0E, req[1]];
            g.extend_from_slice(r.raw_path);
            Some(g)
        }
        _ => None,
    };
    let before = get.as_ref().and_then(|g| read(adapter, g, now));
    let promise = Promise::of(adapter.device().name(), req);
    let snapshot = promise.snapshot(adapter, now);
    let len = adapter.execute(req, now, &mut reply[..limit]);
    let status = check_reply(req, &reply[..len], limit);
    if status != 0 {
        // First, before the Get below counts as a request.
        promise.check(snapshot, adapter, now, status);
        if let (Some(g), Some(before)) = (&get, &before) {
            assert_eq!(
                read(adapter, g, now).as_ref(),
                Some(before),
                "a refused Set (status {status:#04x}) changed what Get reads"
            );
        }
    }
    if status == 0 {
        if let (Some(g), Ok(r)) = (&get, Request::parse(req)) {
            if round_trips(adapter.device().name(), &r) {
                check_round_trip(adapter, g, now);
            }
        }
    }
    if let Some(kind) = adapter.take_reset() {
        adapter.close_all(CloseReason::Reset);
        let _ = adapter.device_mut().reset(kind);
    }
    status
}

/// What a profile promises of a refused request beyond its target attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Promise {
    /// Nothing more.
    None,
    /// Parker IPA, class 0x64/0x65 and tags: "a refused request writes nothing" (the whole
    /// device as before, but for the Class 3 message counter every request to them counts).
    ParkerNothingWritten,
    /// Ametek PLS, a Set of class 0xC1: "validated whole; a broken rule leaves everything as
    /// it was" (every configuration attribute; the error latched in the inputs is the point).
    AmetekConfigurationUnchanged,
}

/// What a snapshot holds: the device, or the Ametek configuration attributes.
enum Snapshot {
    None,
    Device(Box<Profile>),
    Attributes(Vec<Option<Vec<u8>>>),
}

/// Parker: a read every request to its classes could be, to count it like the refused one.
const PARKER_REFERENCE_READ: [u8; 12] = [
    0x53, 0x03, 0x20, 0x64, 0x25, 0x00, 0x00, 0x10, 0x01, 0x00, 0x00, 0x00,
];

impl Promise {
    fn of(profile: &str, req: &[u8]) -> Self {
        let Ok(r) = Request::parse(req) else {
            return Promise::None;
        };
        match (profile, r.path.class) {
            ("parker-ipa", Some(0x64 | 0x65) | None) => Promise::ParkerNothingWritten,
            ("ametek-pls", Some(0xC1)) if r.service == 0x10 => {
                Promise::AmetekConfigurationUnchanged
            }
            _ => Promise::None,
        }
    }

    fn snapshot(self, adapter: &mut Adapter<Profile>, now: Instant) -> Snapshot {
        match self {
            Promise::None => Snapshot::None,
            Promise::ParkerNothingWritten => Snapshot::Device(Box::new(adapter.device().clone())),
            Promise::AmetekConfigurationUnchanged => Snapshot::Attributes(
                (1..=38)
                    .map(|a| read(adapter, &req(0x0E, 0xC1, 1, Some(a), &[]), now))
                    .collect(),
            ),
        }
    }

    fn check(self, snapshot: Snapshot, adapter: &mut Adapter<Profile>, now: Instant, status: u8) {
        match snapshot {
            Snapshot::None => {}
            Snapshot::Device(mut before) => {
                // Which inputs changed is the stack's bookkeeping (it drains the marks after
                // each request), not something the request wrote.
                let mut after = adapter.device().clone();
                for d in [&mut *before, &mut after] {
                    if let Some(c) = d.input_changes() {
                        c.clear();
                    }
                }
                // Refused by the stack (never reached the device), or by the device (counted).
                if *before == after {
                    return;
                }
                let mut shadow = crate::script::adapter(*before);
                let mut reply = [0u8; REPLY];
                let len = shadow.execute(&PARKER_REFERENCE_READ, now, &mut reply);
                assert_eq!(
                    check_reply(&PARKER_REFERENCE_READ, &reply[..len], REPLY),
                    0,
                    "the reference read failed"
                );
                let mut counted = shadow.into_device();
                if let Some(c) = counted.input_changes() {
                    c.clear();
                }
                assert!(
                    counted == after,
                    "a refused request (status {status:#04x}) wrote something"
                );
            }
            Snapshot::Attributes(before) => {
                let after: Vec<_> = (1..=38)
                    .map(|a| read(adapter, &req(0x0E, 0xC1, 1, Some(a), &[]), now))
                    .collect();
                assert_eq!(
                    after, before,
                    "a refused Set of 0xC1 (status {status:#04x}) changed the configuration"
                );
            }
        }
    }
}

/// Whether a Set the profile accepted must be a fixed point of its conversion: the value
/// read back, written again, is accepted and reads back the same. PositionServo System940
/// (class 0x64: integer, REAL and text forms of one variable) and the AKD parameter values
/// (class 0x0F attribute 1).
fn round_trips(profile: &str, r: &Request<'_>) -> bool {
    matches!(
        (profile, r.path.class, r.path.attribute),
        ("position-servo", Some(0x64), Some(_)) | ("kollmorgen-akd", Some(0x0F), Some(1))
    )
}

/// Reads the attribute with Get request `get`, writes what it read back with
/// Set_Attribute_Single, and checks that is accepted and reads the same.
fn check_round_trip(adapter: &mut Adapter<Profile>, get: &[u8], now: Instant) {
    let Some(first) = read(adapter, get, now) else {
        return;
    };
    let mut set = vec![0x10];
    set.extend_from_slice(&get[1..]);
    set.extend_from_slice(&first);
    let mut reply = [0u8; REPLY];
    let len = adapter.execute(&set, now, &mut reply);
    let status = check_reply(&set, &reply[..len], REPLY);
    assert_eq!(
        status, 0,
        "writing back what {get:02x?} read ({first:02x?}) was refused"
    );
    let again = read(adapter, get, now);
    assert_eq!(
        again.as_deref(),
        Some(&first[..]),
        "writing back what {get:02x?} read changed it"
    );
}

/// The reply data of a successful request, or `None`.
fn read(adapter: &mut Adapter<Profile>, req: &[u8], now: Instant) -> Option<Vec<u8>> {
    let mut reply = [0u8; REPLY];
    let len = adapter.execute(req, now, &mut reply);
    let r = &reply[..len];
    (check_reply(req, r, REPLY) == 0).then(|| r[4 + 2 * usize::from(r[3])..].to_vec())
}

/// Asserts `reply` is a well-formed Message Router reply to `req`; returns its general status.
pub fn check_reply(req: &[u8], reply: &[u8], limit: usize) -> u8 {
    assert!(reply.len() <= limit, "reply longer than its buffer");
    assert!(
        reply.len() >= 4,
        "reply shorter than a header: {reply:02x?}"
    );
    let service = req.first().copied().unwrap_or(0);
    assert_eq!(reply[0], service | 0x80, "reply service of {req:02x?}");
    assert_eq!(reply[1], 0, "reserved byte");
    assert!(
        4 + 2 * usize::from(reply[3]) <= reply.len(),
        "additional status beyond the reply: {reply:02x?}"
    );
    reply[2]
}

/// Builds a profile script.
#[derive(Debug, Default, Clone)]
pub struct ProfileScript(pub Vec<u8>);

impl ProfileScript {
    fn with_u16(mut self, op: u8, data: &[u8]) -> Self {
        self.0.push(op);
        self.0.extend_from_slice(&(data.len() as u16).to_le_bytes());
        self.0.extend_from_slice(data);
        self
    }
    /// An explicit request.
    pub fn request(self, req: &[u8]) -> Self {
        self.with_u16(REQUEST, req)
    }
    /// `write_assembly` of the device's assembly `index`.
    pub fn write(self, index: u8, data: &[u8]) -> Self {
        self.with_u16(WRITE | (index << 2), data)
    }
    /// `ms` (10..=640) milliseconds pass.
    pub fn wait(mut self, ms: u16) -> Self {
        self.0.push(TIME | ((ms / 10).clamp(1, 64) as u8 - 1) << 2);
        self
    }
    /// Every assembly is read.
    pub fn read(mut self) -> Self {
        self.0.push(READ);
        self
    }
    /// The script's requests, in order.
    pub fn requests(&self) -> Vec<Vec<u8>> {
        let mut out = Vec::new();
        let mut c = Cursor(&self.0);
        while let Some(op) = c.u8() {
            if matches!(op & 0x03, REQUEST | WRITE) {
                let n = c.u16().unwrap_or(0);
                let data = c.take(usize::from(n));
                if op & 0x03 == REQUEST {
                    out.push(data.to_vec());
                }
            }
        }
        out
    }
}

/// A request to `class`/`instance`(/`attribute`) with `data`.
fn req(service: u8, class: u16, instance: u16, attribute: Option<u16>, data: &[u8]) -> Vec<u8> {
    request(service, &path(class, instance, attribute), data)
}

/// A request on the symbolic path `name`.
fn tag(service: u8, name: &str, data: &[u8]) -> Vec<u8> {
    let mut p = vec![0x91, name.len() as u8];
    p.extend_from_slice(name.as_bytes());
    if p.len() % 2 == 1 {
        p.push(0);
    }
    request(service, &p, data)
}

fn le<T: Copy, const N: usize>(values: &[T], f: impl Fn(T) -> [u8; N]) -> Vec<u8> {
    values.iter().flat_map(|&v| f(v)).collect()
}

/// PositionServo text: 4-byte length, ASCII.
fn text(s: &str) -> Vec<u8> {
    let mut v = (s.len() as u32).to_le_bytes().to_vec();
    v.extend_from_slice(s.as_bytes());
    v
}

/// Named seed scripts for the profile called `name`: its manual's examples, each request
/// answered with success (the seed self-check).
pub fn seeds(name: &str) -> Vec<(&'static str, ProfileScript)> {
    let s = ProfileScript::default;
    match name {
        // PM94H201 6.3 and 7.2: System940 class 0x64, instance = variable, attributes
        // 0/1 integer, 2/3 REAL, 4/5 text (RAM / RAM and EPM).
        "position-servo" => vec![
            (
                "example_6_3_real_integer_text",
                s().request(&req(0x10, 0x64, 100, Some(2), &42.75f32.to_le_bytes()))
                    .request(&req(0x0E, 0x64, 100, Some(0), &[]))
                    .request(&req(0x0E, 0x64, 100, Some(4), &[]))
                    .request(&req(0x10, 0x64, 101, Some(0), &(-7i32).to_le_bytes()))
                    .request(&req(0x10, 0x64, 102, Some(4), &text("3.25")))
                    .request(&req(0x10, 0x64, 261, Some(4), &text("0xC00000BC")))
                    .request(&req(0x01, 0x64, 100, None, &[])),
            ),
            (
                "epm_copy_and_reset",
                s().request(&req(0x10, 0x64, 100, Some(3), &500.0f32.to_le_bytes()))
                    .request(&req(0x10, 0x64, 100, Some(1), &9u32.to_le_bytes()))
                    .request(&req(0x10, 0x64, 100, Some(5), &text("-12.5")))
                    .request(&req(0x05, 0x01, 1, None, &[0]))
                    .request(&req(0x0E, 0x64, 100, Some(4), &[])),
            ),
            (
                "assemblies_and_time",
                s().request(&req(0x0E, 0x04, 105, Some(3), &[]))
                    .write(3, &[0; 8])
                    .wait(100)
                    .read()
                    .request(&req(0x03, 0x64, 100, None, &[3, 0, 0, 0, 2, 0, 4, 0])),
            ),
        ],
        // 88-032525-01: class 0x64 services 0x50-0x54 (figures 4-9), class 0x65 0x53
        // (figure 10), tag services on "P4112" (figures 1-2) and "P39202".
        "parker-ipa" => vec![
            (
                "figures_4_5_jog_write_read",
                s().request(&[
                    0x50, 0x04, 0x20, 0x64, 0x25, 0x00, 0x3C, 0x30, 0x30, 0x01, 0x00, 0x00, 0x70,
                    0x41, 0x00, 0x00, 0x16, 0x43, 0x00, 0x00, 0xFA, 0x42, 0x00, 0x40, 0x1C, 0x44,
                ])
                .request(&req(0x51, 0x64, 12348, Some(1), &4i32.to_le_bytes()))
                .wait(50)
                .read(),
            ),
            (
                "figures_6_9_flags_and_or",
                s().request(&[
                    0x53, 0x04, 0x20, 0x64, 0x25, 0x00, 0x08, 0x11, 0x30, 0x01, 0x03, 0, 0, 0,
                ])
                .request(&req(
                    0x52,
                    0x64,
                    4111,
                    Some(1),
                    &0x1234_5678i32.to_le_bytes(),
                ))
                .request(&[
                    0x54, 0x04, 0x20, 0x64, 0x25, 0x00, 0x0F, 0x10, 0x30, 0x01, 0x00, 0xFF, 0xFF,
                    0xFF, 0x55, 0x00, 0x00, 0x00,
                ]),
            ),
            (
                "figure_10_read_group",
                s().request(&req(0x50, 0x64, 12304, Some(1), &10.5f32.to_le_bytes()))
                    .request(&[
                        0x53, 0x04, 0x20, 0x65, 0x25, 0x00, 0x10, 0x30, 0x30, 0x01, 0x04, 0, 0, 0,
                    ])
                    .request(&req(0x53, 0x65, 0x3002, Some(1), &8i32.to_le_bytes())),
            ),
            (
                "figures_1_2_tags",
                s().request(&req(
                    0x52,
                    0x64,
                    4112,
                    Some(1),
                    &le(&[7i32, -8, 9], i32::to_le_bytes),
                ))
                .request(&[
                    0x4C, 0x04, 0x91, 0x05, 0x50, 0x34, 0x31, 0x31, 0x32, 0x00, 0x03, 0x00,
                ])
                .request(&{
                    let mut w = vec![
                        0x4D, 0x04, 0x91, 0x05, 0x50, 0x34, 0x31, 0x30, 0x30, 0x00, 0xC4, 0, 1, 0,
                    ];
                    w.extend_from_slice(&0x0BAD_CAFEi32.to_le_bytes());
                    w
                })
                .request(&tag(0x4D, "P39001", &{
                    let mut w = vec![0xCA, 0, 1, 0];
                    w.extend_from_slice(&77.0f32.to_le_bytes());
                    w
                }))
                .request(&tag(0x48, "P39200", &[4, 0]))
                .request(&tag(
                    0x4E,
                    "P4101",
                    &le(&[0xFFFF_00FFu32, 0x55], u32::to_le_bytes),
                ))
                .request(&tag(0x4C, "p4360", &[3, 0])),
            ),
            (
                "output_assembly",
                s().write(1, &[0x11; 64]).wait(20).read().request(&req(
                    0x0E,
                    0x01,
                    1,
                    Some(7),
                    &[],
                )),
            ),
        ],
        // 7500.MOR: class 0xC0 status (Get), 0xC1 configuration (Get/Set, validated whole),
        // output assembly 150 (7 words).
        "ametek-pls" => vec![
            (
                "status_and_configuration_reads",
                s().request(&req(0x0E, 0xC0, 1, Some(1), &[]))
                    .request(&req(0x0E, 0xC0, 1, Some(2), &[]))
                    .request(&req(0x0E, 0xC1, 1, Some(1), &[]))
                    .request(&req(0x0E, 0xC1, 1, Some(2), &[]))
                    .request(&req(0x0E, 0xC1, 1, Some(18), &[]))
                    .request(&req(0x0E, 0xC1, 1, Some(34), &[])),
            ),
            (
                "pls_object_example",
                s().request(&req(
                    0x10,
                    0xC1,
                    1,
                    Some(1),
                    &le(&ametek_pls_object(), u16::to_le_bytes),
                ))
                .request(&req(0x0E, 0xC1, 1, Some(1), &[])),
            ),
            (
                "run_enable_output",
                s().request(&req(
                    0x10,
                    0x04,
                    150,
                    Some(3),
                    &le(&[1u16, 0, 0, 0, 0, 0, 0], u16::to_le_bytes),
                ))
                .write(2, &le(&[1u16, 0, 0, 0, 0, 0, 0], u16::to_le_bytes))
                .wait(100)
                .read()
                .request(&req(0x0E, 0x04, 100, Some(3), &[])),
            ),
        ],
        // AKD EtherNet/IP manual: the command handshake of 6.2.4 on assembly 101, the
        // position controller class 0x25 and the parameter class 0x0F.
        "kollmorgen-akd" => {
            let mut step1 = [0u8; 64];
            step1[..8].copy_from_slice(&[0x80, 0x00, 0x21, 0x20, 0xE8, 0x03, 0x00, 0x00]);
            let mut step2 = step1;
            step2[0] |= 0x40;
            let mut set_mode = [0u8; 64];
            set_mode[..8].copy_from_slice(&[0x80, 0x00, 0x3B, 0x20, 1, 0, 0, 0]);
            set_mode[24] = 3;
            let mut set_mode_load = set_mode;
            set_mode_load[0] |= 0x40;
            vec![
                (
                    "handshake_6_2_4",
                    s().request(&req(0x10, 0x25, 1, Some(3), &[1]))
                        .write(1, &step1)
                        .read()
                        .write(1, &step2)
                        .request(&req(0x0E, 0x25, 1, Some(6), &[]))
                        .wait(50)
                        .write(1, &step1)
                        .read(),
                ),
                (
                    "set_attribute_over_io",
                    s().write(1, &set_mode)
                        .write(1, &set_mode_load)
                        .read()
                        .request(&req(0x0E, 0x25, 1, Some(3), &[])),
                ),
                (
                    "parameter_object",
                    s().request(&req(0x0E, 0x0F, 1, Some(6), &[]))
                        .request(&req(0x0E, 0x0F, 1, Some(1), &[]))
                        .request(&req(0x0E, 0x0F, 205, Some(1), &[]))
                        .request(&req(0x10, 0x0F, 5, Some(1), &(-7i64).to_le_bytes()))
                        .request(&req(0x10, 0x0F, 4, Some(1), &(-3i16).to_le_bytes()))
                        .request(&req(0x0E, 0x0F, 5, Some(1), &[])),
                ),
            ]
        }
        _ => Vec::new(),
    }
}

/// §4.1's valid PLS object of the Ametek manual (class 0xC1 attribute 1): group 1 SF 360,
/// outputs 1 and 17, input 9; groups 2-8 SF 360.
fn ametek_pls_object() -> [u16; 48] {
    let mut w = [0u16; 48];
    for g in 0..8 {
        w[6 * g] = 360;
    }
    w[1] = 0x0001;
    w[2] = 0x0001;
    w[3] = 0x0100;
    w
}
