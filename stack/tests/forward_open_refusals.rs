//! Forward_Open's finer refusals and their replies: an O->T redundant owner, configuration
//! data (its size in words, an odd size's pad byte, a configuration another connection
//! names), a heartbeat's size, and a request whose data does not parse.

mod common;

use common::*;
use enip_stack::wire::forward_open::NetworkParams;
use enip_stack::wire::Writer;

#[test]
fn a_heartbeat_of_size_0_is_refused_0x0127() {
    // A Class 1 datagram always carries its sequence count: 2, or 6 with a run/idle header.
    let mut h = Harness::new();
    let path = io_path(None, 152, 101, None);
    let mut f = fo(3, &path, 1_000);
    f.o_t_params = NetworkParams::from_u16(0x4800);
    assert_eq!(open(&mut h, &f).1, vec![0x0127, 2]);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 6);
    assert_eq!(open(&mut h, &f).0, 0);
}

#[test]
fn a_redundant_owner_is_refused_0x0125() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut f = fo(1, &path, 10_000);
    f.o_t_params.redundant_owner = true;
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0125)));
    assert_eq!(h.adapter.connections().len(), 0);
}

#[test]
fn a_configuration_in_use_may_be_repeated_not_changed() {
    let mut h = Harness::new();
    let owner = io_path(Some(151), 110, 100, Some(&[1; 10]));
    assert_eq!(open(&mut h, &fo(1, &owner, 10_000)).0, 0);
    // An input-only connection naming the same configuration with other data: 0x0106, and
    // the owner's configuration stays.
    let other = io_path(Some(151), 152, 101, Some(&[2; 10]));
    let mut f = fo(2, &other, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(ext_of(&mut h, &f), (0x01, Some(0x0106)));
    assert_eq!(h.adapter.device().data[&151], vec![1; 10]);
    // The same data, or none: opened.
    let same = io_path(Some(151), 152, 101, Some(&[1; 10]));
    let mut f = fo(3, &same, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(open(&mut h, &f).0, 0);
    let none = io_path(Some(151), 152, 102, None);
    let mut f = fo(4, &none, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(open(&mut h, &f).0, 0);
    // Once no connection names it, a new one configures the device again.
    for serial in [1, 3, 4] {
        assert_eq!(close(&mut h, serial).0, 0);
    }
    let mut f = fo(5, &other, 10_000);
    f.o_t_params = NetworkParams::from_u16(0x4800 | 2);
    assert_eq!(open(&mut h, &f).0, 0);
    assert_eq!(h.adapter.device().data[&151], vec![2; 10]);
}

#[test]
fn an_odd_sized_configuration_comes_with_a_pad_byte_the_device_does_not_see() {
    let mut h = Harness::new();
    let config = h
        .adapter
        .device_mut()
        .assemblies
        .iter_mut()
        .find(|a| a.instance == 151)
        .unwrap();
    config.size = 5;
    // Its data segment counts words: 3 words, the last byte a pad.
    let path = io_path(Some(151), 110, 100, Some(&[1, 2, 3, 4, 5, 0]));
    assert_eq!(open(&mut h, &fo(1, &path, 10_000)).0, 0);
    assert_eq!(h.adapter.device().data[&151], vec![1, 2, 3, 4, 5]);
    // Two words or four: 0x0126 with the size in words.
    let path = io_path(Some(151), 110, 101, Some(&[1, 2, 3, 4]));
    assert_eq!(open(&mut h, &fo(2, &path, 10_000)).1, vec![0x0126, 3]);
}

#[test]
fn a_forward_open_that_does_not_parse_still_names_its_triad() {
    let mut h = Harness::new();
    let path = io_path(None, 110, 100, None);
    let mut data = [0u8; 128];
    let mut w = Writer::new(&mut data);
    fo(9, &path, 10_000).emit(&mut w).unwrap();
    let n = w.len();
    let triad = [9, 0, 0x37, 0x13, 0xEE, 0xFF, 0xC0, 0];
    // Two bytes past the path: too much data, with the failure reply's body.
    let long = [&data[..n], &[0, 0][..]].concat();
    let (g, words, body) = status(&h.request(0x54, &cm_path(), &long));
    assert_eq!((g, words), (0x15, vec![]));
    assert_eq!(body, [&triad[..], &[0, 0][..]].concat());
    // Cut in the path: not enough data, the same body.
    let (g, _, body) = status(&h.request(0x54, &cm_path(), &data[..n - 2]));
    assert_eq!((g, body), (0x13, [&triad[..], &[0, 0][..]].concat()));
    // Cut before the triad ends: nothing to name.
    let (g, _, body) = status(&h.request(0x54, &cm_path(), &data[..17]));
    assert_eq!((g, body), (0x13, vec![]));
    // A Forward_Close too.
    let (g, _, body) = status(&h.request(
        0x4E,
        &cm_path(),
        &[0x0A, 0x0E, 9, 0, 0x37, 0x13, 0xEE, 0xFF, 0xC0, 0, 1],
    ));
    assert_eq!((g, body), (0x13, [&triad[..], &[0, 0][..]].concat()));
}
