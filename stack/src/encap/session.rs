//! The session table: one slot per TCP socket, each framing its socket's byte stream into
//! encapsulation frames ([`Framer::feed`]).

use core::net::SocketAddrV4;

use crate::time::Instant;
use crate::wire::encap::{EncapRepr, HEADER_LEN};

/// What [`Framer::feed`] made of the bytes it was given.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feed<'a> {
    /// A whole frame: its header, parsed once for whoever answers it, and its bytes. They are
    /// borrowed from the input when the frame stood whole at its front with nothing buffered
    /// (no copy), else from the framer's buffer. `consumed` bytes of the input were used.
    Frame {
        /// The frame's header.
        header: EncapRepr,
        /// The whole frame, header included.
        frame: &'a [u8],
        /// Bytes of the input used.
        consumed: usize,
    },
    /// The frame is not complete yet: all of the input is buffered.
    Buffered,
    /// `consumed` bytes of the input were the rest of a frame too long to take, skipped:
    /// give what follows them to the next call.
    Skipped {
        /// Bytes of the input used.
        consumed: usize,
    },
    /// The header declares more data than the stack accepts (a frame longer than the
    /// framer's `F` bytes): nothing is buffered, and its data is skipped as it arrives, up
    /// to the next frame. `consumed` bytes of the input were used (the rest of the header,
    /// and what came of the data).
    TooLong {
        /// The frame's header.
        header: EncapRepr,
        /// Bytes of the input used.
        consumed: usize,
    },
}

/// Reassembles encapsulation frames of at most `F` bytes from one TCP byte stream.
#[derive(Debug, Clone)]
pub struct Framer<const F: usize> {
    /// The first bytes of a frame that arrived split across segments.
    buf: heapless::Vec<u8, F>,
    /// `buf` holds a whole frame already handed out: it is dropped at the next feed.
    handed_out: bool,
    /// Bytes of a frame too long to take still to come: they are skipped.
    skip: usize,
}

impl<const F: usize> Framer<F> {
    const fn new() -> Self {
        Framer {
            buf: heapless::Vec::new(),
            handed_out: false,
            skip: 0,
        }
    }

    /// Feeds bytes received in order: returns the next whole frame, if they complete one, and
    /// buffers what is left of an incomplete one. At most one frame per call: give the rest
    /// of the input (after `consumed`) to the next call. The frame borrowed from the buffer
    /// stays valid until then.
    pub fn feed<'a>(&'a mut self, data: &'a [u8]) -> Feed<'a> {
        if self.handed_out {
            self.buf.clear();
            self.handed_out = false;
        }
        if self.skip > 0 {
            return Feed::Skipped {
                consumed: self.skip(data.len()),
            };
        }
        self.frame_from(data)
    }

    /// [`Self::feed`] while the rest of a frame too long to take is still to come: that
    /// is skipped first, alone, as much as `available` bytes of input hold of it; returns
    /// how many. Out of line: the request path pays one comparison.
    #[cold]
    #[inline(never)]
    fn skip(&mut self, available: usize) -> usize {
        let skipped = self.skip.min(available);
        self.skip = self.skip.saturating_sub(skipped);
        skipped
    }

