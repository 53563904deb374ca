//! The one dispatcher of the object model: every object, built-in or a device's vendor
//! class, is a [`ClassDef`] plus an [`Object`] that reads and writes values; this module
//! answers the attribute services, the class attributes (instance 0) and every status rule
//! from them.
//!
//! Status rules, in the order they are checked: no instance in the path 0x05, unknown
//! instance 0x16, the object's own services (Reset, Forward_Open, vendor services...), then
//! no attribute in the path 0x05, unknown attribute 0x14, Get of a write-only attribute
//! 0x2C, Set of a read-only one 0x0E, value shorter than its type 0x13 or longer 0x15, then
//! the object's verdict on the value (0x09 invalid, 0x0C object state, 0x10 device state),
//! reply too large 0x11, and anything else 0x08 (service not supported). Get_Attribute_Single
//! and Get_Attributes_All carrying data are too much data (0x15). A failed Set
//! changes nothing; Set_Attribute_List applies each entry on its own, as CIP specifies.

use crate::cip::object::{Access, AttributeDef, ClassDef, DataType};
use crate::cip::service;
use crate::cip::status::{CipError, CipResult, General};
use crate::cip::Request;
use crate::config::MAX_MULTIPLE_SERVICES;
use crate::wire::{Reader, Writer};

/// Values and services of one class; the attribute services come from [`serve`].
pub(crate) trait Object {
    /// The class definition.
    fn class(&self) -> &ClassDef;
    /// True if `instance` (at least 1) exists.
    fn has_instance(&self, instance: u32) -> bool {
        instance <= self.class().max_instance
    }
    /// Class attribute 2: the highest instance number.
    fn max_instance(&self) -> u32 {
        self.class().max_instance
    }
    /// Class attribute 3: the number of instances.
    fn instance_count(&self) -> u32 {
        self.max_instance()
    }
    /// The access rule of `attr` on `instance` (the definition's, unless the instance
    /// narrows it); `None` (0x14) for an attribute not implemented whose default value only
    /// fills Get_Attributes_All's layout (as the TCP/IP object's 7 and 12).
    fn access(&self, _instance: u32, attr: &AttributeDef) -> Option<Access> {
        Some(attr.access)
    }
    /// The optional services the class answers beyond the attribute lists, which every class
    /// answers ([`attribute_services`]): class attribute 5 lists both (Vol 1 4-4.1).
    fn extra_optional_services(&self) -> &'static [u8] {
        &[]
    }
    /// The size of a [`DataType::RunTime`] attribute of `instance`.
    fn run_time_size(&self, _instance: u32, _attr: &AttributeDef) -> Option<usize> {
        None
    }
    /// Writes the value of `attr` of `instance`.
    fn get(&mut self, instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult;
    /// Stores `value` (exactly the attribute's bytes) or refuses it, changing nothing.
    fn set(&mut self, _instance: u32, _attr: &AttributeDef, _value: &[u8]) -> CipResult {
        Err(General::AttributeNotSettable.into())
    }
    /// Runs a service other than the attribute services on `instance` (0: the class);
    /// `None` if it is not one of the object's own.
    fn service(
        &mut self,
        _instance: u32,
        _req: &Request<'_>,
        _w: &mut Writer<'_>,
    ) -> Option<CipResult> {
        None
    }
}

/// Answers `req` for the class `obj`: its own services first, then the attribute services.
/// One copy for every class, through `dyn Object` (a copy per class cost about 3 KiB of
/// flash; explicit messaging only, no Class 1 request comes here).
#[inline(never)]
pub(crate) fn serve(obj: &mut dyn Object, req: &Request<'_>, w: &mut Writer<'_>) -> CipResult {
    let instance = req
        .path
        .instance_or_point()
        .ok_or(CipError::new(General::PathDestinationUnknown))?;
    if instance == 0 {
        if let Some(r) = obj.service(0, req, w) {
            return r;
        }
        let mut class = ClassLevel {
            def: *obj.class(),
            max_instance: obj.max_instance(),
            instances: obj.instance_count(),
            services: obj.extra_optional_services(),
        };
        return attribute_services(&mut class, 0, req, w);
    }
    if !obj.has_instance(instance) {
        return Err(General::ObjectDoesNotExist.into());
    }
    if let Some(r) = obj.service(instance, req, w) {
        return r;
    }
    attribute_services(obj, instance, req, w)
}

