//! In-memory PHY integration test (no root, no real network): the firmware runtime with the
//! generic profile on one embassy-net stack (198.18.0.2/24) behind the link task, as on the
//! boards, and a test client on another (198.18.0.1/24), joined by an in-memory Ethernet
//! wire and driven on this thread.
//!
//! Covered: RegisterSession, SendRRData Get_Attribute_Single (Identity product name),
//! Set_Attribute_Single on output assembly 150 read back from input assembly 100, unicast and
//! broadcast ListIdentity over UDP, the client after the last session refused while every
//! session stays served, a stalled client that does not hold up the others, a socket freed by
//! UnregisterSession taking the next client, the encapsulation inactivity timeout, and a
//! Class 1 exclusive owner through the link task (O->T data reaching the adapter, T->O data
//! with headers and checksums the client's stack accepts, the watchdog ending it), and an
//! idle session closed at its inactivity timeout while only Class 1 data comes.
//!
//! Every scenario runs twice ([`at_both_sizes`]): with the adapter and its `Resources` at the
//! default capacities (3 sessions, 10 connections), and at 16 sessions, 64 connections,
//! 1 524-byte frames and 16 delayed ListIdentity replies.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::future::Future;
use std::net::Ipv4Addr;
use std::rc::Rc;
use std::task::{Context, Waker};

use embassy_futures::join::join4;
use embassy_futures::select::{select, Either};
use embassy_net::tcp::{ConnectError, TcpSocket};
use embassy_net::udp::{PacketMetadata, UdpSocket};
use embassy_net::{Ipv4Cidr, Stack, StackResources, StaticConfigV4};
use embassy_time::{with_deadline, with_timeout, Duration, Timer};
use enip_firmware::link::{self, LinkFrames, NetDriver};
use enip_firmware::Resources;
use enip_profiles::generic;
use enip_profiles::Profile;
use enip_stack::config::{
    MAX_CONNECTIONS, MAX_ENCAP_FRAME, MAX_PENDING_LIST_IDENTITY, MAX_SESSIONS,
};
use enip_stack::originator;
use enip_stack::wire::cpf::{self, item_type};
use enip_stack::wire::encap::{command, Packet, HEADER_LEN};
use enip_stack::wire::forward_open::{ForwardOpenReplyRepr, Triad};
use enip_stack::wire::identity_item::IdentityRepr;
use enip_stack::wire::message_router::ResponseRepr;
use enip_stack::wire::Writer;
use enip_stack::Adapter;
use host_tests::scanner::{generic_forward_open, OWNER_O_T, OWNER_PATH};

mod client;
mod while_class1;
mod wire;

use client::*;
use while_class1::*;

const ADAPTER_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 2);
const CLIENT_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 1);
const BROADCAST_IP: Ipv4Addr = Ipv4Addr::new(198, 18, 0, 255);
const PORT: u16 = 44818;
const IO_PORT: u16 = 2222;
/// Bound of a whole test, enforced by [`block_on`].
const TEST_LIMIT: Duration = Duration::from_secs(10);
/// Bound of one request/reply exchange.
const STEP: Duration = Duration::from_secs(2);
/// embassy-net sockets of either side: enough for the large size's 16 sessions, the client
/// refused after them, and the UDP sockets.
const NET_SOCKETS: usize = 24;

/// Instantiates each scenario (a function generic over the adapter's sessions, connections,
/// frame size and ListIdentity queue) as a test at the default capacities and one at 16
/// sessions / 64 connections / 1 524-byte frames / 16 delayed replies.
macro_rules! at_both_sizes {
    ($($scenario:ident),* $(,)?) => {
        mod default_size {
            use super::*;
            $(
                #[test]
                fn $scenario() {
                    super::$scenario::<
                        MAX_SESSIONS,
                        MAX_CONNECTIONS,
                        MAX_ENCAP_FRAME,
                        MAX_PENDING_LIST_IDENTITY,
                    >();
                }
            )*
        }
        mod large_size {
            $(
                #[test]
                fn $scenario() {
                    super::$scenario::<16, 64, { 24 + 1500 }, 16>();
                }
            )*
        }
    };
}

