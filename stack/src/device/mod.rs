//! The [`Device`] trait: what a device profile supplies to the stack, and the types it
//! speaks in (identity, assemblies, vendor classes, admission, events, input changes).
//! [`crate::guide`] walks through writing one.

pub mod admission;
pub mod connection_kind;
pub mod electronic_key;
pub mod events;
pub mod front;
pub mod inputs;
pub mod multicast;

use crate::cip::context::RequestContext;
use crate::cip::object::{Access, AttributeDef, ClassDef};
use crate::cip::request::Request;
use crate::cip::status::{CipError, CipResult, General};
use crate::time::Instant;
use crate::wire::Writer;

pub use admission::{Direction, OpenRequest};
pub use connection_kind::{Kind, Trigger};
pub use electronic_key::KeyMismatch;
pub use events::{CloseReason, ConnectionEvent, ConnectionInfo, ConnectionPoints};
pub use front::Front;
pub use inputs::InputChanges;
pub use multicast::{Multicast, MulticastConfig};

/// Identity object values (class 0x01, attributes 1-7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IdentityInfo {
    /// Vendor ID (attribute 1).
    pub vendor_id: u16,
    /// Device type (attribute 2).
    pub device_type: u16,
    /// Product code (attribute 3).
    pub product_code: u16,
    /// Major and minor revision (attribute 4).
    pub revision: (u8, u8),
    /// Serial number (attribute 6).
    pub serial_number: u32,
    /// Product name (attribute 7), at most 32 characters.
    pub product_name: &'static str,
}

/// What an assembly instance is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AssemblyRole {
    /// Produced by the device (T->O data); read-only to explicit messages.
    Input,
    /// Consumed by the device (O->T data).
    Output,
    /// Configuration data, written at Forward_Open or explicitly.
    Config,
    /// O->T connection point of an input-only connection (heartbeat, no data).
    InputOnlyHeartbeat,
    /// O->T connection point of a listen-only connection (heartbeat, no data).
    ListenOnlyHeartbeat,
    /// Explicit messaging only: read and written, never connected.
    Explicit,
}

impl AssemblyRole {
    /// True if explicit Set_Attribute_Single may write the data.
    pub const fn settable(self) -> bool {
        matches!(
            self,
            AssemblyRole::Output | AssemblyRole::Config | AssemblyRole::Explicit
        )
    }
}

/// One assembly instance a device exposes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AssemblyInfo {
    /// Instance ID.
    pub instance: u16,
    /// Its role.
    pub role: AssemblyRole,
    /// Data size in bytes.
    pub size: u16,
    /// True if O->T data for it carries the 32-bit run/idle header.
    pub run_idle_header: bool,
}

