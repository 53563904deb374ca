//! LLDP at the frame level: received LLDP frames (ethertype 0x88CC to the nearest-bridge
//! group address) go to the adapter's LLDP Data Table, never to the TCP/IP stack, and the
//! adapter's LLDPDUs go out behind the Ethernet header written here while the link is up.
//! [`LldpPort`] is the adapter's LLDP side as the link task calls it; the schedule (start,
//! msgTxInterval, changes, turning LLDP off) is the stack's
//! ([`enip_stack::objects::LldpState`]). [`shutdown`] sends the shutdown LLDPDU for a runtime
//! that is about to stop.

use core::future::poll_fn;
use core::task::{Context, Poll};

use embassy_net_driver::{Driver, HardwareAddress, TxToken};

use super::frame::{copy, send_copy};
use enip_stack::adapter::MAX_LLDPDU;
use enip_stack::wire::lldp::{ETHERTYPE, MULTICAST_MAC};
use enip_stack::Instant;

/// Ethernet header: destination, source, ethertype.
const HEADER_LEN: usize = 14;
/// The shortest Ethernet frame without its CRC; shorter ones are padded with zeros.
const MIN_FRAME: usize = 60;
/// The largest LLDP frame the adapter sends.
const FRAME_MAX: usize = HEADER_LEN + MAX_LLDPDU;

/// The adapter's LLDP calls the link task makes; implemented by [`crate::SharedAdapter`].
pub trait LldpPort {
    /// Feeds a received LLDPDU (`Adapter::lldp_receive`).
    fn lldp_receive(&self, lldpdu: &[u8], now: Instant);
    /// Writes the LLDPDU due at `now` into `out`; its length, 0 if none
    /// (`Adapter::lldp_transmit`).
    fn lldp_transmit(&self, now: Instant, out: &mut [u8]) -> usize;
    /// Writes the shutdown LLDPDU into `out`; its length, 0 if LLDP does not transmit
    /// (`Adapter::lldp_shutdown`).
    fn lldp_shutdown(&self, out: &mut [u8]) -> usize;
    /// When an LLDPDU is next due (`Adapter::lldp_deadline`).
    fn lldp_deadline(&self) -> Option<Instant>;
    /// The link came up (`Adapter::lldp_link_up`).
    fn lldp_link_up(&self);
}

/// The LLDPDU of an untagged LLDP frame to the nearest-bridge group address; `None` for any
/// other frame.
pub(crate) fn lldpdu(frame: &[u8]) -> Option<&[u8]> {
    let (header, payload) = frame.split_first_chunk::<HEADER_LEN>()?;
    let (to, rest) = header.split_first_chunk::<6>()?;
    let kind = rest.get(6..)?;
    (*to == MULTICAST_MAC && kind == ETHERTYPE.to_be_bytes()).then_some(payload)
}

/// Sends the LLDPDU due at `at` from `mac` (the link is up); true if one waits for the
/// driver's room (whose wake-up then brings the link task back). `next` is the link task's
/// copy of the adapter's LLDP deadline (`None`: LLDP off), asked for again only when `stale`
/// (the link came up, or the stack sent frames, which may answer a request that changed the
/// LLDP settings or the host name), when it came due, and after a send: the adapter's lock
/// stays off the wake-ups of Class 1.
pub(crate) fn service<D: Driver>(
    cx: &mut Context<'_>,
    driver: &mut D,
    port: &dyn LldpPort,
    mac: [u8; 6],
    at: Instant,
    next: &mut Option<Instant>,
    stale: bool,
) -> bool {
    if stale || next.is_some_and(|d| d <= at) {
        *next = port.lldp_deadline();
    }
    if next.is_none_or(|d| d > at) {
        return false;
    }
    let Some(tx) = driver.transmit(cx) else {
        return true;
    };
    let mut frame = [0u8; FRAME_MAX];
    let len = write_frame(&mut frame, mac, |out| port.lldp_transmit(at, out));
    if let Some(bytes) = frame.get(..len).filter(|b| !b.is_empty()) {
        send_copy(tx, bytes);
    }
    *next = port.lldp_deadline();
    false
}