at_both_sizes!(
    explicit_messaging_over_tcp,
    list_identity_over_udp,
    every_session_is_served_the_next_client_refused_and_a_stalled_one_blocks_nobody,
    idle_connection_is_closed_after_the_inactivity_timeout,
    class1_io_through_the_link_task,
    junk_does_not_turn_the_t_o_data_away,
    an_idle_session_closes_on_time_while_class1_data_flows,
);

/// Polls `fut` on this thread, on the host runtime's loop (which fires the timers); panics
/// past [`TEST_LIMIT`].
fn block_on<F: Future>(fut: F) -> F::Output {
    let limited = select(fut, Timer::after(TEST_LIMIT));
    match enip_host_runtime::block_on(limited).expect("the host runtime's loop") {
        Either::First(out) => out,
        Either::Second(()) => panic!("test exceeded {TEST_LIMIT:?}"),
    }
}

fn static_config(ip: Ipv4Addr) -> embassy_net::Config {
    embassy_net::Config::ipv4_static(StaticConfigV4 {
        address: Ipv4Cidr::new(ip, 24),
        gateway: None,
        dns_servers: Default::default(),
    })
}

/// Runs `scenario` against an adapter with the generic profile, at `S` sessions, `C`
/// connections, `F`-byte frames and `L` delayed ListIdentity replies; everything on this
/// thread.
fn with_adapter<const S: usize, const C: usize, const F: usize, const L: usize>(
    scenario: impl AsyncFnOnce(Stack<'_>),
) {
    let (adapter_port, client_port) = wire::pair([2, 0, 0, 0, 0, 2], [2, 0, 0, 0, 0, 1]);
    let mut adapter_sockets = Resources::<F>::stack_resources::<NET_SOCKETS>();
    let mut client_sockets = StackResources::<NET_SOCKETS>::new();
    // As on the boards, the adapter's port belongs to the link task: Class 1 datagrams go
    // between it and the adapter, every other frame through `frames` to embassy-net.
    let frames = LinkFrames::new();
    let (adapter_net, mut adapter_runner) = embassy_net::new(
        NetDriver::new(&frames, &adapter_port),
        static_config(ADAPTER_IP),
        &mut adapter_sockets,
        0x0123_4567,
    );
    let (client_net, mut client_runner) = embassy_net::new(
        client_port,
        static_config(CLIENT_IP),
        &mut client_sockets,
        0x89AB_CDEF,
    );
    let mut adapter = Adapter::<_, S, C, F, L>::with_capacities(
        Profile::from_name("generic").expect("generic profile"),
        enip_firmware::network_config(adapter_net),
        42,
    );
    // Not about Address Conflict Detection: no seconds of probing (the TAP tests cover it).
    adapter.skip_acd();
    let adapter = enip_firmware::share(adapter);
    let mut resources = Box::new(Resources::<F>::new());
    let background = join4(
        adapter_runner.run(),
        client_runner.run(),
        enip_firmware::run(adapter_net, &adapter, &mut resources, |_| {}),
        link::run(adapter_port, &frames, &adapter),
    );
    match block_on(select(background, scenario(client_net))) {
        Either::First(never) => match never.0 {},
        Either::Second(()) => {}
    }
}

/// Reads Identity attribute 7 on `session` and checks it is the generic profile's name.
async fn check_product_name(client: &mut Client<'_>, session: u32) {
    let (status, data) = client
        .request(session, GET_ATTRIBUTE_SINGLE, &IDENTITY_NAME, &[])
        .await;
    assert_eq!(status, 0);
    let name = generic::IDENTITY.product_name.as_bytes();
    assert_eq!(data[0] as usize, name.len());
    assert_eq!(&data[1..], name);
}

fn explicit_messaging_over_tcp<const S: usize, const C: usize, const F: usize, const L: usize>() {
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx, mut tx) = ([0u8; 2048], [0u8; 2048]);
        let (mut client, session) = Client::registered(net, &mut rx, &mut tx).await;
        check_product_name(&mut client, session).await;

        let outputs: Vec<u8> = (1..=32).collect();
        let (status, data) = client
            .request(
                session,
                SET_ATTRIBUTE_SINGLE,
                &assembly_data(generic::OUTPUT),
                &outputs,
            )
            .await;
        assert_eq!((status, data.len()), (0, 0), "Set output assembly 150");
        let (status, data) = client
            .request(
                session,
                GET_ATTRIBUTE_SINGLE,
                &assembly_data(generic::INPUT),
                &[],
            )
            .await;
        assert_eq!(status, 0);
        assert_eq!(data, outputs, "input assembly 100 echoes the outputs");

        // A request split across TCP segments and two requests in one segment both work.
        let frame = send_rr_data(session, GET_ATTRIBUTE_SINGLE, &IDENTITY_NAME, &[]);
        client.write(&frame[..10]).await;
        embassy_time::Timer::after_millis(20).await;
        let reply = client.exchange(&frame[10..]).await;
        assert_eq!(Packet::new_checked(&reply[..]).unwrap().status(), 0);
        let two = [frame.clone(), frame].concat();
        let first = client.exchange(&two).await;
        let mut second = vec![0; first.len()];
        client.read_exact(&mut second).await;
        assert_eq!(first, second);
    });
}

