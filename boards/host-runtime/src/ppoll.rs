//! [`ppoll`]: the one wait on descriptors of the host's loops (this crate's executor and
//! `enip-host --bind`'s kernel-socket loop).

use std::io;
use std::time::Duration;

/// Waits until a descriptor of `fds` is ready or `timeout` passes (`None`: no timeout);
/// returns how many are ready, 0 on a timeout or when a signal ended the wait.
pub fn ppoll(fds: &mut [libc::pollfd], timeout: Option<Duration>) -> io::Result<usize> {
    let ts = timeout.map(|t| libc::timespec {
        tv_sec: libc::time_t::try_from(t.as_secs()).unwrap_or(libc::time_t::MAX),
        tv_nsec: t.subsec_nanos() as libc::c_long,
    });
    let ts_ptr = ts.as_ref().map_or(std::ptr::null(), |t| t as *const _);
    // SAFETY: `fds` is a valid, exclusively borrowed array of `fds.len()` pollfd entries and
    // `ts_ptr` is null or points to a timespec that outlives the call; a null signal mask
    // leaves the mask unchanged.
    let n = unsafe {
        libc::ppoll(
            fds.as_mut_ptr(),
            fds.len() as libc::nfds_t,
            ts_ptr,
            std::ptr::null(),
        )
    };
    match usize::try_from(n) {
        Ok(n) => Ok(n),
        Err(_) => {
            let e = io::Error::last_os_error();
            if e.kind() == io::ErrorKind::Interrupted {
                fds.iter_mut().for_each(|f| f.revents = 0);
                Ok(0)
            } else {
                Err(e)
            }
        }
    }
}
