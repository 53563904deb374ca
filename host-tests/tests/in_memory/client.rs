//! The test client: encapsulation requests built by hand and a TCP socket that sends them
//! and reads the replies.

use super::*;

/// Encapsulation header for `command` with `len` data bytes.
pub(crate) fn header(command: u16, len: usize, session: u32, context: [u8; 8]) -> Vec<u8> {
    let mut h = Vec::with_capacity(HEADER_LEN + len);
    h.extend_from_slice(&command.to_le_bytes());
    h.extend_from_slice(&(len as u16).to_le_bytes());
    h.extend_from_slice(&session.to_le_bytes());
    h.extend_from_slice(&0u32.to_le_bytes());
    h.extend_from_slice(&context);
    h.extend_from_slice(&0u32.to_le_bytes());
    h
}

pub(crate) fn register_session() -> Vec<u8> {
    let mut f = header(command::REGISTER_SESSION, 4, 0, *b"register");
    f.extend_from_slice(&[1, 0, 0, 0]);
    f
}

/// SendRRData carrying the Message Router request `service` on `path`, with `data`.
pub(crate) fn send_rr_data(session: u32, service: u8, path: &[u8], data: &[u8]) -> Vec<u8> {
    let mut mr = vec![service, (path.len() / 2) as u8];
    mr.extend_from_slice(path);
    mr.extend_from_slice(data);
    let mut body = vec![0, 0, 0, 0, 5, 0]; // interface handle 0, timeout 5 s
    body.extend_from_slice(&2u16.to_le_bytes());
    body.extend_from_slice(&[0, 0, 0, 0]); // null address item
    body.extend_from_slice(&item_type::UNCONNECTED_DATA.to_le_bytes());
    body.extend_from_slice(&(mr.len() as u16).to_le_bytes());
    body.extend_from_slice(&mr);
    let mut f = header(command::SEND_RR_DATA, body.len(), session, *b"rr-data!");
    f.extend_from_slice(&body);
    f
}

/// Class 0x01 instance 1 attribute 7 (product name).
pub(crate) const IDENTITY_NAME: [u8; 6] = [0x20, 0x01, 0x24, 0x01, 0x30, 0x07];
pub(crate) const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;
pub(crate) const SET_ATTRIBUTE_SINGLE: u8 = 0x10;

/// Assembly (class 0x04) `instance`, attribute 3 (data).
pub(crate) fn assembly_data(instance: u16) -> Vec<u8> {
    let [lo, hi] = instance.to_le_bytes();
    vec![0x20, 0x04, 0x25, 0x00, lo, hi, 0x30, 0x03]
}

/// A connected client TCP socket with its own buffers.
pub(crate) struct Client<'a> {
    socket: TcpSocket<'a>,
}

impl<'a> Client<'a> {
    pub(crate) async fn connect(
        net: Stack<'a>,
        rx: &'a mut [u8],
        tx: &'a mut [u8],
    ) -> Result<Self, ConnectError> {
        Self::connect_within(net, rx, tx, 1).await
    }

    /// Connects and registers a session; returns the client and the session handle.
    pub(crate) async fn registered(
        net: Stack<'a>,
        rx: &'a mut [u8],
        tx: &'a mut [u8],
    ) -> (Self, u32) {
        let mut client = Self::connect(net, rx, tx).await.expect("connect");
        let session = client.register().await;
        (client, session)
    }

    /// Connects, trying up to `attempts` times 100 ms apart.
    pub(crate) async fn connect_within(
        net: Stack<'a>,
        rx: &'a mut [u8],
        tx: &'a mut [u8],
        attempts: usize,
    ) -> Result<Self, ConnectError> {
        let mut socket = TcpSocket::new(net, rx, tx);
        let mut attempt = 1;
        loop {
            let connect = with_timeout(STEP, socket.connect((ADAPTER_IP, PORT)));
            match connect.await.expect("connect timed out") {
                Ok(()) => return Ok(Client { socket }),
                Err(e) if attempt == attempts => return Err(e),
                Err(_) => {
                    attempt += 1;
                    socket.abort();
                    embassy_time::Timer::after_millis(100).await;
                }
            }
        }
    }

