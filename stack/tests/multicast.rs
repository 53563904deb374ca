//! Multicast T->O shared by several connections (CIP Vol 1, 3-5.5.2): a connection asking
//! for the multicast data of a producing point already produced to the group joins that
//! production (same T->O connection ID, one stream) when its T->O parameters match, and is
//! refused with the "mismatched" extended status when they do not; the production outlives
//! the connection that started it while another non-listen-only connection shares it, and
//! listen-only connections go only with the last one.

mod common;

use common::*;
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, ForwardOpenRepr, NetworkParams};

/// Multicast T->O of 32 bytes, scheduled priority, fixed size.
const T_O_MULTICAST: u16 = 0x2800 | 34;
/// A heartbeat O->T (sequence count only), point to point.
const HEARTBEAT: u16 = 0x4800 | 2;

fn owner(serial: u16, path: &[u8], rpi: u32) -> ForwardOpenRepr<'_> {
    let mut f = fo(serial, path, rpi);
    f.t_o_params = NetworkParams::from_u16(T_O_MULTICAST);
    f
}

fn heartbeat(serial: u16, path: &[u8], rpi: u32) -> ForwardOpenRepr<'_> {
    let mut f = owner(serial, path, rpi);
    f.o_t_params = NetworkParams::from_u16(HEARTBEAT);
    f
}

/// Opens `f`: its T->O connection ID, or the general status and words of the refusal.
fn open(h: &mut Harness, f: &ForwardOpenRepr<'_>) -> Result<u32, (u8, Vec<u16>)> {
    match status(&h.forward_open(f)) {
        (0, _, data) => Ok(ForwardOpenReplyRepr::parse(&data)
            .unwrap()
            .t_o_connection_id),
        (g, words, _) => Err((g, words)),
    }
}

/// The T->O connection IDs of the datagrams due over the next `ms` milliseconds.
fn produced(h: &mut Harness, ms: u64) -> Vec<u32> {
    let mut ids = Vec::new();
    let end = h.now.0 + ms * 1000;
    while h.now.0 < end {
        while let Some(due) = h.adapter.io_due(h.now) {
            let mut out = vec![0u8; due.max_len];
            let n = h.adapter.write_io(due, h.now, Some(&mut out));
            assert!(n > 0);
            // Sequenced address item: the connection ID follows the CPF count and item header.
            ids.push(u32::from_le_bytes(out[6..10].try_into().unwrap()));
        }
        h.now.0 += 500;
    }
    ids
}

#[test]
fn a_second_multicast_connection_joins_the_production() {
    let mut h = Harness::new();
    let owner_path = io_path(None, 110, 100, None);
    let input_only = io_path(None, 152, 100, None);
    let t_o = open(&mut h, &owner(1, &owner_path, 10_000)).unwrap();
    assert_eq!(open(&mut h, &heartbeat(2, &input_only, 10_000)), Ok(t_o));
    let producers = h.adapter.connections().iter();
    assert_eq!(producers.filter(|(_, c)| c.producer().is_some()).count(), 1);
    // One stream to the group: every 10 ms, one datagram.
    let ids = produced(&mut h, 50);
    assert!(
        ids.len() <= 6 && ids.iter().all(|&id| id == t_o),
        "{ids:x?}"
    );
}

#[test]
fn the_production_outlives_its_first_connection_while_another_shares_it() {
    let mut h = Harness::new();
    let owner_path = io_path(None, 110, 100, None);
    let input_only = io_path(None, 152, 100, None);
    let listen_only = io_path(None, 153, 100, None);
    let t_o = open(&mut h, &owner(1, &owner_path, 10_000)).unwrap();
    assert_eq!(open(&mut h, &heartbeat(2, &input_only, 10_000)), Ok(t_o));
    assert_eq!(open(&mut h, &heartbeat(3, &listen_only, 10_000)), Ok(t_o));
    produced(&mut h, 25);

    // The owner goes; the input-only and the listener stay, and the data goes on as before.
    assert_eq!(close(&mut h, 1).0, 0);
    assert_eq!(h.adapter.connections().len(), 2);
    let ids = produced(&mut h, 50);
    assert!((4..=6).contains(&ids.len()), "{ids:x?}");
    assert!(ids.iter().all(|&id| id == t_o), "{ids:x?}");

    // The last connection that is not listen-only goes: the listener goes with it.
    assert_eq!(close(&mut h, 2).0, 0);
    assert!(h.adapter.connections().is_empty());
    assert_eq!(produced(&mut h, 30), Vec::<u32>::new());
}

