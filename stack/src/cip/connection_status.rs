//! Connection Manager extended status codes (general status 0x01), Vol 1 table 3-5.33.

/// Connection in use or duplicate Forward_Open.
pub const DUPLICATE: u16 = 0x0100;
/// Transport class and trigger combination not supported.
pub const TRANSPORT_NOT_SUPPORTED: u16 = 0x0103;
/// Ownership conflict.
pub const OWNERSHIP_CONFLICT: u16 = 0x0106;
/// Target connection not found (Forward_Close).
pub const NOT_FOUND: u16 = 0x0107;
/// Invalid network connection parameter.
pub const BAD_NETWORK_PARAMS: u16 = 0x0108;
/// Invalid connection size.
pub const BAD_SIZE: u16 = 0x0109;
/// Target for the connection not configured (the device refused its configuration).
pub const NOT_CONFIGURED: u16 = 0x0110;
/// RPI value(s) not acceptable.
pub const RPI_NOT_ACCEPTABLE: u16 = 0x0112;
/// Out of connections.
pub const OUT_OF_CONNECTIONS: u16 = 0x0113;
/// Vendor ID or product code mismatch.
pub const KEY_VENDOR_PRODUCT: u16 = 0x0114;
/// Device type mismatch.
pub const KEY_DEVICE_TYPE: u16 = 0x0115;
/// Revision mismatch.
pub const KEY_REVISION: u16 = 0x0116;
/// Non-listen-only connection not opened (listen-only without an owner).
pub const NO_OWNER_FOR_LISTEN_ONLY: u16 = 0x0119;
/// RPI smaller than the production inhibit time.
pub const RPI_BELOW_INHIBIT: u16 = 0x011B;
/// O->T redundant owner flag not supported (this stack has no redundant owner connections).
pub const REDUNDANT_OWNER: u16 = 0x0125;
/// Invalid configuration size.
pub const BAD_CONFIG_SIZE: u16 = 0x0126;
/// Invalid O->T size.
pub const BAD_O_T_SIZE: u16 = 0x0127;
/// Invalid T->O size.
pub const BAD_T_O_SIZE: u16 = 0x0128;
/// Invalid configuration application path.
pub const BAD_CONFIG_PATH: u16 = 0x0129;
/// Invalid consuming application path.
pub const BAD_CONSUMING_PATH: u16 = 0x012A;
/// Invalid producing application path.
pub const BAD_PRODUCING_PATH: u16 = 0x012B;
/// Null Forward_Open not supported.
pub const NULL_FORWARD_OPEN: u16 = 0x0132;
/// Connection timeout multiplier not acceptable.
pub const BAD_TIMEOUT_MULTIPLIER: u16 = 0x0133;
/// Mismatched T->O fixed/variable flag (joining an existing multicast production).
pub const MISMATCHED_FIXED_VARIABLE: u16 = 0x0135;
/// Mismatched T->O priority (joining an existing multicast production).
pub const MISMATCHED_PRIORITY: u16 = 0x0136;
/// Mismatched T->O production trigger (joining an existing multicast production).
pub const MISMATCHED_TRIGGER: u16 = 0x0138;
/// Mismatched production inhibit time (joining an existing multicast production).
pub const MISMATCHED_INHIBIT: u16 = 0x0139;
/// Invalid segment in the connection path.
pub const BAD_SEGMENT: u16 = 0x0315;
/// Multicast T->O requested by an originator off the subnet while the TTL keeps it local.
pub const MULTICAST_OFF_SUBNET: u16 = 0x0813;

/// The meaning of extended status `ext` in words, for logs ("" for one this stack does not
/// name).
pub const fn describe(ext: u16) -> &'static str {
    match ext {
        DUPLICATE => "connection in use or duplicate Forward_Open",
        TRANSPORT_NOT_SUPPORTED => "transport class and trigger not supported",
        OWNERSHIP_CONFLICT => "ownership conflict: another exclusive owner holds the outputs",
        NOT_FOUND => "no such connection",
        BAD_NETWORK_PARAMS => "invalid network connection parameter",
        BAD_SIZE => "invalid connection size",
        NOT_CONFIGURED => "the device refused the configuration",
        RPI_NOT_ACCEPTABLE => "RPI not acceptable",
        OUT_OF_CONNECTIONS => "out of connections",
        KEY_VENDOR_PRODUCT => "electronic key: vendor ID or product code mismatch",
        KEY_DEVICE_TYPE => "electronic key: device type mismatch",
        KEY_REVISION => "electronic key: revision mismatch",
        NO_OWNER_FOR_LISTEN_ONLY => "listen only without a connection to follow",
        RPI_BELOW_INHIBIT => "RPI smaller than the production inhibit time",
        REDUNDANT_OWNER => "redundant owner connections not supported",
        BAD_CONFIG_SIZE => "invalid configuration size",
        BAD_O_T_SIZE => "invalid O->T size",
        BAD_T_O_SIZE => "invalid T->O size",
        BAD_CONFIG_PATH => "invalid configuration application path",
        BAD_CONSUMING_PATH => "invalid consuming application path",
        BAD_PRODUCING_PATH => "invalid producing application path",
        NULL_FORWARD_OPEN => "null Forward_Open not supported",
        BAD_TIMEOUT_MULTIPLIER => "connection timeout multiplier not acceptable",
        MISMATCHED_FIXED_VARIABLE => "T->O fixed/variable differs from the multicast it joins",
        MISMATCHED_PRIORITY => "T->O priority differs from the multicast it joins",
        MISMATCHED_TRIGGER => "production trigger differs from the multicast it joins",
        MISMATCHED_INHIBIT => "production inhibit time differs from the multicast it joins",
        BAD_SEGMENT => "invalid segment in the connection path",
        MULTICAST_OFF_SUBNET => "multicast T->O requested from another subnet with TTL 1",
        _ => "",
    }
}