/// Get/Set_Attribute_Single, Get/Set_Attribute_List and Get_Attributes_All on `instance`.
///
/// Every class through `dyn Object`, one copy (a copy per class cost about 8 KiB of flash).
pub(crate) fn attribute_services(
    obj: &mut dyn Object,
    instance: u32,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    if req.service != service::GET_ATTRIBUTE_SINGLE {
        return other_attribute_services(obj, instance, req, w);
    }
    let attr = lookup(obj.class(), req.path.attribute)?;
    if !req.data.is_empty() {
        return Err(General::TooMuchData.into());
    }
    get_one(obj, instance, &attr, w)
}

/// The attribute services other than Get_Attribute_Single.
fn other_attribute_services(
    obj: &mut dyn Object,
    instance: u32,
    req: &Request<'_>,
    w: &mut Writer<'_>,
) -> CipResult {
    match req.service {
        service::SET_ATTRIBUTE_SINGLE => {
            let attr = lookup(obj.class(), req.path.attribute)?;
            let len = value_len(obj, instance, &attr, req.data)?;
            if len < req.data.len() {
                return Err(General::TooMuchData.into());
            }
            obj.set(instance, &attr, req.data)
        }
        service::GET_ATTRIBUTES_ALL if !obj.class().get_all.is_empty() => {
            if !req.data.is_empty() {
                return Err(General::TooMuchData.into());
            }
            let def = *obj.class();
            for &id in def.get_all {
                let attr = def.attribute(id).ok_or(unsupported())?;
                obj.get(instance, attr, w)?;
            }
            Ok(())
        }
        service::GET_ATTRIBUTE_LIST => get_list(obj, instance, req.data, w),
        service::SET_ATTRIBUTE_LIST => set_list(obj, instance, req.data, w),
        _ => Err(General::ServiceNotSupported.into()),
    }
}

/// The attribute a path names: none is 0x05, an unknown one 0x14.
fn lookup(class: &ClassDef, attribute: Option<u32>) -> CipResult<AttributeDef> {
    let id = attribute.ok_or(CipError::new(General::PathDestinationUnknown))?;
    u16::try_from(id)
        .ok()
        .and_then(|id| class.attribute(id))
        .copied()
        .ok_or(unsupported())
}

fn unsupported() -> CipError {
    CipError::new(General::AttributeNotSupported)
}

/// One attribute's value, if it is gettable (0x2C if not); for the object's own type on the
/// Get_Attribute_Single path, through `dyn Object` for the lists.
fn get_one(
    obj: &mut dyn Object,
    instance: u32,
    attr: &AttributeDef,
    w: &mut Writer<'_>,
) -> CipResult {
    if !obj.access(instance, attr).ok_or(unsupported())?.gettable() {
        return Err(General::AttributeNotGettable.into());
    }
    obj.get(instance, attr, w)
}

/// The length of a Set value for `attr` at the front of `data`; 0x0E if not settable.
fn value_len(
    obj: &dyn Object,
    instance: u32,
    attr: &AttributeDef,
    data: &[u8],
) -> CipResult<usize> {
    if !obj.access(instance, attr).ok_or(unsupported())?.settable() {
        return Err(General::AttributeNotSettable.into());
    }
    attr.data_type
        .value_len(data, obj.run_time_size(instance, attr))
}

/// The attribute count of a list request: a count the data cannot hold (2 bytes an ID at
/// least) is not enough data (0x13), one beyond what a reply may carry resource unavailable
/// (0x02).
fn list_count(r: &mut Reader<'_>) -> CipResult<u16> {
    let count = r.u16()?;
    if r.remaining() < usize::from(count) * 2 {
        return Err(General::NotEnoughData.into());
    }
    if usize::from(count) > MAX_MULTIPLE_SERVICES {
        return Err(General::ResourceUnavailable.into());
    }
    Ok(count)
}

/// Get_Attribute_List: count, then per attribute its id, status and (on success) value.
fn get_list(obj: &mut dyn Object, instance: u32, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    let mut r = Reader::new(data);
    let count = list_count(&mut r)?;
    let need = usize::from(count) * 2;
    if r.remaining() != need {
        return Err(if r.remaining() < need {
            General::NotEnoughData
        } else {
            General::TooMuchData
        }
        .into());
    }
    w.u16(count)?;
    let mut failed = false;
    for _ in 0..count {
        let id = r.u16()?;
        w.u16(id)?;
        let status_at = w.len();
        w.u16(0)?;
        let value_at = w.len();
        let got = lookup(obj.class(), Some(u32::from(id)))
            .and_then(|attr| get_one(obj, instance, &attr, w));
        if let Err(e) = got {
            if e.general == General::ReplyDataTooLarge {
                return Err(e);
            }
            w.truncate(value_at);
            w.patch_u16(status_at, u16::from(e.general));
            failed = true;
        }
    }
    if failed {
        return Err(CipError::new(General::AttributeListError).keeping_data());
    }
    Ok(())
}

