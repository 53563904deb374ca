//! Clean exit on SIGINT and SIGTERM: the program is told first (it sends the LLDP shutdown
//! frame on the TAP board), and exits 0 on its own or after [`GRACE`].

use std::io::Write;
use std::os::unix::net::UnixStream;
use std::time::Duration;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// How long the program may take to stop on its own once told.
const GRACE: Duration = Duration::from_millis(500);

/// Starts a thread that exits the process with status 0 on SIGINT or SIGTERM. With `tell`,
/// it first writes a byte to it (the other end becomes readable) and waits up to [`GRACE`]
/// for the program to exit itself.
pub fn exit_on_termination(tell: Option<UnixStream>) -> std::io::Result<()> {
    let mut signals = Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                log::info!("signal {signal} received, exiting");
                if let Some(mut tell) = tell {
                    if tell.write_all(&[1]).is_ok() {
                        std::thread::sleep(GRACE);
                    }
                }
                std::process::exit(0);
            }
        })?;
    Ok(())
}