    pub(crate) async fn write(&mut self, bytes: &[u8]) {
        let mut rest = bytes;
        while !rest.is_empty() {
            let n = with_timeout(STEP, self.socket.write(rest))
                .await
                .expect("write timed out")
                .expect("write failed");
            rest = &rest[n..];
        }
    }

    pub(crate) async fn read_exact(&mut self, out: &mut [u8]) {
        let mut at = 0;
        while at < out.len() {
            let n = with_timeout(STEP, self.socket.read(&mut out[at..]))
                .await
                .expect("read timed out")
                .expect("read failed");
            assert!(n > 0, "adapter closed the connection");
            at += n;
        }
    }

    /// Waits for the adapter to close the connection (within 3 s), then closes our side.
    pub(crate) async fn expect_close(&mut self) {
        let mut buf = [0u8; 64];
        let read = with_timeout(Duration::from_secs(3), self.socket.read(&mut buf));
        match read.await.expect("adapter closes the connection in time") {
            Ok(0) | Err(_) => {}
            Ok(n) => panic!("{n} unexpected bytes instead of the close"),
        }
        self.socket.close();
        let _ = with_timeout(STEP, self.socket.flush()).await;
    }

    /// Sends `frame` and returns the encapsulation reply frame.
    pub(crate) async fn exchange(&mut self, frame: &[u8]) -> Vec<u8> {
        self.write(frame).await;
        let mut reply = vec![0; HEADER_LEN];
        self.read_exact(&mut reply).await;
        let len = u16::from_le_bytes([reply[2], reply[3]]) as usize;
        reply.resize(HEADER_LEN + len, 0);
        self.read_exact(&mut reply[HEADER_LEN..]).await;
        reply
    }

    /// Registers a session; returns its handle.
    pub(crate) async fn register(&mut self) -> u32 {
        let reply = self.exchange(&register_session()).await;
        let p = Packet::new_checked(&reply[..]).expect("reply frame");
        assert_eq!(p.command(), command::REGISTER_SESSION);
        assert_eq!(p.status(), 0, "RegisterSession status");
        assert_eq!(p.sender_context(), *b"register");
        assert_ne!(p.session_handle(), 0);
        p.session_handle()
    }

    /// Sends one unconnected request; returns the reply's general status and data.
    pub(crate) async fn request(
        &mut self,
        session: u32,
        service: u8,
        path: &[u8],
        data: &[u8],
    ) -> (u8, Vec<u8>) {
        let reply = self
            .exchange(&send_rr_data(session, service, path, data))
            .await;
        let p = Packet::new_checked(&reply[..]).expect("reply frame");
        assert_eq!((p.command(), p.status()), (command::SEND_RR_DATA, 0));
        assert_eq!(p.session_handle(), session);
        let items = cpf::Packet::new_checked(&p.data()[6..]).expect("CPF");
        let item = items
            .find(item_type::UNCONNECTED_DATA)
            .expect("unconnected data item");
        let mr = ResponseRepr::parse(item.data).expect("Message Router reply");
        assert_eq!(mr.service, service | 0x80);
        (mr.general_status, mr.data.to_vec())
    }
}

/// The buffers of the client's Class 1 socket.
pub(crate) struct IoBuffers {
    rx_meta: [PacketMetadata; 16],
    tx_meta: [PacketMetadata; 4],
    rx: [u8; 2048],
    tx: [u8; 512],
}

impl IoBuffers {
    pub(crate) fn new() -> Self {
        IoBuffers {
            rx_meta: [PacketMetadata::EMPTY; 16],
            tx_meta: [PacketMetadata::EMPTY; 4],
            rx: [0; 2048],
            tx: [0; 512],
        }
    }

    /// The client's Class 1 socket on these buffers, bound to UDP port 2222.
    pub(crate) fn bound<'a>(&'a mut self, net: Stack<'a>) -> UdpSocket<'a> {
        let IoBuffers {
            rx_meta,
            tx_meta,
            rx,
            tx,
        } = self;
        let mut io = UdpSocket::new(net, rx_meta, rx, tx_meta, tx);
        io.bind(IO_PORT).expect("bind 2222");
        io
    }
}
