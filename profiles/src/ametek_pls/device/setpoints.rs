//! An output's setpoint pattern (§2.4, 2.5): standard windows, stitching, time-based and
//! motion-detect setpoints, with speed compensation and remote setpoint tune.

use super::super::params::{setpoint, Config, HIGH_SPEED};
use super::geometry::{interpolate, shift, window};

/// Output `o`'s setpoint pattern at position `pos` (scale factor `sf`) and speed `rpm`,
/// its setpoints advanced by `tune` counts; `timed` says whether a time-based setpoint is
/// still within its time.
pub fn pattern(
    cfg: &Config,
    o: usize,
    pos: u16,
    sf: u16,
    rpm: u16,
    tune: i32,
    timed: bool,
) -> bool {
    let prog = cfg.program(o);
    if prog.count == 0 {
        return false;
    }
    let c = prog.compensation;
    let (lead, trail) = if o < HIGH_SPEED && c.iter().any(|&x| x != 0) {
        (
            interpolate(rpm, c[0], c[3], c[1], c[4]),
            interpolate(rpm, c[0], c[3], c[2], c[5]),
        )
    } else {
        (0, 0)
    };
    let std_window = |on: u16, off: u16| {
        let on = shift(on, tune + lead, sf);
        let off = shift(off, tune + trail, sf);
        window(pos, on, off)
    };
    let [p1, p2, p3, p4] = prog.params;
    let first = match prog.kind {
        setpoint::STANDARD => std_window(p1, p2),
        setpoint::STITCHING => {
            let on = shift(p1, tune + lead, sf);
            let off = shift(p2, tune + trail, sf);
            let cycle = u32::from(p3) + u32::from(p4);
            let into = (u32::from(pos) + u32::from(sf) - u32::from(on)) % u32::from(sf);
            window(pos, on, off) && (cycle == 0 || into % cycle < u32::from(p3))
        }
        setpoint::TIME_BASED => timed,
        setpoint::MOTION_DETECT => rpm >= p1,
        _ => false,
    };
    let rest = prog
        .extra
        .iter()
        .take(usize::from(prog.count.saturating_sub(1)).min(7))
        .any(|&(on, off)| std_window(on, off));
    first || rest
}
