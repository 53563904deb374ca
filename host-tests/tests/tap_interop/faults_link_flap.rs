//! Link flap (issue 13 item 2): the TAP is taken down for 2 s in the namespace and brought
//! back while Class 1 I/O runs. The adapter keeps its address, sees the link go down and up,
//! connections whose timeout (multiplier x RPI) is shorter than the outage time out, one
//! whose timeout outlasts it lives on, one that is not fed after the outage closes at its
//! timeout measured from its last O->T, and new sessions and connections open within 1 s of
//! link-up. `ENIP_FAULTS_LONG=1` (or `ENIP_FAULTS_FLAPS=N`) repeats it (5 flaps).

use std::io;
use std::net::{Ipv4Addr, SocketAddrV4, UdpSocket};
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::common;
use crate::fault_io::{board_real_time, drive, ms_between, Feed, IO_PORT};
use crate::faults::{cm_counter, forward_open, session, triad};
use enip_stack::wire::epath::{LogicalType, SegmentRepr};
use host_tests::faults::{count, most, ms, report};
use host_tests::netns::Namespace;
use host_tests::rig::{BOARD_IP, TAP};
use host_tests::scanner::{HEARTBEAT_O_T, INPUT_ONLY_PATH, OWNER_O_T, OWNER_PATH};

/// How long the link stays down.
const OUTAGE: Duration = Duration::from_secs(2);
/// The owner: 10 ms x4, 40 ms, dies in the outage.
const OWNER_RPI: Duration = Duration::from_millis(10);
/// The long-lived input-only connections: 20 ms x128 = 2.56 s, longer than the outage.
const LONG_RPI: Duration = Duration::from_millis(20);
const LONG_MULTIPLIER: u8 = 5;
const LONG_TIMEOUT: Duration = Duration::from_millis(20 * 128);
/// Lateness allowed after a timeout (the adapter's timer on a shared 2-core VM).
const MARGIN: Duration = Duration::from_millis(100);
/// Bound for a new session and connection after link-up.
const BACK_BOUND: Duration = Duration::from_secs(1);

#[test]
#[ignore = "needs root: network namespace and TAP"]
fn faults_link_flap() {
    let flaps = count("ENIP_FAULTS_FLAPS", 1, 5);
    let rig = common::start("faults_link_flap");
    board_real_time(&rig);
    let ns = rig.ns();
    let rounds: Vec<Value> = (0..flaps)
        .map(|round| {
            ns.inside(|| flap(ns, round as u16))
                .expect("namespace")
                .unwrap_or_else(|e| panic!("flap {round}: {e}\n{}", rig.board_log()))
        })
        .collect();
    let log = rig.board_log();
    let downs = log.matches("link up false").count();
    assert!(
        downs >= 2 * flaps as usize,
        "the link state is not tracked: {downs} 'link up false' lines\n{log}"
    );
    report(
        "link_flap",
        json!({
            "flaps": flaps,
            "outage_ms": ms(OUTAGE),
            "worst_session_after_up_ms": most(&rounds, "session_after_up_ms"),
            "worst_forward_open_after_up_ms": most(&rounds, "forward_open_after_up_ms"),
            "worst_io_resumed_after_up_ms": most(&rounds, "io_resumed_after_up_ms"),
            "unfed_timeout_ms": LONG_TIMEOUT.as_millis() as u64,
            "worst_unfed_closed_after_ms": most(&rounds, "unfed_closed_after_ms"),
            "rounds": rounds,
        }),
    );
    // Frames the adapter sent before the outage are acknowledged by segments it never saw
    // while the TAP was down: check only its own encapsulation and UDP frames.
    common::finish_hostile(rig);
}

