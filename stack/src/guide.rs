//! Writing a device: the [`crate::Device`] trait step by step, and what the stack guarantees.
//!
//! A device is one type that implements [`crate::Device`]. Only four methods are required
//! (identity, the assembly list, read and write of assembly data); everything else has a
//! default that behaves like a plain I/O block. The stack owns the protocol: sessions,
//! the Message Router, every standard object, Forward_Open validation, the connection table,
//! production timing and every status code. The device owns its data and its decisions.
//!
//! # 1. Identity and assemblies
//!
//! ```
//! use enip_stack::cip::{CipError, CipResult, General};
//! use enip_stack::{AssemblyInfo, AssemblyRole, Device, IdentityInfo};
//!
//! const IDENTITY: IdentityInfo = IdentityInfo {
//!     vendor_id: 0xFFFF,
//!     device_type: 7, // general purpose discrete I/O
//!     product_code: 16,
//!     revision: (1, 1),
//!     serial_number: 0x0000_0042,
//!     product_name: "16-channel I/O block",
//! };
//! const INPUTS: u16 = 100;
//! const OUTPUTS: u16 = 150;
//! const CONFIG: u16 = 151;
//! const ASSEMBLIES: [AssemblyInfo; 3] = [
//!     AssemblyInfo { instance: INPUTS, role: AssemblyRole::Input, size: 2, run_idle_header: false },
//!     AssemblyInfo { instance: OUTPUTS, role: AssemblyRole::Output, size: 2, run_idle_header: true },
//!     AssemblyInfo { instance: CONFIG, role: AssemblyRole::Config, size: 1, run_idle_header: false },
//! ];
//!
//! #[derive(Default)]
//! struct Block { inputs: [u8; 2], outputs: [u8; 2], filter_ms: u8 }
//!
//! impl Device for Block {
//!     fn identity(&self) -> &IdentityInfo { &IDENTITY }
//!     fn assemblies(&self) -> &[AssemblyInfo] { &ASSEMBLIES }
//!     fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
//!         match instance {
//!             INPUTS => out.copy_from_slice(&self.inputs),
//!             OUTPUTS => out.copy_from_slice(&self.outputs),
//!             _ => out.copy_from_slice(&[self.filter_ms]),
//!         }
//!         Ok(out.len())
//!     }
//!     fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult {
//!         match instance {
//!             OUTPUTS => self.outputs.copy_from_slice(data),
//!             // Byte 0 out of range: target not configured, the offending byte (0) added.
//!             CONFIG if data[0] > 100 => return Err(CipError::connection(0x0110).with_additional(0x0110, 0)),
//!             CONFIG => self.filter_ms = data[0],
//!             _ => return Err(General::AttributeNotSettable.into()),
//!         }
//!         Ok(())
//!     }
//! }
//! # let mut b = Block::default();
//! # assert_eq!(b.write_assembly(CONFIG, &[101]).unwrap_err().additional(), &[0x0110, 0]);
//! ```
//!
//! The stack calls `read_assembly` with `out` exactly the assembly's current size (as
//! [`crate::Device::assemblies`] says at that moment; see the capacities below for the
//! largest), and sends exactly the length it returns (never more than the size). It calls `write_assembly` with exactly the assembly's current size:
//! O->T data in Run (never Idle data, never a duplicate), an explicit Set of an output,
//! configuration or explicit assembly, and a Forward_Open's configuration data. Heartbeat
//! assemblies ([`crate::AssemblyRole::InputOnlyHeartbeat`], [`crate::AssemblyRole::ListenOnlyHeartbeat`],
//! size 0) never reach it: their connections carry no O->T data, and they are not settable
//! (a Set is 0x0E), so a device needs no arm for them.
//!
//! **Checking configuration data: one place.** Check it in `write_assembly` and refuse it
//! with a connection failure, the extended status and any additional word (here the
//! offending byte): a Forward_Open carrying it is refused with exactly that error (before
//! the connection exists; [`crate::Device::admit`] need not look at it), and an explicit
//! Set of the configuration assembly answers 0x09 (invalid attribute value), changing
//! nothing. Any other error from the configuration assembly refuses a Forward_Open with
//! 0x01/0x0110 (target not configured).
//!
//! # 2. A vendor class
//!
//! Declare the class as data ([`crate::cip::object::ClassDef`]); the stack serves
//! Get/Set_Attribute_Single, Get/Set_Attribute_List, Get_Attributes_All, the class
//! attributes 1-7 and every status rule (see [`crate::cip::object`]); the device only
//! converts values. Vendor services (0x4B-0x63...) reach
//! [`crate::Device::handle_request`] once the stack found the instance.
//!
//! ```
//! use enip_stack::cip::context::RequestContext;
//! use enip_stack::cip::object::{AttributeDef, ClassDef, DataType};
//! use enip_stack::cip::{CipResult, General, Request};
//! use enip_stack::device::AttributeRef;
//! use enip_stack::wire::Writer;
//! # use enip_stack::{AssemblyInfo, Device, IdentityInfo};
//!
//! /// Class 0x70: one instance per channel, a debounce time (settable, 0-100 ms) and a
//! /// counter of edges (read-only); service 0x4B clears the counter.
//! const CHANNELS: ClassDef = ClassDef {
//!     id: 0x70,
//!     name: "Channel",
//!     revision: 1,
//!     max_instance: 16,
//!     attributes: &[
//!         AttributeDef::get_set(1, DataType::Usint, "Debounce"),
//!         AttributeDef::get(2, DataType::Udint, "Edges"),
//!     ],
//!     get_all: &[1, 2],
//!     optional_attributes: &[],
//! };
//!
//! struct Block { debounce: [u8; 16], edges: [u32; 16] }
//!
//! impl Device for Block {
//! #   fn identity(&self) -> &IdentityInfo { unimplemented!() }
//! #   fn assemblies(&self) -> &[AssemblyInfo] { &[] }
//! #   fn read_assembly(&mut self, _: u16, _: &mut [u8]) -> CipResult<usize> { Ok(0) }
//! #   fn write_assembly(&mut self, _: u16, _: &[u8]) -> CipResult { Ok(()) }
//!     fn classes(&self) -> &[ClassDef] { &[CHANNELS] }
//!     fn get_attribute(&mut self, _cx: &RequestContext, at: &AttributeRef<'_>, w: &mut Writer<'_>) -> CipResult {
//!         let ch = at.instance as usize - 1; // the stack checked 1..=16
//!         match at.attribute.id {
//!             1 => w.u8(self.debounce[ch])?,
//!             _ => w.u32(self.edges[ch])?,
//!         }
//!         Ok(())
//!     }
//!     fn set_attribute(&mut self, _cx: &RequestContext, at: &AttributeRef<'_>, value: &[u8]) -> CipResult {
//!         // Only attribute 1 is settable, and `value` is exactly one byte.
//!         match value[0] {
//!             v @ 0..=100 => self.debounce[at.instance as usize - 1] = v,
//!             _ => return Err(General::InvalidAttributeValue.into()),
//!         }
//!         Ok(())
//!     }
//!     fn handle_request(&mut self, _cx: &RequestContext, req: &Request<'_>, _w: &mut Writer<'_>) -> Option<CipResult> {
//!         let ch = req.path.instance? as usize;
//!         (req.service == 0x4B).then(|| { self.edges[ch - 1] = 0; Ok(()) })
//!     }
//! }
//! ```
//!
//! A handler that refuses a value changes nothing; Set_Attribute_List applies each entry on
//! its own and skips a refused one. [`crate::cip::context::RequestContext`] tells a handler
//! whether the request came unconnected or over which Class 3 connection, from which peer,
//! and when. To test a device without a network, [`crate::Adapter::execute`] runs one
//! Message Router request through the same machinery, and
//! [`crate::virtual_scanner::VirtualScanner`] plays a whole scanner in virtual time
//! (sessions, explicit requests, Forward_Open, Class 1 data both ways, watchdogs).
//!
//! # 3. Admission of connections
//!
//! [`crate::Device::admit`] sees every Forward_Open the stack found valid, with everything
//! in it ([`crate::device::OpenRequest`]), before the connection exists. Its error goes out
//! exactly as given.
//!
//! ```
//! use enip_stack::cip::{CipError, CipResult};
//! use enip_stack::device::{ConnectionEvent, OpenRequest};
//! use enip_stack::cip::connection_status::{OUT_OF_CONNECTIONS, OWNERSHIP_CONFLICT};
//! use enip_stack::device::Kind;
//!
//! /// One Class 1 connection at a time, RPI 2-100 ms.
//! #[derive(Default)]
//! struct Policy { class1_open: usize }
//!
//! impl Policy {
//!     fn admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
//!         if request.is_class1() && self.class1_open > 0 {
//!             let ext = if request.kind == Kind::ExclusiveOwner { OWNERSHIP_CONFLICT } else { OUT_OF_CONNECTIONS };
//!             return Err(CipError::connection(ext));
//!         }
//!         request.refuse_rpi(2_000, 100_000)
//!     }
//!     fn connection_event(&mut self, event: ConnectionEvent) {
//!         match event {
//!             ConnectionEvent::Opened(c) if c.kind != Kind::Explicit => self.class1_open += 1,
//!             ConnectionEvent::Closed(c, _) if c.kind != Kind::Explicit => self.class1_open -= 1,
//!             _ => {}
//!         }
//!     }
//! }
//! ```
//!
//! (In a device, these two are the bodies of `Device::admit` and
//! `Device::connection_event`.) Configuration data of an admitted Forward_Open is then
//! written with `write_assembly` (when the connection is an exclusive owner, or no owner
//! exists), which checks it (section 1); an error there answers 0x01/0x0110 unless it is
//! already a connection failure, which goes out as given.
//!
//! # 4. Events
//!
//! [`crate::device::ConnectionEvent`]: `Opened` (slot, kind, points, RPIs, originator and
//! triad), `Closed` with a [`crate::device::CloseReason`] (Forward_Close, timeout,
//! dependency, session closed, Reset, reconfigured), `OwnershipGained` / `OwnershipLost`, and
//! `RunIdle`. Enough for status parameters that report the live connection.
//!
//! # 5. Inputs that change
//!
//! Cyclic connections read the inputs every RPI by themselves: at once when they open, then
//! on the adapter's grid of their RPI, so connections of one RPI read them at the same
//! instants ([`crate::io::ConnectionTable::grid_phase`]). For change-of-state and
//! application-triggered connections, the device says which input assemblies changed: it
//! keeps an [`crate::device::InputChanges`], marks it, and lends it from
//! [`crate::Device::input_changes`]. The stack looks after every call into the device
//! (explicit requests, O->T data, [`crate::Adapter::poll_device`]), so a device without a
//! clock of its own gets its changes produced too, as soon as the production inhibit time
//! allows.
//!
//! ```
//! use enip_stack::device::InputChanges;
//!
//! struct Block { inputs: [u8; 2], changes: InputChanges }
//! impl Block {
//!     /// Called by the firmware's input scan.
//!     fn scan(&mut self, pins: [u8; 2]) {
//!         if pins != self.inputs {
//!             self.inputs = pins;
//!             self.changes.mark(100);
//!         }
//!     }
//!     // In `impl Device`: fn input_changes(&mut self) -> Option<&mut InputChanges> { Some(&mut self.changes) }
//! }
//! ```
//!
//! # 6. Assembly sizes that follow the configuration
//!
//! [`crate::Device::assemblies`] is read at every Forward_Open, Get and Set, so a device may
//! keep its list in a field and change sizes when its configuration changes. A device should
//! refuse (0x10, device state conflict) a change that resizes an assembly a connection is
//! using; it knows which from its events. If it does not, the stack closes each connection
//! whose consumed or produced assembly changed size with `CloseReason::Reconfigured` right
//! after the explicit request that changed it, so no datagram of a stale size goes out.
//!
//! # 7. Capacities
//!
//! Every table is sized at compile time, by the [`crate::Adapter`]'s type:
//! `Adapter<D, SESSIONS, CONNECTIONS, FRAME, LIST_IDENTITY>`, with the defaults of
//! [`crate::config`] (3 TCP sessions, 10 CIP connections shared by Class 1 and Class 3,
//! 1 048-byte encapsulation frames, 4 delayed ListIdentity replies) that fit a small MCU.
//! [`crate::Adapter::new`] builds the default; a gateway or a soft device on Linux names its
//! sizes once, in a type alias, and builds with [`crate::Adapter::with_capacities`]:
//!
//! ```
//! # use enip_stack::{Adapter, AssemblyInfo, Device, IdentityInfo, NetworkConfig};
//! # use enip_stack::cip::CipResult;
//! # struct Gateway;
//! # impl Device for Gateway {
//! #   fn identity(&self) -> &IdentityInfo { unimplemented!() }
//! #   fn assemblies(&self) -> &[AssemblyInfo] { &[] }
//! #   fn read_assembly(&mut self, _: u16, _: &mut [u8]) -> CipResult<usize> { Ok(0) }
//! #   fn write_assembly(&mut self, _: u16, _: &[u8]) -> CipResult { Ok(()) }
//! # }
//! # let net = NetworkConfig::new_static([198, 18, 0, 2].into(), [255, 255, 255, 0].into(), [2, 0, 0, 0, 0, 2]);
//! /// 16 sessions, 64 connections, frames of the header plus a 1 500-byte payload (a
//! /// 1 448-byte assembly read explicitly), 16 ListIdentity replies waiting their delay.
//! type GatewayAdapter = Adapter<Gateway, 16, 64, { 24 + 1500 }, 16>;
//! let adapter = GatewayAdapter::with_capacities(Gateway, net, 0x5eed);
//! assert_eq!(adapter.connections().len(), 0);
//! ```
//!
//! - `FRAME` bounds every explicit message and reply: the runtime's reply buffers have that
//!   size (`enip_firmware::Resources<FRAME>`, which the embedded runtime takes with the
//!   adapter, and the encapsulation TCP's [`crate::tcp::TcpServer`]`<SESSIONS, FRAME>`, two
//!   replies a session), and an assembly read explicitly must fit it (0x11 otherwise). Class 1
//!   data does not pass through it: a Large_Forward_Open carries an assembly as large as
//!   the device declares, up to 1 448 bytes in one Ethernet frame.
//! - The choices are checked against each other where the adapter is built, at compile
//!   time: 1 to 254 sessions and connections, `FRAME` at least
//!   [`crate::adapter::MIN_FRAME`] (a 504-byte Class 3 message) and within the 16-bit
//!   length field, at least one ListIdentity slot; the embedded runtime's
//!   `Resources::<FRAME>::stack_resources::<N>()` refuses fewer embassy-net sockets than
//!   its UDP socket needs.
//!
//!   ```compile_fail
//!   # use enip_stack::{Adapter, AssemblyInfo, Device, IdentityInfo, NetworkConfig};
//!   # use enip_stack::cip::CipResult;
//!   # struct Gateway;
//!   # impl Device for Gateway {
//!   #   fn identity(&self) -> &IdentityInfo { unimplemented!() }
//!   #   fn assemblies(&self) -> &[AssemblyInfo] { &[] }
//!   #   fn read_assembly(&mut self, _: u16, _: &mut [u8]) -> CipResult<usize> { Ok(0) }
//!   #   fn write_assembly(&mut self, _: u16, _: &[u8]) -> CipResult { Ok(()) }
//!   # }
//!   # let net = NetworkConfig::new_static([198, 18, 0, 2].into(), [255, 255, 255, 0].into(), [2, 0, 0, 0, 0, 2]);
//!   // error: "FRAME: at least MIN_FRAME, for a 504-byte Class 3 message"
//!   let small = Adapter::<Gateway, 3, 10, 256>::with_capacities(Gateway, net, 1);
//!   ```
//! - Const generics rather than a `Config` trait: stable Rust cannot size an array by a
//!   trait's associated constant in generic code, and a const parameter costs nothing at
//!   run time: the default build is the same code as before the sizes were parameters.
//!
//! # 8. A device in front of another
//!
//! A wrapper that changes one thing of a device it holds (another identity for each
//! device of a simulated plant, a board's diagnostics class served before the profile's)
//! implements [`crate::device::Front`] instead of [`crate::Device`]: it names the inner device and
//! takes over [`crate::Device::identity`] or [`crate::Device::handle_request`]; every other call goes
//! through to the inner device, and the wrapper is a [`crate::Device`] itself.
//!
//! # What the stack guarantees
//!
//! - **Idle data**: O->T data whose run/idle header says Idle is never written to the
//!   device; the device hears `RunIdle(false)` and chooses its idle state itself. Run data
//!   is written only when its sequence count is new.
//! - **Owned outputs**: an explicit Set of an output assembly that an exclusive-owner
//!   connection holds is refused with 0x10 (device state conflict); the device never sees it.
//! - **Connection loss**: when the watchdog (multiplier x RPI) expires, the connection is
//!   closed with `Closed(_, Timeout)`, followed by `OwnershipLost(Timeout)` when it was the last
//!   exclusive owner. The stack never writes outputs itself: the device applies its safe
//!   state on `OwnershipLost` (the PositionServo profile disables the drive there).
//! - **Refused writes**: a refused Set, or refused O->T data, leaves the device as it was and
//!   every other session and connection goes on.
