//! The assemblies of the OpENer sample application: input 100, output 150 (echoed into
//! 100), configuration 151, the heartbeat points 152 and 153, and 154 for explicit
//! messaging.

use enip_stack::{AssemblyInfo, AssemblyRole};

/// Input assembly (T->O data).
pub const INPUT: u16 = 100;
/// Output assembly (O->T data, with the run/idle header); echoed into [`INPUT`].
pub const OUTPUT: u16 = 150;
/// Configuration assembly.
pub const CONFIG: u16 = 151;
/// O->T connection point of input-only connections.
pub const INPUT_ONLY_HEARTBEAT: u16 = 152;
/// O->T connection point of listen-only connections.
pub const LISTEN_ONLY_HEARTBEAT: u16 = 153;
/// Assembly for explicit messaging only: reads back what was written.
pub const EXPLICIT: u16 = 154;

/// Size of the input, output and explicit assemblies in bytes.
pub const IO_SIZE: usize = 32;
/// Size of the configuration assembly in bytes.
pub const CONFIG_SIZE: usize = 10;

/// The assembly instances, as the stack sees them.
pub const ASSEMBLIES: [AssemblyInfo; 6] = [
    assembly(INPUT, AssemblyRole::Input, IO_SIZE, false),
    assembly(OUTPUT, AssemblyRole::Output, IO_SIZE, true),
    assembly(CONFIG, AssemblyRole::Config, CONFIG_SIZE, false),
    assembly(
        INPUT_ONLY_HEARTBEAT,
        AssemblyRole::InputOnlyHeartbeat,
        0,
        false,
    ),
    assembly(
        LISTEN_ONLY_HEARTBEAT,
        AssemblyRole::ListenOnlyHeartbeat,
        0,
        false,
    ),
    assembly(EXPLICIT, AssemblyRole::Explicit, IO_SIZE, false),
];

const fn assembly(
    instance: u16,
    role: AssemblyRole,
    size: usize,
    run_idle_header: bool,
) -> AssemblyInfo {
    AssemblyInfo {
        instance,
        role,
        size: size as u16,
        run_idle_header,
    }
}
