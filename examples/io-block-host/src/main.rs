//! The example I/O block on a Linux TAP device: the device plus one library call
//! (`io-block-host --eds` prints its EDS).
//!
//! ```text
//! ip netns add lab && ip -n lab tuntap add dev tap0 mode tap && ip -n lab link set tap0 up
//! ip -n lab addr add 198.18.0.1/24 dev tap0
//! ip netns exec lab cargo run -p io-block-host -- --tap tap0 --ip 198.18.0.2/24
//! ```

fn main() {
    enip_host::run_device(io_block::IoBlock::new(), &io_block::EDS)
}
