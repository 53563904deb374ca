//! [`InputChanges`]: the input assemblies a device says have new data.

use crate::config::MAX_CHANGED_INPUTS;

/// Input assembly instances with new data since the stack last looked
/// ([`crate::Device::input_changes`]). The stack triggers change-of-state and
/// application-triggered production of each, within the production inhibit time, and clears
/// the set.
///
/// A device keeps one, marks it where its inputs change and lends it when asked:
///
/// ```
/// use enip_stack::device::InputChanges;
///
/// let mut changes = InputChanges::new();
/// changes.mark(100);
/// changes.mark(100);
/// changes.mark(101);
/// assert_eq!(changes.iter().collect::<Vec<_>>(), [100, 101]);
/// changes.clear();
/// assert!(changes.is_empty());
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct InputChanges {
    instances: heapless::Vec<u16, MAX_CHANGED_INPUTS>,
    all: bool,
}

impl InputChanges {
    /// Nothing changed.
    pub const fn new() -> Self {
        InputChanges {
            instances: heapless::Vec::new(),
            all: false,
        }
    }
    /// Input assembly `instance` has new data. More distinct instances than
    /// [`MAX_CHANGED_INPUTS`] count as "every input changed".
    pub fn mark(&mut self, instance: u16) {
        if !self.all
            && !self.instances.contains(&instance)
            && self.instances.push(instance).is_err()
        {
            self.all = true;
        }
    }
    /// Every input assembly has new data.
    pub fn mark_all(&mut self) {
        self.all = true;
    }
    /// Forgets every mark (the stack does, once it has triggered them).
    pub fn clear(&mut self) {
        self.instances.clear();
        self.all = false;
    }
    /// True if nothing changed.
    pub fn is_empty(&self) -> bool {
        !self.all && self.instances.is_empty()
    }
    /// True if every input assembly is to be treated as changed.
    pub fn all(&self) -> bool {
        self.all
    }
    /// The instances marked one by one (all of them, unless [`InputChanges::all`]).
    pub fn iter(&self) -> impl Iterator<Item = u16> + '_ {
        self.instances.iter().copied()
    }
}
