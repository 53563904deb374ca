//! The adapter's side of Address Conflict Detection: what the runtime that runs
//! [`crate::acd::Acd`] reports, kept where the TCP/IP Interface object reads it, and
//! attribute 11 saved in the non-volatile store.

use super::Adapter;
use crate::acd::{AcdSettings, AcdState, LastConflict};
use crate::device::Device;

impl<
        D: Device,
        const SESSIONS: usize,
        const CONNECTIONS: usize,
        const FRAME: usize,
        const LIST_IDENTITY: usize,
    > Adapter<D, SESSIONS, CONNECTIONS, FRAME, LIST_IDENTITY>
{
    /// Address Conflict Detection as the TCP/IP object reports it.
    pub fn acd(&self) -> &AcdState {
        &self.inner.objects.acd
    }

    /// Whether the runtime should detect conflicts on the address it starts: TCP/IP
    /// attribute 10 as stored (a Set applies at the next start), unless
    /// [`Adapter::skip_acd`] was called.
    pub fn acd_selected(&self) -> bool {
        let acd = &self.inner.objects.acd;
        acd.settings.select && !acd.skipped
    }

    /// No detection in this run whatever attribute 10 says, and nothing stored (a test rig's
    /// `--acd off`: tests that are not about conflicts start without probing's delay).
    pub fn skip_acd(&mut self) {
        self.inner.objects.acd.skipped = true;
    }

    /// The runtime detects conflicts (capability bit 7), whether or not attribute 10 has it
    /// do so in this run.
    pub fn set_acd_capable(&mut self) {
        self.inner.objects.acd.capable = true;
    }

    /// Status bits 6 (a conflict was detected) and 7 (the address is not used because of
    /// one).
    pub fn set_acd_status(&mut self, conflict: bool, fault: bool) {
        let acd = &mut self.inner.objects.acd;
        acd.conflict = conflict;
        acd.fault = fault;
    }

    /// Records `last` as attribute 11 and saves it when its activity or remote MAC differ
    /// from the saved one (so a flood of conflicts from one host cannot wear the flash out;
    /// a store that fails is logged, the attribute still reads the new value).
    pub fn record_acd_conflict(&mut self, last: LastConflict) {
        let acd = &mut self.inner.objects.acd;
        acd.settings.last = last;
        acd.conflict = true;
        let news = (acd.saved.activity, acd.saved.remote_mac) != (last.activity, last.remote_mac);
        let Some(store) = self.inner.store.as_deref_mut() else {
            return;
        };
        if news {
            if acd.settings.save(store).is_ok() {
                acd.saved = last;
            } else {
                warn!("ACD: saving the last conflict failed");
            }
        }
    }

    /// Loads attributes 10 and 11 from the attached store.
    pub(super) fn load_acd(&mut self) {
        let Some(store) = self.inner.store.as_deref_mut() else {
            return;
        };
        let acd = &mut self.inner.objects.acd;
        match AcdSettings::stored(store) {
            Ok(Some(settings)) => {
                acd.settings = settings;
                acd.saved = settings.last;
            }
            Ok(None) => {}
            Err(_) => warn!("ACD settings unreadable: factory defaults"),
        }
    }
}
