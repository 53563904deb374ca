//! Reading QEMU's execution trace of the emulated board for `cargo xtask bench --qemu`
//! ([`crate::bench_qemu`]): the firmware's symbols, every translation block's instructions
//! attributed to its function, the cycles counted by a marker function (the executor's idle
//! loop left out), and the latencies within a wake-up; the parts of the firmware.

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::Command;

use crate::util::{self, output, Result};

/// The firmware's functions: start address, end address, demangled name; sorted.
pub struct Symbols(Vec<(u32, u32, String)>);

impl Symbols {
    /// Reads the function symbols of `elf` (`arm-none-eabi-nm`).
    pub fn read(elf: &Path) -> Result<Symbols> {
        let elf = elf.to_string_lossy();
        let text = output(Command::new("arm-none-eabi-nm").args(["-C", "-S", "-n", &elf]))
            .ok_or_else(|| util::Error(format!("arm-none-eabi-nm {elf} failed")))?;
        let mut all = Vec::new();
        for line in text.lines() {
            let mut cols = line.splitn(4, ' ');
            let (Some(addr), Some(size), Some("t" | "T" | "W"), Some(name)) =
                (cols.next(), cols.next(), cols.next(), cols.next())
            else {
                continue;
            };
            let (Ok(addr), Ok(size)) =
                (u32::from_str_radix(addr, 16), u32::from_str_radix(size, 16))
            else {
                continue;
            };
            // Thumb functions have bit 0 set in their symbol value.
            let start = addr & !1;
            all.push((start, start + size, name.to_string()));
        }
        all.sort();
        Ok(Symbols(all))
    }

    /// Index of the function holding `pc`, if any.
    pub fn find(&self, pc: u32) -> Option<usize> {
        let i = self.0.partition_point(|(start, _, _)| *start <= pc);
        let i = i.checked_sub(1)?;
        (pc < self.0[i].1).then_some(i)
    }

    pub fn name(&self, i: Option<usize>) -> &str {
        i.map_or("?", |i| self.0[i].2.as_str())
    }

    /// True if a function starts at `pc`.
    fn starts(&self, pc: u32) -> bool {
        self.find(pc).is_some_and(|i| self.0[i].0 == pc)
    }

    /// Start address of the function called `name`.
    pub fn start_of(&self, name: &str) -> Option<u32> {
        self.0.iter().find(|s| s.2 == name).map(|s| s.0)
    }

    /// Start addresses of the functions whose name ends with `suffix`.
    pub fn starts_ending(&self, suffix: &str) -> Vec<u32> {
        self.0
            .iter()
            .filter(|s| s.2.ends_with(suffix))
            .map(|s| s.0)
            .collect()
    }
}

/// What a traced run counted over its cycles.
#[derive(Default)]
pub struct Cost {
    pub cycles: u64,
    /// Instructions by function index (`None`: outside every symbol).
    by_function: HashMap<Option<usize>, u64>,
    /// Instructions by translation block (its first address): the finer attribution
    /// written to `blocks-N.txt` beside the logs.
    by_block: HashMap<u32, u64>,
    /// Entries of a function (its start) from a block (the one run before): the callers.
    calls: HashMap<(u32, u32), u64>,
    /// Function names, resolved.
    pub names: Vec<(String, u64)>,
    /// Instructions from a wake-up of the board to the device's `write_assembly`, per call.
    pub to_device: Vec<u64>,
    /// Instructions from `write_assembly` (where the device marks its input changed) to the
    /// T->O frame handed to the driver in the same wake-up, per frame.
    pub to_driver: Vec<u64>,
    /// Wake-ups of the link task over the cycles counted (calls of its loop's body).
    pub wake_ups: u64,
}

impl Cost {
    pub fn total(&self) -> u64 {
        self.names.iter().map(|(_, n)| n).sum()
    }

    pub fn per_cycle(&self, n: u64) -> f64 {
        (n as f64 / self.cycles.max(1) as f64 * 10.0).round() / 10.0
    }

    /// Link task wake-ups per cycle, to two decimals.
    pub fn wake_ups_per_cycle(&self) -> f64 {
        (self.wake_ups as f64 / self.cycles.max(1) as f64 * 100.0).round() / 100.0
    }

    /// Calls of the functions starting at `starts` over the cycles counted.
    pub fn calls_into(&self, starts: &[u32]) -> u64 {
        self.calls
            .iter()
            .filter(|((_, to), _)| starts.contains(to))
            .map(|(_, n)| n)
            .sum()
    }