/// One flap with fresh connections (serials from `round`); returns its figures.
fn flap(ns: &Namespace, round: u16) -> io::Result<Value> {
    let udp = UdpSocket::bind(SocketAddrV4::new(Ipv4Addr::UNSPECIFIED, IO_PORT))?;
    let mut s = session()?;
    let timeouts_before = cm_counter(&mut s, 8)?;
    let refused = |e| io::Error::other(format!("Forward_Open refused: {e:?}"));
    let serial = 10 * round;
    let owner = s
        .forward_open(&forward_open(
            triad(serial + 1, 0xF1A9),
            &OWNER_PATH,
            OWNER_O_T,
            0,
            OWNER_RPI.as_micros() as u32,
        ))?
        .map_err(refused)?;
    let mut long = |n: u16| {
        s.forward_open(&forward_open(
            triad(serial + n, 0xF1A9),
            &INPUT_ONLY_PATH,
            HEARTBEAT_O_T,
            LONG_MULTIPLIER,
            LONG_RPI.as_micros() as u32,
        ))
        .and_then(|r| r.map_err(refused))
    };
    let survivor = long(2)?;
    let unfed = long(3)?;
    let feeds = [
        Feed::new(&owner, OWNER_RPI, true),
        Feed::new(&survivor, LONG_RPI, false),
        Feed::new(&unfed, LONG_RPI, false),
    ];
    let start = Instant::now();
    let end = start + Duration::from_millis(500) + OUTAGE + LONG_TIMEOUT;
    let (traffic, down_at, up_at, back) = std::thread::scope(|sc| -> io::Result<_> {
        let io = sc.spawn(|| drive(&udp, &feeds, end));
        std::thread::sleep(Duration::from_millis(500));
        // The unfed connection's last O->T goes out before the link does.
        feeds[2].starve();
        let down_at = Instant::now();
        ns.exec_checked("ip", &["link", "set", TAP, "down"])?;
        std::thread::sleep(OUTAGE.saturating_sub(down_at.elapsed()));
        ns.exec_checked("ip", &["link", "set", TAP, "up"])?;
        let up_at = Instant::now();
        let back = reconnect(round)?;
        let traffic = io
            .join()
            .map_err(|_| io::Error::other("I/O thread panicked"))??;
        Ok((traffic, down_at, up_at, back))
    })?;
    // The session from before the outage still works, and the survivor is still open.
    let closed = s.forward_close(survivor.triad)?;
    let timeouts = cm_counter(&mut s, 8)?.wrapping_sub(timeouts_before);
    let owner_last = traffic.last_before(owner.t_o_connection_id, down_at);
    let owner_after = traffic.first_after(owner.t_o_connection_id, up_at);
    let resumed = traffic.first_after(survivor.t_o_connection_id, up_at);
    let unfed_last = traffic.arrivals(unfed.t_o_connection_id).max();
    let unfed_sent = traffic.last_sent[2];
    let figures = json!({
        "outage_ms": ms(up_at - down_at),
        "owner_last_t_o_before_down_ms": owner_last.map(|t| ms_between(down_at, t)),
        "session_after_up_ms": ms(back.session),
        "forward_open_after_up_ms": ms(back.forward_open),
        "address_kept": back.address == BOARD_IP,
        "io_resumed_after_up_ms": resumed.map(|t| ms_between(up_at, t)),
        "unfed_closed_after_ms": unfed_last.zip(unfed_sent).map(|(l, s)| ms_between(s, l)),
        "o_t_send_errors_during_outage": traffic.send_errors,
        "connection_timeouts": timeouts,
    });
    println!("link flap {round}: {figures}");
    let fail = |what: &str| Err(io::Error::other(format!("{what}: {figures}")));
    if back.address != BOARD_IP {
        return fail("the adapter changed its address");
    }
    if back.session > BACK_BOUND || back.forward_open > BACK_BOUND {
        return fail("no new session and connection within 1 s of link-up");
    }
    if owner_after.is_some() {
        return fail("the 40 ms owner produced after a 2 s outage");
    }
    if resumed.is_none() || closed.general != 0 {
        return fail("the connection whose timeout outlasts the outage did not live on");
    }
    // Closed between its last T->O and one RPI later, at multiplier x RPI after its last O->T.
    let (Some(last), Some(sent)) = (unfed_last, unfed_sent) else {
        return fail("the unfed connection was never seen");
    };
    let closed_after = last.duration_since(sent);
    if closed_after + LONG_RPI + Duration::from_millis(2) < LONG_TIMEOUT
        || closed_after > LONG_TIMEOUT + MARGIN
    {
        return fail("the unfed connection did not close at multiplier x RPI");
    }
    if timeouts != 2 {
        return fail("expected exactly the owner and the unfed connection to time out");
    }
    Ok(figures)
}

/// How the adapter answered right after link-up.
struct Back {
    /// Link-up to a registered session.
    session: Duration,
    /// Link-up to an accepted Forward_Open (exclusive owner) on it.
    forward_open: Duration,
    /// The address in TCP/IP attribute 5.
    address: Ipv4Addr,
}

/// Right after link-up: a new session, an exclusive owner opened and closed on it, and the
/// interface configuration read back.
fn reconnect(round: u16) -> io::Result<Back> {
    let up = Instant::now();
    let mut s = session()?;
    let session = up.elapsed();
    let opened = s
        .forward_open(&forward_open(
            triad(10 * round + 4, 0xF1A9),
            &OWNER_PATH,
            OWNER_O_T,
            0,
            100_000,
        ))?
        .map_err(|e| io::Error::other(format!("Forward_Open after link-up: {e:?}")))?;
    let forward_open = up.elapsed();
    let r = s.forward_close(opened.triad)?;
    if r.general != 0 {
        return Err(io::Error::other(format!(
            "Forward_Close after link-up: {r:?}"
        )));
    }
    let r = s.request(
        0x0E,
        &[
            SegmentRepr::Logical(LogicalType::Class, 0xF5),
            SegmentRepr::Logical(LogicalType::Instance, 1),
            SegmentRepr::Logical(LogicalType::Attribute, 5),
        ],
        &[],
    )?;
    let ip = r
        .data
        .get(..4)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
        .ok_or_else(|| io::Error::other(format!("TCP/IP attribute 5: {r:?}")))?;
    Ok(Back {
        session,
        forward_open,
        address: Ipv4Addr::from(ip),
    })
}
