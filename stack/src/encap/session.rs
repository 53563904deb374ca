//! The session table: one slot per TCP socket, with its frame reassembly buffer.

use core::net::SocketAddrV4;

use crate::config::{MAX_ENCAP_DATA, MAX_ENCAP_FRAME, MAX_SESSIONS};
use crate::time::Instant;
use crate::wire::encap::{EncapRepr, HEADER_LEN};

/// How much of the current frame the slot still lacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// This many more bytes.
    Bytes(usize),
    /// The frame is complete; its header, parsed once for whoever handles it.
    Complete(EncapRepr),
    /// The header declares more data than the stack accepts.
    TooLong,
}

/// One TCP socket's encapsulation state.
#[derive(Debug, Clone)]
pub struct Slot {
    /// The peer, while a TCP connection is open on this socket.
    pub peer: Option<SocketAddrV4>,
    /// The registered session handle, if any.
    pub handle: Option<u32>,
    /// Bytes of a frame received so far.
    pub rx: heapless::Vec<u8, MAX_ENCAP_FRAME>,
    /// Last time a byte arrived.
    pub last_activity: Instant,
}

impl Slot {
    const fn new() -> Self {
        Slot {
            peer: None,
            handle: None,
            rx: heapless::Vec::new(),
            last_activity: Instant(0),
        }
    }

    /// What the frame being reassembled still needs.
    pub fn need(&self) -> Need {
        frame_need(&self.rx)
    }
}

/// What a frame whose first bytes are `rx` still needs.
pub fn frame_need(rx: &[u8]) -> Need {
    if rx.len() < HEADER_LEN {
        return Need::Bytes(HEADER_LEN.saturating_sub(rx.len()));
    }
    let Ok(header) = EncapRepr::parse_header(rx) else {
        return Need::Bytes(HEADER_LEN.saturating_sub(rx.len()));
    };
    let length = usize::from(header.length);
    if length > MAX_ENCAP_DATA {
        return Need::TooLong;
    }
    match (HEADER_LEN + length).checked_sub(rx.len()) {
        Some(0) | None => Need::Complete(header),
        Some(n) => Need::Bytes(n),
    }
}

/// All session slots.
#[derive(Debug, Clone)]
pub struct Sessions {
    slots: [Slot; MAX_SESSIONS],
    next_handle: u32,
}

impl Sessions {
    /// Every slot free; handles start from `seed`.
    pub fn new(seed: u32) -> Self {
        Sessions {
            slots: [const { Slot::new() }; MAX_SESSIONS],
            next_handle: seed,
        }
    }
    /// The slot of socket `index`.
    pub fn get(&self, index: usize) -> Option<&Slot> {
        self.slots.get(index)
    }
    /// The slot of socket `index`, mutably.
    pub fn get_mut(&mut self, index: usize) -> Option<&mut Slot> {
        self.slots.get_mut(index)
    }
    /// A fresh non-zero handle that no slot uses; the socket index is in the low byte.
    pub fn new_handle(&mut self, index: usize) -> u32 {
        loop {
            self.next_handle = self.next_handle.wrapping_add(0x100);
            let h = (self.next_handle & !0xFF) | (index as u32).wrapping_add(1);
            if h != 0 && !self.slots.iter().any(|s| s.handle == Some(h)) {
                return h;
            }
        }
    }
    /// Resets socket `index` to a fresh connection from `peer` (or to free, with `None`).
    pub fn reset(&mut self, index: usize, peer: Option<SocketAddrV4>, now: Instant) {
        if let Some(s) = self.slots.get_mut(index) {
            *s = Slot::new();
            s.peer = peer;
            s.last_activity = now;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn need_counts_header_then_data() {
        let mut h = [0u8; 30];
        h[2] = 6;
        assert_eq!(frame_need(&h[..10]), Need::Bytes(14));
        assert_eq!(frame_need(&h[..24]), Need::Bytes(6));
        assert!(matches!(frame_need(&h[..30]), Need::Complete(_)));
        h[2] = 0xFF;
        h[3] = 0xFF;
        assert_eq!(frame_need(&h[..24]), Need::TooLong);
    }

    #[test]
    fn handles_unique_and_nonzero() {
        let mut s = Sessions::new(u32::MAX - 0x100);
        let a = s.new_handle(0);
        s.get_mut(0).unwrap().handle = Some(a);
        let b = s.new_handle(1);
        assert!(a != 0 && b != 0 && a != b);
        assert_eq!(b & 0xFF, 2);
    }
}
