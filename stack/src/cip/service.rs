//! CIP service codes used by the standard objects.

/// Get_Attributes_All.
pub const GET_ATTRIBUTES_ALL: u8 = 0x01;
/// Set_Attributes_All.
pub const SET_ATTRIBUTES_ALL: u8 = 0x02;
/// Get_Attribute_List.
pub const GET_ATTRIBUTE_LIST: u8 = 0x03;
/// Set_Attribute_List.
pub const SET_ATTRIBUTE_LIST: u8 = 0x04;
/// Reset.
pub const RESET: u8 = 0x05;
/// Multiple_Service_Packet.
pub const MULTIPLE_SERVICE_PACKET: u8 = 0x0A;
/// Get_Attribute_Single.
pub const GET_ATTRIBUTE_SINGLE: u8 = 0x0E;
/// Set_Attribute_Single.
pub const SET_ATTRIBUTE_SINGLE: u8 = 0x10;
/// Get_and_Clear (Ethernet Link counters).
pub const GET_AND_CLEAR: u8 = 0x4C;
/// Forward_Close (Connection Manager).
pub const FORWARD_CLOSE: u8 = 0x4E;
/// Unconnected_Send (Connection Manager).
pub const UNCONNECTED_SEND: u8 = 0x52;
/// Forward_Open (Connection Manager).
pub const FORWARD_OPEN: u8 = 0x54;
/// Large_Forward_Open (Connection Manager).
pub const LARGE_FORWARD_OPEN: u8 = 0x5B;
