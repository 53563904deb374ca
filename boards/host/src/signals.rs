//! Clean exit on SIGINT and SIGTERM.

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Starts a thread that exits the process with status 0 on SIGINT or SIGTERM.
pub fn exit_on_termination() -> std::io::Result<()> {
    let mut signals = Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                log::info!("signal {signal} received, exiting");
                std::process::exit(0);
            }
        })?;
    Ok(())
}