fn list_identity_over_udp<const S: usize, const C: usize, const F: usize, const L: usize>() {
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx_meta, mut tx_meta) = ([PacketMetadata::EMPTY; 4], [PacketMetadata::EMPTY; 4]);
        let (mut rx, mut tx) = ([0u8; 1024], [0u8; 1024]);
        let mut socket = UdpSocket::new(net, &mut rx_meta, &mut rx, &mut tx_meta, &mut tx);
        socket.bind(50_000).expect("bind");
        // Unicast: answered at once. Broadcast: answered within the 500 ms asked for in
        // the first two bytes of the sender context.
        for (to, context) in [
            (ADAPTER_IP, *b"unicast!"),
            (BROADCAST_IP, [0xF4, 0x01, 0, 0, 0, 0, 0, 7]),
        ] {
            let request = header(command::LIST_IDENTITY, 0, 0, context);
            socket.send_to(&request, (to, PORT)).await.expect("send");
            let mut buf = [0u8; 512];
            let (n, meta) = with_timeout(Duration::from_millis(1500), socket.recv_from(&mut buf))
                .await
                .expect("ListIdentity reply in time")
                .expect("recv");
            assert_eq!(meta.endpoint, (ADAPTER_IP, PORT).into());
            let p = Packet::new_checked(&buf[..n]).expect("reply frame");
            assert_eq!((p.command(), p.status()), (command::LIST_IDENTITY, 0));
            assert_eq!(p.sender_context(), context);
            let items = cpf::Packet::new_checked(p.data()).expect("CPF");
            let item = items.find(item_type::LIST_IDENTITY).expect("identity item");
            let id = IdentityRepr::parse(item.data).expect("identity");
            let expected = generic::IDENTITY;
            assert_eq!(id.vendor_id, expected.vendor_id);
            assert_eq!(id.device_type, expected.device_type);
            assert_eq!(id.product_code, expected.product_code);
            assert_eq!(id.revision, expected.revision);
            assert_eq!(id.serial_number, expected.serial_number);
            assert_eq!(id.product_name, expected.product_name.as_bytes());
            assert_eq!((id.socket.addr, id.socket.port), (ADAPTER_IP, PORT));
        }
    });
}

