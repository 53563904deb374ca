//! Blind data injection into an encapsulation session (RFC 5961 section 5), from
//! `peers/tcp_injection.py`: a segment forged as a registered client's, at its next sequence
//! number but acknowledging a number older than any window it offered, must not reach the
//! session; the client's own next request is answered as if nothing had come.

use std::time::Duration;

use serde_json::json;

use crate::common;
use host_tests::peers;
use host_tests::rig::BOARD_IP;

/// How far before the board's next sequence number the forged ACK lies: beyond any window
/// a client offers without scaling (65 535), and within 2^31 (so it reads as old, not new).
const OLDER_BY: u32 = 1 << 20;

#[test]
#[ignore = "needs root and tshark"]
fn hostile_tcp_blind_data_injection() {
    let rig = common::start("hostile_tcp_blind_data_injection");
    let input = json!({"target": BOARD_IP.to_string(), "older_by": OLDER_BY});
    let out = peers::run(
        rig.ns(),
        "tcp_injection.py",
        &input,
        Duration::from_secs(30),
    )
    .unwrap_or_else(|e| panic!("{e}\nboard log:\n{}", rig.board_log()));
    println!("tcp_injection.py: {out}");
    assert_eq!(
        (&out["forged_answered"], &out["reply_command"]),
        (&json!(false), &json!(0x63)),
        "the forged segment's request reached the session: {out}"
    );
    // It answered with an ACK of the client's next byte (RFC 5961 5.2's challenge), and
    // nothing it sent acknowledged the forged bytes.
    let acks = out["board_acks"].as_array().expect("board_acks");
    assert!(
        out["challenge_ack"] == json!(true) && !acks.is_empty(),
        "no challenge ACK: {out}"
    );
    assert!(
        acks.iter().all(|a| a == &json!(0)),
        "the board acknowledged the forged data: {out}"
    );
    common::finish_hostile(rig);
}
