//! The example I/O block as NUCLEO-H563ZI firmware: the device plus one library call.
//!
//! ```text
//! cargo build -p io-block-nucleo-h563zi --release --target thumbv8m.main-none-eabihf
//! probe-rs run --chip STM32H563ZITx target/thumbv8m.main-none-eabihf/release/io-block-nucleo-h563zi
//! ```
#![no_std]
#![no_main]

use embassy_executor::Spawner;
use enip_nucleo_h563zi::AdapterCell;

/// The adapter over the I/O block, for the whole run.
static ADAPTER: AdapterCell<io_block::IoBlock> = AdapterCell::new();

#[embassy_executor::main]
async fn main(spawner: Spawner) {
    defmt::info!("io-block-nucleo-h563zi: booting");
    let network = enip_nucleo_h563zi::static_ipv4([192, 168, 1, 10], 24, None);
    // The I/O block saves nothing: it leaves the non-volatile store to the adapter.
    let device = |_store| io_block::IoBlock::new();
    enip_nucleo_h563zi::run(spawner, &ADAPTER, device, network).await
}
