//! Encapsulation: sessions on TCP sockets, framing across segments, command handling,
//! and the delayed ListIdentity replies to broadcast requests.

pub mod commands;
pub mod list_identity;
pub mod session;