#[test]
fn a_join_with_other_t_o_parameters_is_refused_with_the_mismatch() {
    let mut h = Harness::new();
    let owner_path = io_path(None, 110, 100, None);
    let listen_only = io_path(None, 153, 100, None);
    open(&mut h, &owner(1, &owner_path, 10_000)).unwrap();

    // Another T->O RPI: 0x0112 with the required one (type 4) for T->O.
    let mut f = heartbeat(2, &listen_only, 10_000);
    f.t_o_rpi = 20_000;
    assert_eq!(
        open(&mut h, &f),
        Err((1, vec![0x0112, 0x0400, 10_000, 0, 10_000, 0]))
    );
    let mut f = heartbeat(3, &listen_only, 10_000);
    f.t_o_params = NetworkParams::from_u16(T_O_MULTICAST | 0x0200);
    assert_eq!(open(&mut h, &f), Err((1, vec![0x0135])), "fixed/variable");
    let mut f = heartbeat(4, &listen_only, 10_000);
    f.t_o_params = NetworkParams::from_u16(T_O_MULTICAST & !0x0C00);
    assert_eq!(open(&mut h, &f), Err((1, vec![0x0136])), "priority");
    let mut f = heartbeat(5, &listen_only, 10_000);
    f.transport = 0x11;
    assert_eq!(open(&mut h, &f), Err((1, vec![0x0138])), "trigger");
    // An input-only connection is held to the same rules.
    let input_only = io_path(None, 152, 100, None);
    let mut f = heartbeat(6, &input_only, 10_000);
    f.t_o_rpi = 5_000;
    assert_eq!(
        open(&mut h, &f),
        Err((1, vec![0x0112, 0x0400, 10_000, 0, 10_000, 0]))
    );
    assert_eq!(h.adapter.connections().len(), 1);
}

#[test]
fn a_join_of_a_triggered_production_must_match_its_inhibit_time() {
    let mut h = Harness::new();
    let mut owner_path = io_path(None, 110, 100, None);
    owner_path.extend_from_slice(&[0x43, 2]);
    let mut f = owner(1, &owner_path, 10_000);
    f.transport = 0x11;
    let t_o = open(&mut h, &f).unwrap();
    let mut listen_only = io_path(None, 153, 100, None);
    listen_only.extend_from_slice(&[0x43, 3]);
    let mut f = heartbeat(2, &listen_only, 10_000);
    f.transport = 0x11;
    assert_eq!(open(&mut h, &f), Err((1, vec![0x0139])));
    let listen_only = &mut listen_only;
    let at = listen_only.len() - 1;
    listen_only[at] = 2;
    let mut f = heartbeat(3, listen_only, 10_000);
    f.transport = 0x11;
    assert_eq!(open(&mut h, &f), Ok(t_o));
}

/// [`TestDevice`] noting the inhibit time of each Forward_Open it is asked to admit.
struct Inhibits {
    inner: TestDevice,
    seen: Vec<enip_stack::Duration>,
}

impl enip_stack::device::Front for Inhibits {
    type Inner = TestDevice;
    fn inner(&self) -> &TestDevice {
        &self.inner
    }
    fn inner_mut(&mut self) -> &mut TestDevice {
        &mut self.inner
    }
    fn front_admit(
        &mut self,
        request: &enip_stack::device::OpenRequest<'_>,
    ) -> enip_stack::cip::CipResult {
        self.seen.push(request.inhibit);
        enip_stack::Device::admit(&mut self.inner, request)
    }
}

#[test]
fn a_joining_connection_is_admitted_with_the_inhibit_time_it_asked_for() {
    let mut h = Harness::with_device(Inhibits {
        inner: TestDevice::new(),
        seen: Vec::new(),
    });
    let mut owner_path = io_path(None, 110, 100, None);
    owner_path.extend_from_slice(&[0x43, 2]);
    let mut f = owner(1, &owner_path, 10_000);
    f.transport = 0x11;
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    let t_o = ForwardOpenReplyRepr::parse(&data)
        .unwrap()
        .t_o_connection_id;
    let mut input_only = io_path(None, 152, 100, None);
    input_only.extend_from_slice(&[0x43, 2]);
    let mut f = heartbeat(2, &input_only, 10_000);
    f.transport = 0x11;
    let (g, _, data) = status(&h.forward_open(&f));
    assert_eq!(g, 0);
    assert_eq!(
        ForwardOpenReplyRepr::parse(&data)
            .unwrap()
            .t_o_connection_id,
        t_o
    );
    // Both asked for 2 ms (the second must, to join): the device hears 2 ms both times.
    let two = enip_stack::Duration::from_millis(2);
    assert_eq!(h.adapter.device().seen, [two, two]);
}