    /// One line per translation block, the costliest first: its address, instructions per
    /// cycle and function (for `addr2line` on the image).
    pub fn blocks(&self, symbols: &Symbols) -> String {
        let mut blocks: Vec<_> = self.by_block.iter().collect();
        blocks.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        blocks
            .into_iter()
            .map(|(pc, n)| {
                let name = symbols.name(symbols.find(*pc));
                format!("{pc:08x} {:>8.1} {name}\n", self.per_cycle(*n))
            })
            .chain(self.calls.iter().map(|((from, to), n)| {
                let (caller, callee) = (symbols.find(*from), symbols.find(*to));
                format!(
                    "call {from:08x} {:>6.2} {} -> {}\n",
                    self.per_cycle(*n),
                    symbols.name(caller),
                    symbols.name(callee)
                )
            }))
            .collect()
    }

    /// Instructions by part of the firmware.
    pub fn by_part(&self) -> BTreeMap<&'static str, u64> {
        let mut parts = BTreeMap::new();
        for (name, n) in &self.names {
            *parts.entry(part(name)).or_default() += n;
        }
        parts
    }

    pub fn to_json(&self, connections: u32, rpi_us: u32) -> serde_json::Value {
        let parts: serde_json::Map<_, _> = self
            .by_part()
            .into_iter()
            .map(|(k, v)| (k.to_string(), self.per_cycle(v).into()))
            .collect();
        let top: Vec<_> = self
            .names
            .iter()
            .take(15)
            .map(|(name, n)| serde_json::json!([name, self.per_cycle(*n)]))
            .collect();
        serde_json::json!({
            "connections": connections,
            "rpi_us": rpi_us,
            "cycles": self.cycles,
            "per_cycle": self.per_cycle(self.total()),
            "link_wake_ups_per_cycle": self.wake_ups_per_cycle(),
            "by_part": parts,
            "top_functions": top,
            "o_t_to_write_assembly_median": median(&self.to_device),
            "change_to_driver_median": median(&self.to_driver),
        })
    }
}

/// The part of the firmware a function belongs to, by the crate in its demangled name.
fn part(name: &str) -> &'static str {
    if name.contains("TaskStorage<F>::poll") || name.contains("embassy_futures::") {
        return "tasks (inlined futures)";
    }
    let path = name.trim_start_matches(['<', '&', '_']);
    match path.split("::").next().unwrap_or("") {
        "enip_stack" => "enip-stack",
        "enip_firmware" => "firmware runtime",
        "enip_profiles" => "device profile",
        "smoltcp" => "smoltcp",
        "embassy_net" => "embassy-net",
        "enip_qemu_mps2" => "board: LAN9118, timers",
        k if k.starts_with("embassy_") || k == "critical_section" || k == "cortex_m" => {
            "executor, time queue"
        }
        "core" | "compiler_builtins" => "builtins (memcpy, division)",
        k if k.starts_with("mem") || k.starts_with("aeabi") => "builtins (memcpy, division)",
        _ => "other",
    }
}

/// The median of `samples` (0 if none).
pub fn median(samples: &[u64]) -> u64 {
    let mut sorted = samples.to_vec();
    sorted.sort_unstable();
    sorted.get(sorted.len() / 2).copied().unwrap_or(0)
}

/// A translation block: its function and instruction count, and whether it holds the WFE.
#[derive(Clone, Copy)]
struct Block {
    function: Option<usize>,
    instructions: u32,
    wfe: bool,
}

/// The addresses [`count`] watches.
pub struct Marks {
    /// The cycle's marker function.
    pub marker: u32,
    /// The device's `write_assembly` (each profile's in the image).
    pub write_assembly: Vec<u32>,
    /// The driver's frame push, if the image has it.
    pub push_frame: Option<u32>,
}