fn every_session_is_served_the_next_client_refused_and_a_stalled_one_blocks_nobody<
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>() {
    with_adapter::<S, C, F, L>(async |net| {
        // A receive and a transmit buffer per session, and one pair for the client after.
        let mut bufs = vec![[0u8; 1024]; 2 * (S + 1)];
        let (mine, extra) = bufs.split_at_mut(2 * S);
        let [r_next, t_next] = extra else {
            unreachable!("two buffers")
        };
        let mut pairs = mine.chunks_exact_mut(2).map(|pair| match pair {
            [r, t] => (r, t),
            _ => unreachable!("pairs"),
        });
        let (r0, t0) = pairs.next().expect("a session");
        let mut stalled = Client::connect(net, r0, t0).await.expect("connect 1");
        let mut served = Vec::new();
        for (i, (r, t)) in pairs.enumerate() {
            let mut client = Client::connect(net, r, t)
                .await
                .unwrap_or_else(|e| panic!("connect {}: {e:?}", i + 2));
            let session = client.register().await;
            served.push((client, session));
        }
        // The first client sends half a header and goes silent.
        stalled.write(&register_session()[..12]).await;
        match Client::connect(net, r_next, t_next).await {
            Err(ConnectError::ConnectionReset) => {}
            Err(e) => panic!("connection {}: {e:?}", S + 1),
            Ok(_) => panic!("connection {} was accepted", S + 1),
        }
        for (client, session) in &mut served {
            check_product_name(client, *session).await;
        }
        // The stalled client is still served once it finishes its frame.
        let reply = stalled.exchange(&register_session()[12..]).await;
        assert_eq!(Packet::new_checked(&reply[..]).unwrap().status(), 0);
        // Once a session ends, its socket listens again and takes the next client.
        let (a, sa) = served.first_mut().expect("a second session");
        a.write(&header(command::UNREGISTER_SESSION, 0, *sa, [0; 8]))
            .await;
        a.expect_close().await;
        let mut next = Client::connect_within(net, r_next, t_next, 20)
            .await
            .expect("a freed socket accepts again");
        let session = next.register().await;
        check_product_name(&mut next, session).await;
    });
}

fn idle_connection_is_closed_after_the_inactivity_timeout<
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>() {
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx, mut tx) = ([0u8; 1024], [0u8; 1024]);
        let (mut client, session) = Client::registered(net, &mut rx, &mut tx).await;
        // TCP/IP Interface (0xF5) instance 1 attribute 13: encapsulation inactivity timeout.
        let path = [0x20, 0xF5, 0x24, 0x01, 0x30, 0x0D];
        let (status, _) = client
            .request(session, SET_ATTRIBUTE_SINGLE, &path, &1u16.to_le_bytes())
            .await;
        assert_eq!(status, 0, "Set inactivity timeout to 1 s");
        let idle_since = embassy_time::Instant::now();
        client.expect_close().await;
        let idle = idle_since.elapsed();
        assert!(
            idle >= Duration::from_millis(900),
            "closed after {idle:?}, before the timeout"
        );
    });
}

/// Connection Manager (class 6, instance 1) and its Forward_Open service.
const CONNECTION_MANAGER: [u8; 4] = [0x20, 0x06, 0x24, 0x01];
const FORWARD_OPEN: u8 = 0x54;
/// The Class 1 connection's RPI, both directions, and its T->O connection ID.
const CLASS1_RPI_US: u32 = 10_000;
const T_O_ID: u32 = 0x5C00_0001;

/// The Forward_Open of the generic profile's exclusive owner at [`CLASS1_RPI_US`] both
/// ways, point to point, timeout x4.
fn exclusive_owner_request() -> Vec<u8> {
    let triad = Triad {
        connection_serial: 7,
        vendor_id: 0xF00D,
        originator_serial: 7,
    };
    let request = generic_forward_open(triad, T_O_ID, &OWNER_PATH, OWNER_O_T, 0, CLASS1_RPI_US);
    let mut buf = [0u8; 128];
    let mut w = Writer::new(&mut buf);
    request.emit(&mut w).expect("Forward_Open fits");
    w.written().to_vec()
}

