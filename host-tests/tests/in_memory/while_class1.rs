//! The link task's rare work while only Class 1 data comes: its wake-ups are Class 1's, and
//! the rare work's own deadlines must still wake it.

use super::*;

/// A session left idle closes at the encapsulation inactivity timeout while O->T datagrams
/// arrive every RPI and nothing else does: the TCP server's timer wakes the link task
/// between them.
pub(crate) fn an_idle_session_closes_on_time_while_class1_data_flows<
    const S: usize,
    const C: usize,
    const F: usize,
    const L: usize,
>() {
    with_adapter::<S, C, F, L>(async |net| {
        let (mut rx, mut tx) = ([0u8; 1024], [0u8; 1024]);
        let (mut owner, owner_session) = Client::registered(net, &mut rx, &mut tx).await;
        let mut io_buffers = IoBuffers::new();
        let io = io_buffers.bound(net);
        let o_t_id = open_exclusive_owner(&mut owner, owner_session).await;

        let (mut rx, mut tx) = ([0u8; 1024], [0u8; 1024]);
        let (mut idle, idle_session) = Client::registered(net, &mut rx, &mut tx).await;
        // TCP/IP Interface (0xF5) instance 1 attribute 13: encapsulation inactivity timeout.
        let path = [0x20, 0xF5, 0x24, 0x01, 0x30, 0x0D];
        let (status, _) = idle
            .request(
                idle_session,
                SET_ATTRIBUTE_SINGLE,
                &path,
                &1u16.to_le_bytes(),
            )
            .await;
        assert_eq!(status, 0, "Set inactivity timeout to 1 s");
        let idle_since = embassy_time::Instant::now();

        // O->T data every RPI for up to 2.5 s; nothing else goes to the adapter meanwhile.
        let outputs = [0x5Au8; generic::IO_SIZE];
        let sending = async {
            let mut ticker =
                embassy_time::Ticker::every(Duration::from_micros(CLASS1_RPI_US.into()));
            for sequence in 1..=250u16 {
                send_o_t(&io, o_t_id, sequence, &outputs).await;
                ticker.next().await;
            }
        };
        let closing = async {
            idle.expect_close().await;
            idle_since.elapsed()
        };
        match select(sending, closing).await {
            Either::Second(after) => assert!(
                (Duration::from_millis(900)..Duration::from_millis(1_600)).contains(&after),
                "the idle session closed after {after:?}, not at its 1 s timeout"
            ),
            Either::First(()) => panic!("the idle session outlived 2.5 s of Class 1 data"),
        }
    });
}