/// Reads QEMU's log from `fifo` until QEMU stops; counts the instructions of the `wanted.1`
/// calls of the marker after the first `wanted.0` (idle loop excluded), and the latencies
/// (`Cost::to_device`, `Cost::to_driver`) within them. Once the marker is called after the
/// last counted call (its cycle is whole), creates the file `stop`: the load may end.
pub fn count(
    fifo: &Path,
    symbols: &Symbols,
    marks: &Marks,
    wanted: (u64, u64),
    stop: &Path,
) -> Result<Cost> {
    let file = fs::File::open(fifo)?;
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let mut blocks: HashMap<u32, Block> = HashMap::new();
    let mut line = Vec::with_capacity(256);
    let mut translating: Option<(u32, u32, bool)> = None;
    // Blocks run since the last WFE, and whether any ran outside the idle loop's function.
    let mut segment: Vec<u32> = Vec::new();
    let mut busy = false;
    let mut idle_function: Option<Option<usize>> = None;
    let mut markers = 0u64;
    let mut cost = Cost::default();
    // Instructions since the wake-up (the first block outside the idle loop after a WFE),
    // and where in them the device's last `write_assembly` began.
    let mut woken = 0u64;
    let mut written: Option<u64> = None;
    loop {
        line.clear();
        if reader.read_until(b'\n', &mut line)? == 0 {
            break;
        }
        if let Some(rest) = line.strip_prefix(b"Trace ") {
            let Some(pc) = trace_pc(rest) else { continue };
            let Some(block) = blocks.get(&pc).copied() else {
                continue;
            };
            if pc == marks.marker {
                markers += 1;
                if markers == wanted.0 + wanted.1 + 1 {
                    // Reading goes on either way (QEMU must not stall on a full FIFO); without
                    // the file the load runs its whole length.
                    let _ = fs::write(stop, b"");
                }
            }
            let counting = markers > wanted.0 && markers <= wanted.0 + wanted.1;
            if block.wfe {
                idle_function.get_or_insert(block.function);
                if busy && counting {
                    let mut previous = None;
                    for pc in segment.drain(..).chain([pc]) {
                        if let Some(b) = blocks.get(&pc) {
                            *cost.by_function.entry(b.function).or_default() +=
                                u64::from(b.instructions);
                            *cost.by_block.entry(pc).or_default() += u64::from(b.instructions);
                            if let Some(from) = previous.filter(|_| symbols.starts(pc)) {
                                *cost.calls.entry((from, pc)).or_default() += 1;
                            }
                        }
                        previous = Some(pc);
                    }
                }
                segment.clear();
                busy = false;
                (woken, written) = (0, None);
                continue;
            }
            busy |= Some(block.function) != idle_function;
            if busy && counting {
                if marks.write_assembly.contains(&pc) {
                    cost.to_device.push(woken);
                    written = Some(woken);
                } else if Some(pc) == marks.push_frame {
                    if let Some(at) = written.take() {
                        cost.to_driver.push(woken - at);
                    }
                }
            }
            if busy {
                woken += u64::from(block.instructions);
            }
            segment.push(pc);
        } else if line.starts_with(b"IN:") {
            translating = Some((0, 0, false));
        } else if let Some((start, n, wfe)) = translating.as_mut() {
            if let Some(pc) = asm_pc(&line) {
                if *n == 0 {
                    *start = pc;
                }
                *n += 1;
                *wfe |= line.windows(5).any(|w| w == b" wfe ");
            } else if line.iter().all(u8::is_ascii_whitespace) && *n > 0 {
                let (start, n, wfe) = (*start, *n, *wfe);
                blocks.insert(
                    start,
                    Block {
                        function: symbols.find(start),
                        instructions: n,
                        wfe,
                    },
                );
                translating = None;
            }
        }
    }
    cost.cycles = markers.saturating_sub(wanted.0).min(wanted.1);
    let mut names: Vec<(String, u64)> = cost
        .by_function
        .iter()
        .map(|(f, n)| (symbols.name(*f).to_string(), *n))
        .collect();
    names.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    cost.names = names;
    Ok(cost)
}

/// The guest address of an `exec` log line (after `Trace `):
/// `0: 0x7f... [00800408/0000ad3e/00000010/ff000200] symbol`.
fn trace_pc(rest: &[u8]) -> Option<u32> {
    let open = rest.iter().position(|&b| b == b'[')?;
    let fields = rest.get(open + 1..)?;
    let slash = fields.iter().position(|&b| b == b'/')?;
    let pc = fields.get(slash + 1..slash + 9)?;
    u32::from_str_radix(std::str::from_utf8(pc).ok()?, 16).ok()
}

/// The address of an `in_asm` instruction line: `0x0000ad64:  bf20       wfe`.
fn asm_pc(line: &[u8]) -> Option<u32> {
    let hex = line.strip_prefix(b"0x")?;
    let colon = hex.iter().position(|&b| b == b':')?;
    u32::from_str_radix(std::str::from_utf8(hex.get(..colon)?).ok()?, 16).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_lines_give_guest_addresses() {
        assert_eq!(
            trace_pc(b"0: 0x7f1150074f80 [00800408/0000ad3e/00000010/ff000200] run\n"),
            Some(0xad3e)
        );
        assert_eq!(trace_pc(b"0: garbage\n"), None);
        assert_eq!(asm_pc(b"0x0000ad64:  bf20       wfe      \n"), Some(0xad64));
        assert_eq!(asm_pc(b"IN: Reset\n"), None);
    }

    #[test]
    fn functions_fall_into_parts() {
        assert_eq!(
            part("smoltcp::iface::interface::Interface::poll"),
            "smoltcp"
        );
        assert_eq!(
            part("<embassy_net::tcp::TcpSocket as core::ops::Drop>::drop"),
            "embassy-net"
        );
        assert_eq!(
            part("enip_qemu_mps2::lan9118::on_interrupt"),
            "board: LAN9118, timers"
        );
        assert_eq!(part("memcpy"), "builtins (memcpy, division)");
        assert_eq!(part("__aeabi_uldivmod"), "builtins (memcpy, division)");
        assert_eq!(
            part("embassy_executor::raw::SyncExecutor::poll"),
            "executor, time queue"
        );
        assert_eq!(part("enip_stack::io::ConnectionTable::close"), "enip-stack");
    }
}
