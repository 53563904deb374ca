//! The log of a host adapter: `env_logger` on stderr (`RUST_LOG`, default `info`), each line
//! of a fleet's device prefixed by the device's label, which the loop sets while it serves
//! that device ([`set_current`]).

use std::cell::Cell;
use std::io::Write;

thread_local! {
    /// The label of the device being served on this thread.
    static CURRENT: Cell<Option<&'static str>> = const { Cell::new(None) };
}

/// Prefixes this thread's log lines with `label` from now on (`None`: no prefix).
pub fn set_current(label: Option<&'static str>) {
    CURRENT.with(|c| c.set(label));
}

/// Installs the logger (once; later calls do nothing).
pub fn init() {
    let _ = env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format(|buf, record| {
            let ts = buf.timestamp_millis();
            let style = buf.default_level_style(record.level());
            write!(
                buf,
                "[{ts} {style}{:<5}{style:#} {}] ",
                record.level(),
                record.target()
            )?;
            if let Some(label) = CURRENT.with(Cell::get) {
                write!(buf, "{label}: ")?;
            }
            writeln!(buf, "{}", record.args())
        })
        .try_init();
}
