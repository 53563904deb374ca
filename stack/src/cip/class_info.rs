//! Class-level (instance 0) attributes 1-7, shared by every object.

use super::attributes::{read_only_up_to, unsupported, Attributes};
use super::status::CipResult;
use crate::wire::Writer;

/// The class attributes of one object class.
pub(crate) struct ClassInfo {
    /// Attribute 1: object revision.
    pub revision: u16,
    /// Attribute 2: highest instance number.
    pub max_instance: u16,
    /// Attribute 3: number of instances.
    pub instances: u16,
    /// Attribute 4: optional instance attributes implemented.
    pub optional_attributes: &'static [u16],
    /// Attribute 7: highest instance attribute ID.
    pub max_instance_attribute: u16,
}

impl Attributes for ClassInfo {
    fn get(&mut self, id: u16, w: &mut Writer<'_>) -> CipResult {
        match id {
            1 => w.u16(self.revision)?,
            2 => w.u16(self.max_instance)?,
            3 => w.u16(self.instances)?,
            4 => {
                w.u16(self.optional_attributes.len() as u16)?;
                for a in self.optional_attributes {
                    w.u16(*a)?;
                }
            }
            5 => w.u16(0)?,
            6 => w.u16(7)?,
            7 => w.u16(self.max_instance_attribute)?,
            _ => return Err(unsupported()),
        }
        Ok(())
    }
    fn set(&mut self, id: u16, _data: &[u8], _exact: bool) -> CipResult<usize> {
        Err(read_only_up_to(id, 7))
    }
    fn all(&self) -> &'static [u16] {
        &[1, 2, 3, 4, 5, 6, 7]
    }
}