/// The connected data (sequence count, then inputs) of a T->O datagram of [`T_O_ID`].
fn t_o_data(datagram: &[u8]) -> Vec<u8> {
    let p = enip_stack::wire::io_datagram::Packet::new_checked(datagram).expect("T->O datagram");
    assert_eq!(p.connection_id(), T_O_ID, "T->O connection ID");
    p.connected_data().to_vec()
}

/// Opens the generic profile's exclusive owner on `session`; returns its O->T connection ID.
async fn open_exclusive_owner(client: &mut Client<'_>, session: u32) -> u32 {
    let (status, reply) = client
        .request(
            session,
            FORWARD_OPEN,
            &CONNECTION_MANAGER,
            &exclusive_owner_request(),
        )
        .await;
    assert_eq!(status, 0, "Forward_Open refused: {reply:02x?}");
    let opened = ForwardOpenReplyRepr::parse(&reply).expect("Forward_Open reply");
    assert_eq!(opened.t_o_connection_id, T_O_ID);
    opened.o_t_connection_id
}

/// Sends the O->T datagram of connection `o_t_id` numbered `sequence` (both counts), in run
/// mode, carrying `outputs`.
async fn send_o_t(io: &UdpSocket<'_>, o_t_id: u32, sequence: u16, outputs: &[u8]) {
    let mut datagram = [0u8; 128];
    let len = originator::io_datagram(
        &mut datagram,
        o_t_id,
        sequence.into(),
        sequence,
        Some(true),
        outputs,
    )
    .expect("O->T datagram");
    io.send_to(&datagram[..len], (ADAPTER_IP, IO_PORT))
        .await
        .expect("O->T sent");
}

/// A UDP datagram to port 9 from [`CLIENT_IP`] but another station's MAC, its IPv4 header
/// good: junk the adapter drops, which must not teach it where the client is.
fn junk_from_the_clients_address() -> Vec<u8> {
    let mut f = vec![0u8; 14 + 20 + 8 + 4];
    f[..6].copy_from_slice(&[2, 0, 0, 0, 0, 2]);
    f[6..12].copy_from_slice(&[2, 0, 0, 0, 0, 0x66]);
    f[12..14].copy_from_slice(&[0x08, 0x00]);
    let ip = &mut f[14..34];
    ip[0] = 0x45;
    ip[2..4].copy_from_slice(&(20u16 + 8 + 4).to_be_bytes());
    ip[8] = 64;
    ip[9] = 17;
    ip[12..16].copy_from_slice(&CLIENT_IP.octets());
    ip[16..20].copy_from_slice(&ADAPTER_IP.octets());
    let sum = ip
        .chunks(2)
        .map(|w| u32::from(u16::from_be_bytes([w[0], w[1]])))
        .sum::<u32>();
    let folded = (sum & 0xFFFF) + (sum >> 16);
    let folded = (folded & 0xFFFF) + (folded >> 16);
    ip[10..12].copy_from_slice(&(!(folded as u16)).to_be_bytes());
    f[34..36].copy_from_slice(&9u16.to_be_bytes());
    f[36..38].copy_from_slice(&9u16.to_be_bytes());
    f[38..40].copy_from_slice(&12u16.to_be_bytes());
    f
}