    /// [`Self::feed`] once nothing is left to skip: `data` starts a frame or continues the
    /// one buffered.
    #[inline(always)]
    fn frame_from<'a>(&'a mut self, data: &'a [u8]) -> Feed<'a> {
        if self.buf.is_empty() {
            if let Ok(header) = EncapRepr::parse_header(data) {
                match accepted::<F>(header) {
                    Ok(len) if data.len() >= len => {
                        return Feed::Frame {
                            header,
                            frame: data.get(..len).unwrap_or(&[]),
                            consumed: len,
                        }
                    }
                    Ok(_) => {}
                    Err(header) => {
                        let consumed = self.too_long(header, data.len(), HEADER_LEN);
                        return Feed::TooLong { header, consumed };
                    }
                }
            }
            // Cannot fail: shorter than the frame it starts, which fits the buffer.
            let _ = self.buf.extend_from_slice(data);
            return Feed::Buffered;
        }
        // The header first, then as much of the data as it declares.
        let mut consumed = self.take(data, HEADER_LEN);
        let Ok(header) = EncapRepr::parse_header(&self.buf) else {
            return Feed::Buffered;
        };
        let len = match accepted::<F>(header) {
            Ok(len) => len,
            Err(header) => {
                self.buf.clear();
                let consumed = self.too_long(header, data.len(), consumed);
                return Feed::TooLong { header, consumed };
            }
        };
        let rest = data.get(consumed..).unwrap_or(&[]);
        consumed = consumed.saturating_add(self.take(rest, len));
        if self.buf.len() < len {
            return Feed::Buffered;
        }
        self.handed_out = true;
        Feed::Frame {
            header,
            frame: &self.buf,
            consumed,
        }
    }

    /// The frame `header` starts is too long: of `available` bytes of input, `header_end`
    /// ended its header; its data is skipped, this input's part of it now. Returns the input
    /// used.
    #[cold]
    #[inline(never)]
    fn too_long(&mut self, header: EncapRepr, available: usize, header_end: usize) -> usize {
        let data_here = available.saturating_sub(header_end);
        let length = usize::from(header.length);
        let skipped = data_here.min(length);
        self.skip = length.saturating_sub(skipped);
        header_end.saturating_add(skipped)
    }

    /// Moves bytes from the front of `data` into the buffer until it holds `upto` bytes;
    /// returns how many it moved.
    fn take(&mut self, data: &[u8], upto: usize) -> usize {
        let n = upto.saturating_sub(self.buf.len()).min(data.len());
        // Cannot fail: `upto` is at most a frame, which fits the buffer.
        let _ = self.buf.extend_from_slice(data.get(..n).unwrap_or(&[]));
        n
    }
}

/// The length of the frame `header` starts (at most `F`), or the header back if it declares
/// more data than the stack accepts.
fn accepted<const F: usize>(header: EncapRepr) -> Result<usize, EncapRepr> {
    if usize::from(header.length) > F.saturating_sub(HEADER_LEN) {
        return Err(header);
    }
    Ok(HEADER_LEN.saturating_add(usize::from(header.length)))
}

/// One TCP socket's encapsulation state.
#[derive(Debug, Clone)]
pub struct Slot<const F: usize> {
    /// The peer, while a TCP connection is open on this socket.
    pub peer: Option<SocketAddrV4>,
    /// The registered session handle, if any.
    pub handle: Option<u32>,
    /// Last time a byte arrived.
    pub last_activity: Instant,
    /// Frames arriving on the socket.
    framer: Framer<F>,
}

impl<const F: usize> Slot<F> {
    const fn new() -> Self {
        Slot {
            peer: None,
            handle: None,
            last_activity: Instant(0),
            framer: Framer::new(),
        }
    }
}

/// The session a frame arrived on, as the command handling sees it: its own socket's state
/// only, borrowed beside the frame its [`Framer`] holds.
#[derive(Debug)]
pub struct Session<'a> {
    /// The socket's index.
    pub index: usize,
    /// The peer of the TCP connection.
    pub peer: Option<SocketAddrV4>,
    handle: &'a mut Option<u32>,
    next_handle: &'a mut u32,
}

impl Session<'_> {
    /// The registered session handle, if any.
    pub fn handle(&self) -> Option<u32> {
        *self.handle
    }

    /// Registers the session under a fresh handle and returns it. Handles are non-zero and
    /// carry the socket index plus one in their low byte, so no two sockets share one.
    pub fn register(&mut self) -> u32 {
        *self.next_handle = self.next_handle.wrapping_add(0x100);
        let h = (*self.next_handle & !0xFF) | (self.index as u32 & 0xFF).wrapping_add(1);
        *self.handle = Some(h);
        h
    }
}

