//! Adapters on the kernel's TCP/IP stack (`--bind A.B.C.D`, or a fleet from a device list):
//! the same sans-IO [`Adapter`] as on a TAP, driven from kernel sockets by one
//! single-threaded event loop, one [`node::Node`] per device at its own address.
//!
//! Each wake-up of a node does what became ready on its sockets and what is due (the
//! device's clock, T->O production, delayed ListIdentity replies, TCP deadlines); the loop
//! ([`fleet`]) waits in one `epoll` ([`poll`]) until a socket is ready or the next node's
//! deadline. Sockets are non-blocking; datagrams are received into one buffer and built into
//! another, both allocated once for the whole loop; nothing is allocated per Class 1 cycle.
//! Files: [`tcp`] (sessions on 44818), [`udp`] (UDP 44818), [`io`] (Class 1 on 2222),
//! [`netif`] (the interface's configuration).

#[cfg(feature = "tls")]
mod csr;
mod fleet;
mod io;
mod link;
mod netif;
mod node;
mod poll;
mod session;
mod socket;
mod tcp;
#[cfg(feature = "tls")]
pub(crate) mod tls;
mod udp;

use std::process::exit;

use enip_stack::Device;

use crate::netlink::Watch;
use fleet::Fleet;
use node::Node;
pub use node::Spec;

/// Bytes of each datagram buffer: a whole Ethernet payload.
const DATAGRAM_LEN: usize = 1536;

/// Runs every device of `specs` on the kernel's sockets at its address, on this thread, until
/// SIGINT or SIGTERM; a start-up error of any (no interface with its address, a port in use)
/// is printed, prefixed by the device's label, and exits 1.
pub fn run<D: Device>(specs: Vec<Spec<D>>, program: &str) -> ! {
    let fail = |label: Option<&str>, e: String| -> ! {
        match label {
            Some(label) => eprintln!("{program}: {label}: {e}"),
            None => eprintln!("{program}: {e}"),
        }
        exit(1)
    };
    // Subscribed before the first read, so no change after it goes unnoticed (a veth's
    // carrier comes up a moment after the link is set up).
    let watch =
        Watch::open().unwrap_or_else(|e| fail(None, format!("cannot watch interfaces: {e}")));
    let mut nodes = Vec::with_capacity(specs.len());
    for spec in specs {
        let label = spec.label;
        crate::device_log::set_current(label);
        let node = Node::open(spec).unwrap_or_else(|e| fail(label, e));
        match label {
            Some(label) => eprintln!("{program}: {label}: {}", node.listening()),
            None => eprintln!("{program}: {}", node.listening()),
        }
        nodes.push(node);
    }
    crate::device_log::set_current(None);
    let fleet = Fleet::new(nodes, watch)
        .unwrap_or_else(|e| fail(None, format!("cannot wait for sockets: {e}")));
    let e = fleet.run();
    fail(None, format!("waiting for sockets: {e}"))
}