/// Set_Attribute_List: count, then per attribute its id and value; replies id and status
/// each. An entry whose value length cannot be known (unknown attribute, short data) ends
/// the list there; a refused entry of known length is skipped and the rest go on.
fn set_list(obj: &mut dyn Object, instance: u32, data: &[u8], w: &mut Writer<'_>) -> CipResult {
    let mut r = Reader::new(data);
    let count = list_count(&mut r)?;
    let count_at = w.len();
    w.u16(count)?;
    let mut failed = false;
    for done in 0..count {
        let id = r.u16()?;
        w.u16(id)?;
        let attr = match lookup(obj.class(), Some(u32::from(id))) {
            Ok(attr) => attr,
            Err(e) => {
                w.u16(u16::from(e.general))?;
                w.patch_u16(count_at, done.saturating_add(1));
                return Err(CipError::new(General::AttributeListError).keeping_data());
            }
        };
        let len = attr
            .data_type
            .value_len(r.rest(), obj.run_time_size(instance, &attr));
        let value = match len {
            Ok(n) => Some(r.take(n)?),
            Err(_) => None,
        };
        let access = obj.access(instance, &attr);
        let outcome = match (value, len) {
            _ if access.is_none() => Err(unsupported()),
            _ if !access.is_some_and(Access::settable) => {
                Err(CipError::new(General::AttributeNotSettable))
            }
            (Some(value), _) => obj.set(instance, &attr, value),
            (None, Err(e)) => Err(e),
            (None, Ok(_)) => Err(CipError::new(General::NotEnoughData)),
        };
        if let Err(e) = outcome {
            w.u16(u16::from(e.general))?;
            failed = true;
            if value.is_none() {
                w.patch_u16(count_at, done.saturating_add(1));
                break;
            }
        } else {
            w.u16(0)?;
        }
    }
    if failed {
        return Err(CipError::new(General::AttributeListError).keeping_data());
    }
    Ok(())
}

/// The class attributes 1-7, all read-only.
const CLASS_LEVEL: ClassDef = ClassDef {
    id: 0,
    name: "class attributes",
    revision: 0,
    max_instance: 0,
    attributes: &[
        AttributeDef::get(1, DataType::Uint, "Revision"),
        AttributeDef::get(2, DataType::Uint, "Max Instance"),
        AttributeDef::get(3, DataType::Uint, "Number of Instances"),
        AttributeDef::get(4, DataType::Unsized, "Optional Attribute List"),
        AttributeDef::get(5, DataType::Unsized, "Optional Service List"),
        AttributeDef::get(6, DataType::Uint, "Maximum ID Number Class Attributes"),
        AttributeDef::get(7, DataType::Uint, "Maximum ID Number Instance Attributes"),
    ],
    get_all: &[1, 2, 3, 4, 5, 6, 7],
    optional_attributes: &[],
};

/// Instance 0 of a class: the values of [`CLASS_LEVEL`].
struct ClassLevel {
    def: ClassDef,
    max_instance: u32,
    instances: u32,
    /// Attribute 5 after the attribute lists.
    services: &'static [u8],
}

impl Object for ClassLevel {
    fn class(&self) -> &ClassDef {
        &CLASS_LEVEL
    }
    fn get(&mut self, _instance: u32, attr: &AttributeDef, w: &mut Writer<'_>) -> CipResult {
        let uint = |v: u32| u16::try_from(v).unwrap_or(u16::MAX);
        match attr.id {
            1 => w.u16(self.def.revision)?,
            2 => w.u16(uint(self.max_instance))?,
            3 => w.u16(uint(self.instances))?,
            4 => {
                let list = self.def.optional_attributes;
                w.u16(uint(list.len() as u32))?;
                for a in list {
                    w.u16(*a)?;
                }
            }
            5 => {
                let lists = [service::GET_ATTRIBUTE_LIST, service::SET_ATTRIBUTE_LIST];
                w.u16(uint(lists.len().saturating_add(self.services.len()) as u32))?;
                for s in lists.iter().chain(self.services) {
                    w.u16(u16::from(*s))?;
                }
            }
            6 => w.u16(7)?,
            7 => w.u16(self.def.max_attribute())?,
            _ => return Err(unsupported()),
        }
        Ok(())
    }
}
