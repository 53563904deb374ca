//! The assembly instances (§2.1, §3.1; instance numbers \[R\] AM-IO-4): input 100 (17 words,
//! T->O, no header), output 150 (7 words, O->T with the run/idle header), configuration 1
//! (the ":C" tag "is not used": 0 bytes), and the heartbeat points 198/199 of input-only and
//! listen-only connections.

use enip_stack::{AssemblyInfo, AssemblyRole};

/// Input assembly (T->O): 17 UINT words.
pub const INPUT: u16 = 100;
/// Output assembly (O->T): 7 UINT words.
pub const OUTPUT: u16 = 150;
/// Configuration assembly: no data.
pub const CONFIG: u16 = 1;
/// O->T point of input-only connections.
pub const INPUT_ONLY_HEARTBEAT: u16 = 198;
/// O->T point of listen-only connections.
pub const LISTEN_ONLY_HEARTBEAT: u16 = 199;

/// Bytes of the input assembly.
pub const INPUT_BYTES: usize = 34;
/// Bytes of the output assembly.
pub const OUTPUT_BYTES: usize = 14;

/// Every instance, as the stack sees it.
pub const INFOS: [AssemblyInfo; 5] = [
    AssemblyInfo {
        instance: CONFIG,
        role: AssemblyRole::Config,
        size: 0,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: INPUT,
        role: AssemblyRole::Input,
        size: INPUT_BYTES as u16,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: OUTPUT,
        role: AssemblyRole::Output,
        size: OUTPUT_BYTES as u16,
        run_idle_header: true,
    },
    AssemblyInfo {
        instance: INPUT_ONLY_HEARTBEAT,
        role: AssemblyRole::InputOnlyHeartbeat,
        size: 0,
        run_idle_header: false,
    },
    AssemblyInfo {
        instance: LISTEN_ONLY_HEARTBEAT,
        role: AssemblyRole::ListenOnlyHeartbeat,
        size: 0,
        run_idle_header: false,
    },
];

/// The name of each instance (EDS, README).
pub fn name(instance: u16) -> &'static str {
    match instance {
        INPUT => "PLS input data (17 words)",
        OUTPUT => "PLS output data (7 words)",
        CONFIG => "Configuration (not used, no data)",
        INPUT_ONLY_HEARTBEAT => "Input only heartbeat",
        _ => "Listen only heartbeat",
    }
}
