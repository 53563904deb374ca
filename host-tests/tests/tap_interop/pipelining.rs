//! Pipelined requests: a client that sends many requests before reading a reply (one
//! segment of 40 ListIdentity or 16 Get_Attributes_All, `peers/pipelined_burst.py`; cpppo
//! 30 requests deep). Requests whose replies outgrow the connection's room wait in the
//! window the board offered, acknowledged, and are answered once the replies before them
//! are: every reply comes, in order, and the client never has to send a segment again (its
//! `tcpi_total_retrans` stays 0; the window offered never shrinks, RFC 9293 3.8.6.2.2). A
//! client whose FIN follows such a burst at once has it acknowledged with the requests, every
//! reply, then the board's FIN, without sending its FIN again. The same on the host board and
//! the emulated one, whose TCP is the same code.

use std::time::Duration;

use serde_json::{json, Value};

use crate::common::{self, NAME};
use host_tests::peers;
use host_tests::rig::{self, Rig, BOARD_IP};

/// Bound for one peer program run.
const PEER_TIMEOUT: Duration = Duration::from_secs(30);

#[test]
#[ignore = "needs root and tshark"]
fn pipelined_requests_are_all_answered_without_retransmission() {
    let rig = common::start("pipelined_requests");
    bursts(&rig);
    cpppo_deep(&rig);
    common::finish(rig);
}

#[test]
#[ignore = "needs root: network namespace, TAP and QEMU"]
fn pipelined_requests_qemu() {
    let Some(elf) = rig::qemu_elf("generic") else {
        return;
    };
    let pcap = common::scratch("pipelined_requests_qemu.pcapng");
    let rig = Rig::start_qemu(&elf, Some(&pcap)).unwrap_or_else(|e| panic!("rig: {e}"));
    bursts(&rig);
    cpppo_deep(&rig);
    rig.finish().expect("the board ran to the end");
}

/// One segment of 40 ListIdentity requests (about 3.6 KiB of replies against the 2 KiB of
/// room), one of 16 Get_Attributes_All of the Identity object, and 40 ListIdentity again
/// with the client's FIN right behind them.
fn bursts(rig: &Rig) {
    for (kind, count, close_after) in [
        ("list_identity", 40, false),
        ("get_attributes_all", 16, false),
        ("list_identity", 40, true),
    ] {
        let input = json!({"host": BOARD_IP.to_string(), "kind": kind, "count": count,
                           "close_after": close_after});
        let out = peers::run(rig.ns(), "pipelined_burst.py", &input, PEER_TIMEOUT)
            .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
        println!("pipelined_burst.py {kind} x {count}: {}", summary(&out));
        assert_eq!(out["replies"], json!(count), "{kind}: {out}");
        assert_eq!(out["in_order"], json!(true), "{kind}: {out}");
        let zero = |key: &str| {
            out[key]
                .as_array()
                .is_some_and(|a| a.iter().all(|s| s == &json!(0)))
        };
        assert!(
            zero("encap_statuses") && zero("cip_statuses"),
            "{kind}: {out}"
        );
        assert_eq!(
            out["retransmissions"],
            json!(0),
            "{kind}: the client had to send requests or its FIN again: {}",
            summary(&out)
        );
        if close_after {
            assert_eq!(
                out["closed"],
                json!(true),
                "{kind}: no FIN after the replies: {out}"
            );
            println!(
                "  the board's FIN {:.1} ms after the burst",
                out["seconds_to_close"].as_f64().unwrap_or(-1.0) * 1e3
            );
        }
    }
}

/// cpppo's proxy reading the product name 60 times with 30 requests outstanding: pipelining
/// from an independent client (it sends each request in a segment of its own, so its
/// replies do not outgrow the room; the bursts above are what needs the receive buffer).
fn cpppo_deep(rig: &Rig) {
    let input = json!({"host": BOARD_IP.to_string(), "depth": 30, "count": 60,
                       "path": "@1/1/7", "type": "SSTRING"});
    let out = peers::run(rig.ns(), "cpppo_pipelined.py", &input, PEER_TIMEOUT)
        .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!(
        "cpppo_pipelined.py: 60 reads 30 deep in {:.3} s, retransmissions {}",
        out["seconds"].as_f64().unwrap_or(-1.0),
        out["retransmissions"]
    );
    let statuses = out["statuses"].as_array().expect("statuses");
    assert_eq!(statuses.len(), 60, "{out}");
    assert!(statuses.iter().all(|s| s == &json!(0)), "{out}");
    let values = out["values"].as_array().expect("values");
    assert!(values.iter().all(|v| v == &json!([NAME])), "{out}");
    assert_eq!(out["retransmissions"], json!(0), "{out}");
}

/// The figures of a burst without its status lists.
fn summary(out: &Value) -> String {
    format!(
        "{} replies in {:.1} ms, in order {}, retransmissions {}",
        out["replies"],
        out["seconds"].as_f64().unwrap_or(-1.0) * 1e3,
        out["in_order"],
        out["retransmissions"]
    )
}
