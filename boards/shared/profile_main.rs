// The firmware `main` of every board on real hardware, `include!`d by its `main.rs` and
// expanded there with `profile_main!(board_crate, "board-name")`: the device profile chosen
// by the `profile-NAME` feature (the build script writes `profile.rs`), the interface from
// the build-time settings (`network.rs`) or, with the `dhcp` feature, from DHCP.

/// Expands to the board firmware's `main` over the board crate `$board`, logged as `$name`.
macro_rules! profile_main {
    ($board:ident, $name:literal) => {
        /// The device profile chosen by the `profile-NAME` feature.
        mod profile {
            include!(concat!(env!("OUT_DIR"), "/profile.rs"));
        }

        /// The build-time network settings.
        #[cfg(not(feature = "dhcp"))]
        mod network {
            include!(concat!(env!("OUT_DIR"), "/network.rs"));
        }

        use enip_profiles::PoweredUp;

        /// The adapter over the chosen profile, for the whole run.
        static ADAPTER: $board::AdapterCell<profile::Chosen> = $board::AdapterCell::new();

        #[embassy_executor::main]
        async fn main(spawner: embassy_executor::Spawner) {
            defmt::info!("{=str}: booting (profile {})", $name, profile::NAME);
            let device = profile::Chosen::powered_up;
            $board::run(spawner, &ADAPTER, device, net_config()).await
        }

        /// The interface configuration: DHCP with the `dhcp` feature, else the build-time
        /// address.
        fn net_config() -> embassy_net::Config {
            #[cfg(feature = "dhcp")]
            {
                $board::dhcp()
            }
            #[cfg(not(feature = "dhcp"))]
            {
                $board::static_ipv4(network::ADDRESS, network::PREFIX_LEN, network::GATEWAY)
            }
        }
    };
}
