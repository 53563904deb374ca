//! [`RpiFloor`]: how fast a board can run Class 1 connections, in front of any device: a
//! Forward_Open for a Class 1 connection whose RPI (either direction in use) lies below the
//! floor the board computes for that request is refused with 0x01/0x0112 and the floor as the
//! acceptable value, before the device is asked. The board supplies the floor as a function of
//! the request (its sizes), from its own arithmetic or measurement; the runtime holds no
//! figure of any chip.

use enip_stack::cip::status::CipResult;
use enip_stack::config::MAX_RPI_US;
use enip_stack::device::{Front, OpenRequest};
use enip_stack::Device;

/// The RPI floor of a Class 1 request, in microseconds.
pub type Floor = fn(&OpenRequest<'_>) -> u32;

/// A device behind a board's RPI floor.
pub struct RpiFloor<D> {
    device: D,
    floor: Floor,
}

impl<D: Device> RpiFloor<D> {
    /// `device`, admitting Class 1 connections at `floor(request)` microseconds or slower.
    pub const fn new(device: D, floor: Floor) -> Self {
        RpiFloor { device, floor }
    }
}

impl<D: Device> Front for RpiFloor<D> {
    type Inner = D;
    fn inner(&self) -> &D {
        &self.device
    }
    fn inner_mut(&mut self) -> &mut D {
        &mut self.device
    }
    fn front_admit(&mut self, request: &OpenRequest<'_>) -> CipResult {
        if request.is_class1() {
            let floor = (self.floor)(request).min(MAX_RPI_US);
            request.refuse_rpi(floor, MAX_RPI_US)?;
        }
        self.device.admit(request)
    }
}

#[cfg(test)]
mod tests {
    use core::net::Ipv4Addr;

    use enip_profiles::Generic;
    use enip_stack::cip::connection_status::RPI_NOT_ACCEPTABLE;
    use enip_stack::device::{ConnectionPoints, Direction, Kind, Trigger};
    use enip_stack::wire::forward_open::{ConnectionType, NetworkParams, Triad};

    use super::*;

    /// 1 ms per 100 bytes of T->O connection size, at least 2 ms.
    fn by_size(request: &OpenRequest<'_>) -> u32 {
        (u32::from(request.t_o.params.size) * 10).max(2_000)
    }

    /// A point-to-point request of `kind` at `rpi_us` both ways, T->O size `t_o_size`.
    fn request(kind: Kind, rpi_us: u32, t_o_size: u16) -> OpenRequest<'static> {
        let params = |size| NetworkParams {
            redundant_owner: false,
            connection_type: ConnectionType::PointToPoint,
            priority: 0,
            variable: false,
            size,
        };
        OpenRequest {
            kind,
            transport_class: if kind == Kind::Explicit { 3 } else { 1 },
            trigger: Trigger::Cyclic,
            inhibit: enip_stack::Duration::from_millis(0),
            points: ConnectionPoints {
                config: None,
                consumed: Some(150),
                produced: Some(100),
            },
            o_t: Direction {
                rpi_us,
                params: params(36),
            },
            t_o: Direction {
                rpi_us,
                params: params(t_o_size),
            },
            timeout_multiplier: 2,
            originator: Ipv4Addr::new(198, 18, 0, 1),
            triad: Triad {
                connection_serial: 1,
                vendor_id: 1,
                originator_serial: 1,
            },
            key: None,
            config_data: None,
        }
    }

    #[test]
    fn a_class1_rpi_below_the_floor_is_refused_with_the_floor() {
        let mut device = RpiFloor::new(Generic::new(), by_size);
        let e = device
            .admit(&request(Kind::ExclusiveOwner, 1_000, 34))
            .unwrap_err();
        assert_eq!(e.extended(), Some(RPI_NOT_ACCEPTABLE));
        // Both directions below the minimum (type 2), the floor as the acceptable value.
        assert_eq!(e.additional()[1], u16::from_le_bytes([2, 2]));
        assert_eq!(e.additional()[2], 2_000);
        // The floor follows the request: 500 bytes back need 5 ms.
        let e = device
            .admit(&request(Kind::InputOnly, 4_000, 500))
            .unwrap_err();
        assert_eq!(e.additional()[2], 5_000);
    }

    #[test]
    fn at_or_above_the_floor_and_explicit_connections_go_to_the_device() {
        let mut device = RpiFloor::new(Generic::new(), by_size);
        assert_eq!(
            device.admit(&request(Kind::ExclusiveOwner, 2_000, 34)),
            Ok(())
        );
        assert_eq!(device.admit(&request(Kind::ListenOnly, 5_000, 500)), Ok(()));
        // Class 3: its RPI only times the connection out.
        assert_eq!(device.admit(&request(Kind::Explicit, 1_000, 34)), Ok(()));
    }

    /// Sends a Forward_Open for the generic profile's exclusive owner (151/150/100, 32 bytes
    /// each way) at `rpi_us` to an adapter over `device`; returns the reply's general status
    /// and additional status words.
    fn open_at<D: Device>(device: D, rpi_us: u32) -> (u8, heapless::Vec<u16, 8>) {
        use core::net::SocketAddrV4;
        use enip_stack::config::MAX_ENCAP_FRAME;
        use enip_stack::originator::{self, parse_reply};
        use enip_stack::wire::encap::EncapRepr;
        use enip_stack::wire::epath::{LogicalType, SegmentRepr};
        use enip_stack::wire::forward_open::ForwardOpenRepr;
        use enip_stack::wire::Writer;
        use enip_stack::{Adapter, Instant, NetworkConfig, SocketId};

        let net = NetworkConfig::new_static(
            Ipv4Addr::new(198, 18, 0, 2),
            Ipv4Addr::new(255, 255, 255, 0),
            [2, 0, 0, 0, 0, 1],
        );
        let mut a = Adapter::new(device, net, 7);
        let peer = SocketAddrV4::new(Ipv4Addr::new(198, 18, 0, 1), 50000);
        a.tcp_accept(SocketId(0), peer, Instant(0));
        let mut frame = [0u8; 256];
        let mut reply = [0u8; MAX_ENCAP_FRAME];
        let n = originator::register_session(&mut frame).unwrap();
        let out = a.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
        let session = EncapRepr::parse_header(&reply[..out.reply_len])
            .unwrap()
            .session_handle;
        let fo = ForwardOpenRepr {
            large: false,
            priority_tick: 0x0A,
            timeout_ticks: 0x0E,
            o_t_connection_id: 0,
            t_o_connection_id: 0x4C00_0001,
            triad: Triad {
                connection_serial: 1,
                vendor_id: 0xBEEF,
                originator_serial: 0x7E57,
            },
            timeout_multiplier: 2,
            o_t_rpi: rpi_us,
            o_t_params: NetworkParams::from_u16(0x4800 | 38),
            t_o_rpi: rpi_us,
            t_o_params: NetworkParams::from_u16(0x4800 | 34),
            transport: 0x01,
            path: &[0x20, 0x04, 0x24, 151, 0x2C, 150, 0x2C, 100],
        };
        let mut data = [0u8; 128];
        let mut w = Writer::new(&mut data);
        fo.emit(&mut w).unwrap();
        let len = w.len();
        let cm = [
            SegmentRepr::Logical(LogicalType::Class, 6),
            SegmentRepr::Logical(LogicalType::Instance, 1),
        ];
        let n = originator::send_rr_data(&mut frame, session, None, |w| {
            originator::request(w, 0x54, &cm, &data[..len])
        })
        .unwrap();
        let out = a.tcp_receive(SocketId(0), &frame[..n], Instant(0), &mut reply);
        let r = parse_reply(&reply[..out.reply_len])
            .unwrap()
            .response
            .unwrap();
        let words = r
            .additional_status
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect();
        (r.general_status, words)
    }

    #[test]
    fn a_forward_open_below_the_floor_is_refused_through_the_adapter() {
        use crate::diagnostics::{Diagnosed, Platform, StackUse};
        let platform = Platform {
            stack: || StackUse {
                size: 0,
                painted: 0,
                deepest: 0,
            },
            provoke: None,
        };
        // As a board stacks them: its diagnostics in front of its floor in front of the device.
        let board = || Diagnosed::new(RpiFloor::new(Generic::new(), |_| 8_000), platform);
        let (status, words) = open_at(board(), 1_000);
        assert_eq!(status, 0x01);
        assert_eq!(words[0], RPI_NOT_ACCEPTABLE);
        assert_eq!((words[2], words[4]), (8_000, 8_000));
        assert_eq!(open_at(board(), 8_000), (0, heapless::Vec::new()));
        // Without the floor the stack's own minimum (1 ms) is all that holds.
        assert_eq!(open_at(Generic::new(), 1_000), (0, heapless::Vec::new()));
    }

    #[test]
    fn a_floor_above_the_largest_rpi_is_the_largest_rpi() {
        let mut device = RpiFloor::new(Generic::new(), |_| u32::MAX);
        assert_eq!(
            device.admit(&request(Kind::ExclusiveOwner, MAX_RPI_US, 34)),
            Ok(())
        );
    }
}
