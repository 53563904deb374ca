//! Class 3 connected explicit messaging with pycomm3: Forward_Open of a Message Router
//! connection (its Large_Forward_Open of 4000 bytes is refused with 0x0109, and it falls
//! back to 500 bytes), then SendUnitData requests.

use std::time::Duration;

use serde_json::json;

use crate::common::{self, NAME};
use host_tests::peers;
use host_tests::rig::BOARD_IP;

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn pycomm3_connected_messaging() {
    let rig = common::start("pycomm3_connected");
    let out = peers::run(
        rig.ns(),
        "pycomm3_connected.py",
        &json!({"host": BOARD_IP.to_string()}),
        Duration::from_secs(60),
    )
    .unwrap_or_else(|e| panic!("{e}\n{}", rig.board_log()));
    let mut name = vec![NAME.len() as u8];
    name.extend_from_slice(NAME.as_bytes());
    let hex = |b: &[u8]| b.iter().map(|x| format!("{x:02x}")).collect::<String>();
    assert_eq!(out["name"], hex(&name), "{out}");
    assert!(out["set_error"].is_null(), "{out}");
    assert_eq!(out["get"], hex(&(100u8..132).collect::<Vec<_>>()), "{out}");
    assert_eq!(out["connection_size"], 500, "{out}");
    common::finish(rig);
}