/// Everything a device profile supplies. Only identity and assemblies are required.
///
/// A minimal I/O block: 4 input bytes produced, 4 output bytes consumed (with the run/idle
/// header), driven through the adapter's entry points.
///
/// ```
/// use core::net::{Ipv4Addr, SocketAddrV4};
/// use enip_stack::cip::CipResult;
/// use enip_stack::{Adapter, AssemblyInfo, AssemblyRole, Device, IdentityInfo, Instant, NetworkConfig, SocketId};
///
/// const IDENTITY: IdentityInfo = IdentityInfo {
///     vendor_id: 0xFFFF,
///     device_type: 7,
///     product_code: 1,
///     revision: (1, 1),
///     serial_number: 42,
///     product_name: "tiny I/O block",
/// };
/// const ASSEMBLIES: [AssemblyInfo; 2] = [
///     AssemblyInfo { instance: 100, role: AssemblyRole::Input, size: 4, run_idle_header: false },
///     AssemblyInfo { instance: 150, role: AssemblyRole::Output, size: 4, run_idle_header: true },
/// ];
///
/// struct Block { inputs: [u8; 4], outputs: [u8; 4] }
///
/// impl Device for Block {
///     fn identity(&self) -> &IdentityInfo { &IDENTITY }
///     fn assemblies(&self) -> &[AssemblyInfo] { &ASSEMBLIES }
///     fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize> {
///         let data = if instance == 100 { &self.inputs } else { &self.outputs };
///         out.copy_from_slice(data);
///         Ok(data.len())
///     }
///     fn write_assembly(&mut self, _instance: u16, data: &[u8]) -> CipResult {
///         self.outputs.copy_from_slice(data);
///         Ok(())
///     }
/// }
///
/// let net = NetworkConfig::new_static(Ipv4Addr::new(198, 18, 0, 2), Ipv4Addr::new(255, 255, 255, 0), [2, 0, 0, 0, 0, 1]);
/// let mut adapter = Adapter::new(Block { inputs: [1, 2, 3, 4], outputs: [0; 4] }, net, 7);
/// // A scanner connects and registers a session; the reply goes back on the same socket.
/// adapter.tcp_accept(SocketId(0), SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50000), Instant(0));
/// let mut frame = [0u8; 64];
/// let n = enip_stack::originator::register_session(&mut frame).unwrap();
/// let mut reply = [0u8; enip_stack::config::MAX_ENCAP_FRAME];
/// let out = adapter.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
/// assert_eq!((out.consumed, out.reply_len, out.close), (n, 28, false));
/// // Nothing is due until a connection opens.
/// assert_eq!(adapter.io_deadline(), None);
/// ```
pub trait Device {
    /// Identity object values.
    fn identity(&self) -> &IdentityInfo;
    /// Extra identity status bits the device owns (fault bits 8-11); the stack adds the rest.
    fn status_bits(&self) -> u16 {
        0
    }
    /// The assembly instances, with role and current size. The stack reads it at every
    /// Forward_Open, Get and Set, so sizes may follow the device's configuration (see
    /// [`crate::guide`] on run-time sizes).
    fn assemblies(&self) -> &[AssemblyInfo];
    /// Copies assembly `instance` into `out` (sized to the assembly's current size) and
    /// returns the length written; Get and production send exactly that many bytes.
    fn read_assembly(&mut self, instance: u16, out: &mut [u8]) -> CipResult<usize>;
    /// Accepts new data for assembly `instance` (exactly its current size): O->T data in
    /// Run, an explicit Set, or a Forward_Open's configuration data. An error refuses it; a
    /// connection failure refuses a Forward_Open as given and a Set as 0x09 (see
    /// [`crate::guide`]). Heartbeat assemblies never come here.
    fn write_assembly(&mut self, instance: u16, data: &[u8]) -> CipResult;

    /// True if a Class 1 connection may carry `data` bytes of `assembly` (the size its
    /// Forward_Open asks for, without the sequence count or run/idle header); by default
    /// exactly the assembly's current size. A device whose sizes follow its configuration
    /// may accept a range up to the assembly's size: production then sends that many bytes
    /// and consumption hands `write_assembly` that many. Refused sizes get 0x0127/0x0128
    /// with the assembly's size as the acceptable one.
    fn accepts_connection_size(&self, assembly: &AssemblyInfo, data: usize) -> bool {
        data == usize::from(assembly.size)
    }

    /// True if the assembly instances answer Get_Attributes_All (0x01) with their data
    /// (attribute 3), as some devices' manuals list it; by default they do not (0x08).
    fn assembly_get_attributes_all(&self) -> bool {
        false
    }

