//! The vendor classes: [`parameter`], class 0x0F, the drive's parameters by instance with
//! the dynamic map's lists; [`position_controller`], class 0x25, the Position Controller;
//! [`supervisor`], class 0x24, the Position Controller Supervisor.

pub mod parameter;
pub mod position_controller;
pub mod supervisor;