/// All session slots: `S` sockets, each framing frames of at most `F` bytes.
#[derive(Debug, Clone)]
pub struct Sessions<const S: usize, const F: usize> {
    slots: [Slot<F>; S],
    next_handle: u32,
}

impl<const S: usize, const F: usize> Sessions<S, F> {
    /// Every slot free; handles start from `seed`.
    pub fn new(seed: u32) -> Self {
        const {
            // A handle's low byte is the socket index plus one, never 0; the connection
            // table keeps u8::MAX for "no session".
            assert!(S >= 1 && S < u8::MAX as usize, "1 to 254 sessions");
        };
        Sessions {
            slots: [const { Slot::new() }; S],
            next_handle: seed,
        }
    }
    /// The slot of socket `index`.
    pub fn get(&self, index: usize) -> Option<&Slot<F>> {
        self.slots.get(index)
    }
    /// Feeds bytes received on socket `index` at `now` to its [`Framer`]; returns what it
    /// made of them and the session to answer a frame. `None` if there is no such socket.
    pub fn receive<'a>(
        &'a mut self,
        index: usize,
        data: &'a [u8],
        now: Instant,
    ) -> Option<(Feed<'a>, Session<'a>)> {
        let Slot {
            peer,
            handle,
            last_activity,
            framer,
        } = self.slots.get_mut(index)?;
        *last_activity = now;
        let session = Session {
            index,
            peer: *peer,
            handle,
            next_handle: &mut self.next_handle,
        };
        Some((framer.feed(data), session))
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
    extern crate std;
    use std::{vec, vec::Vec};

    use super::*;
    use crate::config::{MAX_ENCAP_DATA, MAX_ENCAP_FRAME, MAX_SESSIONS};

    /// The framer of the default frame size.
    type Framer = super::Framer<MAX_ENCAP_FRAME>;
    /// The default session table.
    type Sessions = super::Sessions<MAX_SESSIONS, MAX_ENCAP_FRAME>;

    /// A frame with command 0x6F, `len` data bytes numbered from 1 and `context` as its
    /// sender context's first byte.
    fn frame(len: u16, context: u8) -> Vec<u8> {
        let mut f = vec![0u8; HEADER_LEN];
        f[0] = 0x6F;
        f[2..4].copy_from_slice(&len.to_le_bytes());
        f[12] = context;
        f.extend((1..=len).map(|b| b as u8));
        f
    }

    /// Feeds `data` in chunks of `chunk` bytes (each chunk until used); the frames handed out.
    fn run(framer: &mut Framer, data: &[u8], chunk: usize) -> Vec<Vec<u8>> {
        let mut frames = Vec::new();
        for piece in data.chunks(chunk) {
            let mut rest = piece;
            loop {
                match framer.feed(rest) {
                    Feed::Frame {
                        header,
                        frame,
                        consumed,
                    } => {
                        assert!(consumed > 0);
                        assert_eq!(frame.len(), HEADER_LEN + usize::from(header.length));
                        frames.push(frame.to_vec());
                        rest = &rest[consumed..];
                    }
                    Feed::Buffered => break,
                    other => panic!("not a frame: {other:?}"),
                }
            }
        }
        frames
    }

    /// The frame and the input consumed of a [`Feed::Frame`].
    fn whole(feed: Feed<'_>) -> (&[u8], usize) {
        match feed {
            Feed::Frame {
                frame, consumed, ..
            } => (frame, consumed),
            other => panic!("no frame: {other:?}"),
        }
    }

    #[test]
    fn a_whole_frame_at_the_front_is_borrowed_not_copied() {
        let mut f = Framer::new();
        let data = [frame(6, 1), frame(0, 2)].concat();
        let (got, consumed) = whole(f.feed(&data));
        assert_eq!((consumed, got.as_ptr()), (30, data.as_ptr()));
        assert!(f.buf.is_empty());
    }

    #[test]
    fn frames_split_anywhere_come_out_whole() {
        let data = [frame(6, 1), frame(0, 2), frame(1000, 3), frame(4, 4)].concat();
        for chunk in [1, 2, 5, 23, 24, 25, 29, 31, 600, 2000] {
            let frames = run(&mut Framer::new(), &data, chunk);
            assert_eq!(
                frames,
                vec![frame(6, 1), frame(0, 2), frame(1000, 3), frame(4, 4)],
                "chunks of {chunk}"
            );
        }
    }

    #[test]
    fn several_frames_in_one_segment_one_per_call() {
        let mut f = Framer::new();
        // A frame split, then its end and two more in one segment.
        let stream = [frame(6, 1), frame(2, 2), frame(3, 3)].concat();
        assert_eq!(f.feed(&stream[..10]), Feed::Buffered);
        let segment = &stream[10..];
        let (first, consumed) = whole(f.feed(segment));
        assert_eq!((first, consumed), (&frame(6, 1)[..], 20));
        let rest = &segment[consumed..];
        let (second, consumed) = whole(f.feed(rest));
        // The buffer was emptied: the next frame is borrowed from the input.
        assert_eq!((second.as_ptr(), consumed), (rest.as_ptr(), 26));
        assert_eq!(whole(f.feed(&rest[26..])).1, 27);
        assert_eq!(f.feed(&[]), Feed::Buffered);
    }

    #[test]
    fn a_frame_longer_than_capacity_is_refused_with_its_header_and_skipped() {
        let long = frame(MAX_ENCAP_DATA as u16 + 1, 7);
        let at_capacity = frame(MAX_ENCAP_DATA as u16, 8);
        assert_eq!(
            run(&mut Framer::new(), &at_capacity, 100),
            vec![at_capacity.clone()]
        );
        let header = EncapRepr::parse_header(&long).unwrap();
        // The long frame between two others, in pieces of every size: its header comes out
        // once, its data nowhere, the frames around it whole.
        let stream = [frame(6, 1), long.clone(), frame(4, 2), at_capacity.clone()].concat();
        for chunk in [1, 2, 10, 23, 24, 25, 30, 600, 1048, 1049, 1050, 4000] {
            let mut f = Framer::new();
            let mut events = Vec::new();
            for piece in stream.chunks(chunk) {
                let mut rest = piece;
                // Bounded: each call uses at least one byte, or all of them.
                for _ in 0..piece.len() + 1 {
                    if rest.is_empty() {
                        break;
                    }
                    match f.feed(rest) {
                        Feed::Frame {
                            frame, consumed, ..
                        } => {
                            events.push(Ok(frame.to_vec()));
                            rest = &rest[consumed..];
                        }
                        Feed::TooLong { header, consumed } => {
                            assert!(consumed > 0, "chunks of {chunk}");
                            events.push(Err(header));
                            rest = &rest[consumed..];
                        }
                        Feed::Skipped { consumed } => {
                            assert!(consumed > 0, "chunks of {chunk}");
                            rest = &rest[consumed..];
                        }
                        Feed::Buffered => break,
                    }
                }
            }
            assert_eq!(
                events,
                vec![
                    Ok(frame(6, 1)),
                    Err(header),
                    Ok(frame(4, 2)),
                    Ok(at_capacity.clone())
                ],
                "chunks of {chunk}"
            );
            assert_eq!(f.feed(&[]), Feed::Buffered, "chunks of {chunk}");
            assert!(f.buf.is_empty() && f.skip == 0, "chunks of {chunk}");
        }
    }

    #[test]
    fn handles_unique_and_nonzero() {
        let mut s = Sessions::new(u32::MAX - 0x100);
        let (_, mut zero) = s.receive(0, &[], Instant(0)).unwrap();
        let a = zero.register();
        assert_eq!(zero.handle(), Some(a));
        let (_, mut one) = s.receive(1, &[], Instant(0)).unwrap();
        let b = one.register();
        assert!(a != 0 && b != 0 && a != b);
        assert_eq!((a & 0xFF, b & 0xFF), (1, 2));
        assert_eq!(s.get(0).unwrap().handle, Some(a));
    }
}
