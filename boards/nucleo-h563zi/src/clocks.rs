//! Clock tree: the ST-LINK's 8 MHz clock (HSE, digital bypass) through PLL1 to 250 MHz
//! (voltage scale 0), as embassy's STM32H5 Ethernet example; HSI48 for the RNG.

use embassy_stm32::rcc::{
    AHBPrescaler, APBPrescaler, Hse, HseMode, Pll, PllDiv, PllMul, PllPreDiv, PllSource, Sysclk,
    VoltageScale,
};
use embassy_stm32::time::Hertz;
use embassy_stm32::Config;

/// 8 MHz / 2 x 125 = 500 MHz VCO; P / 2 = 250 MHz system clock, AHB and APB1 to APB3 at
/// 250 MHz. The RNG's kernel clock is HSI48 (its reset selection; HSI48 is on by default).
pub fn config() -> Config {
    let mut config = Config::default();
    let rcc = &mut config.rcc;
    rcc.hsi = None;
    rcc.hse = Some(Hse {
        freq: Hertz(8_000_000),
        mode: HseMode::BypassDigital,
    });
    rcc.pll1 = Some(Pll {
        source: PllSource::HSE,
        prediv: PllPreDiv::DIV2,
        mul: PllMul::MUL125,
        divp: Some(PllDiv::DIV2),
        divq: None,
        divr: None,
    });
    rcc.sys = Sysclk::PLL1_P;
    rcc.ahb_pre = AHBPrescaler::DIV1;
    rcc.apb1_pre = APBPrescaler::DIV1;
    rcc.apb2_pre = APBPrescaler::DIV1;
    rcc.apb3_pre = APBPrescaler::DIV1;
    rcc.voltage_scale = VoltageScale::Scale0;
    config
}