/// Sends the shutdown LLDPDU (TTL 0) through `driver` if LLDP transmits, waiting for the
/// driver's room: for a runtime about to stop, after its link task (which owns the driver)
/// was stopped. The caller bounds the wait.
pub async fn shutdown<D: Driver>(driver: &mut D, port: &dyn LldpPort) {
    #[allow(unreachable_patterns)] // other media exist only with other driver features
    let mac = match driver.hardware_address() {
        HardwareAddress::Ethernet(mac) => mac,
        _ => return,
    };
    let mut frame = [0u8; FRAME_MAX];
    let len = write_frame(&mut frame, mac, |out| port.lldp_shutdown(out));
    let Some(bytes) = frame.get(..len).filter(|b| !b.is_empty()) else {
        return;
    };
    poll_fn(|cx| match driver.transmit(cx) {
        Some(tx) => {
            tx.consume(bytes.len(), |out| copy(out, bytes));
            Poll::Ready(())
        }
        None => Poll::Pending,
    })
    .await;
}

/// Writes an LLDP frame from `mac` into `frame`: the LLDPDU `lldpdu` writes (returning its
/// length), behind the Ethernet header, padded to the minimum size. Its length, 0 if
/// `lldpdu` wrote nothing.
fn write_frame(
    frame: &mut [u8; FRAME_MAX],
    mac: [u8; 6],
    lldpdu: impl FnOnce(&mut [u8]) -> usize,
) -> usize {
    let (header, payload) = frame.split_at_mut(HEADER_LEN);
    let len = lldpdu(payload);
    if len == 0 {
        return 0;
    }
    if let Some(padding) = payload.get_mut(len..) {
        padding.fill(0);
    }
    let [t0, t1] = ETHERTYPE.to_be_bytes();
    let [d0, d1, d2, d3, d4, d5] = MULTICAST_MAC;
    let [s0, s1, s2, s3, s4, s5] = mac;
    copy(
        header,
        &[d0, d1, d2, d3, d4, d5, s0, s1, s2, s3, s4, s5, t0, t1],
    );
    HEADER_LEN.saturating_add(len).max(MIN_FRAME)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_untagged_lldp_frames_to_the_group_address_are_taken() {
        let mut frame = [0u8; 64];
        frame[..6].copy_from_slice(&MULTICAST_MAC);
        frame[6..12].copy_from_slice(&[2, 0, 0, 0, 0, 9]);
        frame[12..14].copy_from_slice(&[0x88, 0xCC]);
        frame[14] = 0x02;
        let pdu = lldpdu(&frame).unwrap();
        assert_eq!((pdu.len(), pdu[0]), (50, 0x02));
        let mut ipv4 = frame;
        ipv4[12..14].copy_from_slice(&[0x08, 0x00]);
        assert!(lldpdu(&ipv4).is_none());
        let mut unicast = frame;
        unicast[0] = 0x02;
        assert!(lldpdu(&unicast).is_none());
        assert!(lldpdu(&frame[..13]).is_none());
    }

    #[test]
    fn frames_carry_the_header_and_are_padded() {
        let mut frame = [0xFFu8; FRAME_MAX];
        let mac = [2, 0, 0, 0, 0, 7];
        let len = write_frame(&mut frame, mac, |out| {
            out[..4].copy_from_slice(&[0x02, 0x07, 0x04, 0x02]);
            4
        });
        assert_eq!(len, MIN_FRAME);
        assert!(frame[18..MIN_FRAME].iter().all(|b| *b == 0));
        assert_eq!(&frame[..6], &MULTICAST_MAC);
        assert_eq!(&frame[6..12], &mac);
        assert_eq!(&frame[12..18], &[0x88, 0xCC, 0x02, 0x07, 0x04, 0x02]);
        assert_eq!(write_frame(&mut frame, mac, |_| 0), 0);
    }
}
