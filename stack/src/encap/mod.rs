//! Encapsulation sessions: one per TCP socket, framing across segments, and the delayed
//! ListIdentity replies to broadcast requests. The commands a session carries are answered
//! by the [`crate::Adapter`] (`adapter/encap.rs`).

pub mod list_identity;
pub mod session;
