//! What a board without a command line chooses for the simulated resolver: its speed at
//! power-up, from `ENIP_PLS_RPM` at build time (the emulated and Nucleo boards; the host
//! board's `--pls-rpm` overrides it).

/// The resolver's speed at power-up, RPM forward: `ENIP_PLS_RPM` at build time, else 0.
pub const BUILD_RPM: u16 = match BUILD_SETTING {
    Some(rpm) => rpm,
    None => 0,
};

/// `ENIP_PLS_RPM` as read at build time.
const BUILD_SETTING: Option<u16> = match option_env!("ENIP_PLS_RPM") {
    Some(text) => parse_rpm(text),
    None => Some(0),
};

// A bad `ENIP_PLS_RPM` fails the build instead of leaving the resolver still.
const _: () = assert!(
    BUILD_SETTING.is_some(),
    "ENIP_PLS_RPM must be a decimal speed from 0 to 65535"
);

/// A decimal RPM 0-65535, or `None`.
pub const fn parse_rpm(text: &str) -> Option<u16> {
    let mut rest = text.as_bytes();
    if rest.is_empty() {
        return None;
    }
    let mut value: u32 = 0;
    while let [b, tail @ ..] = rest {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value
            .saturating_mul(10)
            .saturating_add(b.wrapping_sub(b'0') as u32);
        if value > u16::MAX as u32 {
            return None;
        }
        rest = tail;
    }
    Some(value as u16)
}
