//! The example I/O block on a Linux TAP device: the device plus one library call.
//!
//! ```text
//! ip netns add lab && ip -n lab tuntap add dev tap0 mode tap && ip -n lab link set tap0 up
//! ip -n lab addr add 198.18.0.1/24 dev tap0
//! ip netns exec lab cargo run -p io-block-host -- --tap tap0 --ip 198.18.0.2/24
//! ```

const USAGE: &str = "usage: io-block-host --tap IFNAME --ip A.B.C.D/LEN [options]";

fn main() {
    let options = enip_host::Options::from_env_args(
        &format!("{USAGE}\n\n{}", enip_host::OPTIONS_USAGE),
        |_, _| Ok(false),
    );
    enip_host::run(io_block::IoBlock::new(), options)
}
