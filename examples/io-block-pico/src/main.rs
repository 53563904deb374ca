//! The example I/O block as W5500-EVB-Pico firmware: the device plus one library call.
//!
//! ```text
//! cargo run -p io-block-pico --release --target thumbv6m-none-eabi   # probe-rs flashes it
//! ```
#![no_std]
#![no_main]

use embassy_executor::Spawner;
use enip_w5500_evb_pico::AdapterCell;

/// The adapter over the I/O block, for the whole run.
static ADAPTER: AdapterCell<io_block::IoBlock> = AdapterCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    defmt::info!("io-block-pico: booting");
    let network = enip_w5500_evb_pico::static_ipv4([192, 168, 1, 10], 24, None);
    // The I/O block saves nothing: it leaves the non-volatile store to the adapter.
    let device = |_store| io_block::IoBlock::new();
    enip_w5500_evb_pico::run(spawner, &ADAPTER, device, network).await
}
