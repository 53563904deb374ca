//! `enip-host --devices FILE`: the devices of a device list, each a shipped profile with its
//! own store and identity, run on the kernel's sockets by one loop.

use enip_host::{DeviceEntry, DeviceSpec, Renamed};
use enip_profiles::Profile;

use crate::profile_options::{self, ProfileOptions};

/// The devices of the list at `path`, ready to run, or the first error.
pub fn devices(path: &str) -> Result<Vec<DeviceSpec<Renamed<Profile>>>, String> {
    let list = enip_host::read_device_list(path.as_ref())?;
    list.into_iter()
        .map(|entry| spec(entry).map_err(|(name, e)| format!("device {name:?}: {e}")))
        .collect()
}

/// One device of the list; an error comes with its name.
fn spec(entry: DeviceEntry) -> Result<DeviceSpec<Renamed<Profile>>, (String, String)> {
    let fail = |e: String| (entry.name.clone(), e);
    let mut profile = crate::profile(&entry.profile).map_err(fail)?;
    let store = enip_host::own_store(entry.nv_file.as_deref()).map_err(fail)?;
    profile_options::set_up(&mut profile, &ProfileOptions::default(), store);
    let device =
        Renamed::new(profile, entry.serial_number, entry.product_name.as_deref()).map_err(fail)?;
    Ok(DeviceSpec {
        label: Some(Box::leak(entry.name.clone().into_boxed_str())),
        ip: entry.address,
        device,
        store,
        tls: None,
    })
}
