//! Common Packet Format (alone and after a SendRRData prefix): items cover the buffer exactly,
//! re-emitting them reproduces it, socket address items round-trip.
#![no_main]

use enip_stack::wire::cpf::{item_type, Packet, SockAddrRepr, SOCKADDR_LEN};
use enip_stack::wire::rr_data::{self, RrDataRepr};
use enip_stack::wire::Writer;
use libfuzzer_sys::fuzz_target;

fn check(buf: &[u8]) {
    let Ok(p) = Packet::new_checked(buf) else {
        return;
    };
    let mut out = vec![0u8; buf.len()];
    let mut w = Writer::new(&mut out);
    w.u16(p.item_count()).expect("fits");
    let mut n = 0;
    for item in p.items() {
        n += 1;
        item.emit(&mut w).expect("fits");
        if matches!(
            item.type_id,
            item_type::SOCKADDR_O_T | item_type::SOCKADDR_T_O
        ) {
            if let Ok(s) = SockAddrRepr::parse(item.data) {
                let mut b = [0u8; SOCKADDR_LEN];
                s.emit(&mut Writer::new(&mut b)).expect("fits");
                assert_eq!(SockAddrRepr::parse(&b), Ok(s));
            }
        }
    }
    assert_eq!(n, usize::from(p.item_count()));
    assert_eq!(w.len(), buf.len());
    assert_eq!(&out[..], buf);
    let first = p.items().next();
    if let Some(first) = first {
        assert_eq!(
            p.find(first.type_id).map(|i| i.type_id),
            Some(first.type_id)
        );
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if let Ok(rr) = rr_data::Packet::new_checked(data) {
        let prefix = RrDataRepr::parse(&rr);
        let mut out = [0u8; rr_data::PREFIX_LEN];
        prefix.emit(&mut Writer::new(&mut out)).expect("fits");
        assert_eq!(&out[..], &data[..prefix.buffer_len()]);
        assert_eq!(rr.cpf().len(), data.len() - rr_data::PREFIX_LEN);
        check(rr.cpf());
    }
});
