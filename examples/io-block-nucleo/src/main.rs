//! The example I/O block as NUCLEO-F767ZI firmware: the device plus one library call.
//!
//! ```text
//! cargo run -p io-block-nucleo --release --target thumbv7em-none-eabihf   # probe-rs flashes it
//! ```
#![no_std]
#![no_main]

use embassy_executor::Spawner;

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    defmt::info!("io-block-nucleo: booting");
    let network = enip_nucleo_f767zi::static_ipv4([192, 168, 1, 10], 24, None);
    // The I/O block saves nothing: it leaves the non-volatile store to the adapter.
    enip_nucleo_f767zi::run(spawner, |_store| io_block::IoBlock::new(), network).await
}
