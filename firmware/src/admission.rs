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

    #[test]
    fn a_floor_above_the_largest_rpi_is_the_largest_rpi() {
        let mut device = RpiFloor::new(Generic::new(), |_| u32::MAX);
        assert_eq!(
            device.admit(&request(Kind::ExclusiveOwner, MAX_RPI_US, 34)),
            Ok(())
        );
    }
}