    /// The vendor classes the device declares; the stack serves their attribute services,
    /// class attributes and status rules, and lists them in the Message Router.
    fn classes(&self) -> &[ClassDef] {
        &[]
    }
    /// True if `instance` (at least 1) of `class` exists; by default `1..=max_instance`.
    fn has_instance(&self, class: &ClassDef, instance: u32) -> bool {
        instance <= class.max_instance
    }
    /// Class attribute 3 of `class`, the number of instances; by default `max_instance`.
    fn instance_count(&self, class: &ClassDef) -> u32 {
        class.max_instance
    }
    /// The access rule of an attribute on one instance; by default its definition's (a
    /// read-only instance of a settable attribute answers 0x0E before its value is read).
    fn attribute_access(&self, at: &AttributeRef<'_>) -> Access {
        at.attribute.access
    }
    /// The size in bytes of a [`crate::cip::object::DataType::RunTime`] attribute of a
    /// declared class on this instance: how much of a Set_Attribute_Single or
    /// Set_Attribute_List value is its (a shorter value is 0x13, a longer Single 0x15). `None`
    /// (the default) refuses a Set of it with 0x14; Gets do not need it.
    fn attribute_size(&self, _at: &AttributeRef<'_>) -> Option<usize> {
        None
    }
    /// Writes the value of a gettable attribute of a declared class.
    fn get_attribute(
        &mut self,
        _cx: &RequestContext,
        _at: &AttributeRef<'_>,
        _w: &mut Writer<'_>,
    ) -> CipResult {
        Err(CipError::new(General::AttributeNotSupported))
    }
    /// Stores `value` (exactly the attribute's encoded bytes, length already checked) in a
    /// settable attribute, or refuses it (0x09 invalid value, 0x0C object state, 0x10 device
    /// state...) and changes nothing.
    fn set_attribute(
        &mut self,
        _cx: &RequestContext,
        _at: &AttributeRef<'_>,
        _value: &[u8],
    ) -> CipResult {
        Err(CipError::new(General::AttributeNotSettable))
    }
    /// Any other request: a vendor service on a declared class (after the stack found the
    /// instance), or a class the device does not declare, or a symbolic path. `None` if it
    /// is not the device's: the stack then serves the attribute services of a declared
    /// class, and answers 0x05 otherwise.
    fn handle_request(
        &mut self,
        _cx: &RequestContext,
        _req: &Request<'_>,
        _reply: &mut Writer<'_>,
    ) -> Option<CipResult> {
        None
    }

    /// Decides on a Forward_Open the stack found valid, before the connection exists:
    /// `Ok(())` accepts it; an error (a connection failure with the device's extended
    /// status) goes out as the reply exactly as given.
    fn admit(&mut self, _request: &OpenRequest<'_>) -> CipResult {
        Ok(())
    }
    /// A connection event: opened, closed (with the reason), ownership, run/idle.
    fn connection_event(&mut self, _event: ConnectionEvent) {}
    /// The input assemblies whose data changed, kept by the device: after every call into
    /// the device (explicit requests, O->T data, [`Device::poll`]) the stack triggers
    /// change-of-state and application-triggered production of each and clears the set.
    /// `None` (the default) for a device whose inputs only change cyclically.
    fn input_changes(&mut self) -> Option<&mut InputChanges> {
        None
    }

    /// Identity Reset service: 0 emulates a power cycle, 1 also restores factory defaults.
    /// Called before the reply is sent, and before the stack restores its own factory
    /// settings: an error refuses the Reset, and the stack then changes nothing. For type 1
    /// the adapter's store is in a batch ([`crate::nv::NvStore::begin`]): the records the
    /// device removes here and the TCP/IP settings are saved as one, and dropped if it
    /// refuses. The device performs the reset afterwards.
    fn reset(&mut self, _kind: u8) -> CipResult {
        Ok(())
    }
    /// Advances the device's own behaviour (a simulation); returns when it next needs a call.
    fn poll(&mut self, _now: Instant) -> Option<Instant> {
        None
    }
    /// The multicast TTL and configuration when the device keeps them itself (e.g. in its
    /// own parameters): `Some` replaces the TCP/IP object's own values everywhere (attributes
    /// 8 and 9, Forward_Open, [`crate::Adapter::multicast_group`] and
    /// [`crate::Adapter::multicast_ttl`]). `config.start` is the address in use, also when
    /// `config.alloc_control` is 0. The stack's own values change at the next start (TCP/IP
    /// status bit 4 meanwhile); a device keeping them applies a Set when it chooses.
    fn multicast(&self) -> Option<Multicast> {
        None
    }
    /// A Set of TCP/IP attribute 8 or 9, already validated by the stack (alloc control 0
    /// comes with no address: the device's default applies), for a device whose
    /// [`Device::multicast`] is `Some`. An error becomes the reply to the Set.
    fn set_multicast(&mut self, _multicast: Multicast) -> CipResult {
        Ok(())
    }
}

/// One attribute of one instance of a declared class, as a request addresses it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttributeRef<'a> {
    /// The class.
    pub class: &'a ClassDef,
    /// The instance (at least 1).
    pub instance: u32,
    /// The attribute.
    pub attribute: &'a AttributeDef,
}

/// The assembly `instance` of `device`, as it describes it now.
pub(crate) fn assembly<D: Device>(device: &D, instance: u32) -> Option<AssemblyInfo> {
    device
        .assemblies()
        .iter()
        .find(|a| u32::from(a.instance) == instance)
        .copied()
}