fn junk_does_not_turn_the_t_o_data_away<
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>() {
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx, mut tx) = ([0u8; 2048], [0u8; 2048]);
        let (mut client, session) = Client::registered(net, &mut rx, &mut tx).await;
        let mut io_buffers = IoBuffers::new();
        let io = io_buffers.bound(net);
        let o_t_id = open_exclusive_owner(&mut client, session).await;
        let outputs = [0u8; generic::IO_SIZE];
        for sequence in 1..=5u16 {
            send_o_t(&io, o_t_id, sequence, &outputs).await;
            Timer::after_micros(CLASS1_RPI_US.into()).await;
        }
        // The junk, then two RPIs without O->T data (the watchdog is four): the T->O
        // datagrams of those RPIs still come to the client's MAC.
        wire::inject_to_port_0(junk_from_the_clients_address());
        Timer::after_micros(1_000).await;
        let mut buf = [0u8; 256];
        while with_timeout(Duration::from_millis(1), io.recv_from(&mut buf))
            .await
            .is_ok()
        {}
        let mut after = 0;
        let until =
            embassy_time::Instant::now() + Duration::from_micros(2 * u64::from(CLASS1_RPI_US));
        while let Ok(Ok(_)) = with_deadline(until, io.recv_from(&mut buf)).await {
            after += 1;
        }
        assert!(
            after >= 1,
            "no T->O datagram reached the client after the junk"
        );
    });
}

fn class1_io_through_the_link_task<
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>() {
    // Timed against the wall clock: the two sizes take turns rather than share the CPU.
    static TIMED: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = TIMED
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx, mut tx) = ([0u8; 2048], [0u8; 2048]);
        let (mut client, session) = Client::registered(net, &mut rx, &mut tx).await;

        // The client's I/O socket first, so no T->O datagram finds the port closed.
        let mut io_buffers = IoBuffers::new();
        let io = io_buffers.bound(net);

        let o_t_id = open_exclusive_owner(&mut client, session).await;

        // 30 RPIs of O->T data; the T->O datagrams come from the adapter's address and port,
        // in sequence, and soon carry the outputs back (input assembly 100 echoes 150).
        let outputs: Vec<u8> = (0..generic::IO_SIZE as u8).map(|b| b ^ 0xA5).collect();
        let mut received = Vec::new();
        let rpi = Duration::from_micros(CLASS1_RPI_US.into());
        let mut ticker = embassy_time::Ticker::every(rpi);
        let start = embassy_time::Instant::now();
        for sequence in 1..=30u16 {
            send_o_t(&io, o_t_id, sequence, &outputs).await;
            ticker.next().await;
            let mut buf = [0u8; 256];
            while let Ok(Ok((n, from))) =
                with_timeout(Duration::from_millis(1), io.recv_from(&mut buf)).await
            {
                assert_eq!(from.endpoint.addr, ADAPTER_IP.into(), "T->O source address");
                assert_eq!(from.endpoint.port, IO_PORT, "T->O source port");
                received.push(t_o_data(&buf[..n]));
            }
        }
        // One per RPI of the time it took (300 ms unless this machine stalled), give or take
        // the phase of the two clocks and the second production's move onto the adapter's
        // grid (up to one RPI after the first's).
        let rpis = (start.elapsed().as_micros() / rpi.as_micros()) as usize;
        assert!(
            (rpis.saturating_sub(4)..=rpis + 2).contains(&received.len()),
            "{} T->O datagrams in {rpis} RPIs",
            received.len()
        );
        let counts: Vec<u16> = received
            .iter()
            .map(|d| u16::from_le_bytes([d[0], d[1]]))
            .collect();
        assert!(
            counts.windows(2).all(|w| w[1] == w[0].wrapping_add(1)),
            "T->O sequence counts {counts:?}"
        );
        assert!(received.iter().all(|d| d.len() == 2 + generic::IO_SIZE));
        assert_eq!(
            received.last().map(|d| &d[2..]),
            Some(&outputs[..]),
            "the inputs echo the O->T outputs"
        );

        // Silence: the watchdog (4 x 10 ms) ends the connection, and the T->O data stops.
        let mut buf = [0u8; 256];
        Timer::after_millis(100).await;
        while with_timeout(Duration::from_millis(1), io.recv_from(&mut buf))
            .await
            .is_ok()
        {}
        let late = with_timeout(Duration::from_millis(200), io.recv_from(&mut buf)).await;
        assert!(late.is_err(), "T->O data after the connection timed out");
    });
}
