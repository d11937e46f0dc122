//! The firmware's machine-read log lines, written ONCE: the chip prints them with
//! `defmt::Format` (feature `defmt`, which the firmware enables) and the host prints the
//! same text with [`core::fmt::Display`] (`camsim predict --f32` regenerates the parity
//! lines from it; `camsim firmware-check` reads the memory and reaction lines back).
//!
//! Every number of a parity line is raw f32 bits in `0x%08x` form, so the host's text
//! equals the chip's bit for bit or the runs differ.

use core::fmt;

use camsim_core::{SpeedPrediction, SpeedReading, SteadyState};

use crate::reading_parity;

/// The clock the budget's real-time factor assumes, Hz: the STM32F4's 168 MHz, one
/// instruction a cycle (a real M4F with flash wait states needs more cycles than
/// instructions). The QEMU demonstration image's boot time is stated at the same clock.
pub const CHIP_CLOCK_HZ: u64 = 168_000_000;
/// Cam speed of the budget's measured revolution, rpm (the reference design's 800 rpm).
pub const CHIP_NOMINAL_RPM: u64 = 800;

/// Real-time factor of a revolution at [`CHIP_NOMINAL_RPM`] that took `instr_per_rev`
/// instructions, at [`CHIP_CLOCK_HZ`] and one instruction a cycle: the real revolution's
/// cycles over the instructions (above 1: faster than real time).
pub fn realtime_factor(instr_per_rev: u64) -> f32 {
    let cycles_per_rev_real_time = CHIP_CLOCK_HZ * 60 / CHIP_NOMINAL_RPM;
    cycles_per_rev_real_time as f32 / instr_per_rev.max(1) as f32
}

/// Raw bits of the six timing errors.
fn timing_bits(t: &[f32; 6]) -> [u32; 6] {
    t.map(f32::to_bits)
}

/// One `parity ...` line: every value the host compares, as raw f32 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParityLine {
    /// A row of the boot table.
    Table {
        /// Row index.
        i: u32,
        /// Grid speed (bits).
        rpm: u32,
        /// Minimum contact force (bits).
        force: u32,
        /// Whether the follower separated.
        jumped: bool,
        /// The six timing errors (bits).
        timing: [u32; 6],
    },
    /// The jump onset (bits), or none up to the search limit.
    Jump(Option<u32>),
    /// A direct simulation between grid points (the interpolation check).
    Check {
        /// Speed (bits).
        rpm: u32,
        /// Minimum contact force (bits).
        force: u32,
        /// Whether the follower separated.
        jumped: bool,
        /// The six timing errors (bits).
        timing: [u32; 6],
    },
    /// A prediction at a vouched speed.
    Sample {
        /// Reading index.
        i: u32,
        /// Speed (bits).
        rpm: u32,
        /// Force margin (bits).
        force: u32,
        /// Speed margin (bits).
        speed: u32,
        /// Alarm asserted.
        alarm: bool,
        /// The six timing errors (bits).
        timing: [u32; 6],
    },
    /// A reading that does not vouch for the speed ([`reading_parity`]).
    Reading {
        /// Reading index.
        i: u32,
        /// [`SpeedReading::kind`].
        kind: &'static str,
        /// The reading's number ([`reading_parity`]).
        value: u32,
        /// Alarm asserted.
        alarm: bool,
    },
}

impl ParityLine {
    /// Row `i` of the boot table at grid speed `rpm`.
    pub fn table(i: u32, rpm: f32, s: &SteadyState<f32>) -> Self {
        Self::Table {
            i,
            rpm: rpm.to_bits(),
            force: s.min_contact_force.to_bits(),
            jumped: s.jumped,
            timing: timing_bits(&s.timing_deg),
        }
    }

    /// The jump onset of the table.
    pub fn jump(rpm: Option<f32>) -> Self {
        Self::Jump(rpm.map(f32::to_bits))
    }

    /// The direct simulation `d` at `rpm`.
    pub fn check(rpm: f32, d: &SteadyState<f32>) -> Self {
        Self::Check {
            rpm: rpm.to_bits(),
            force: d.min_contact_force.to_bits(),
            jumped: d.jumped,
            timing: timing_bits(&d.timing_deg),
        }
    }

    /// Reading `i`, a prediction at a vouched speed, with the alarm state.
    pub fn sample(i: u32, p: &SpeedPrediction<f32>, alarm: bool) -> Self {
        Self::Sample {
            i,
            rpm: p.rpm.to_bits(),
            force: p.force_margin_lb.to_bits(),
            speed: p.speed_margin_rpm.to_bits(),
            alarm,
            timing: timing_bits(&p.timing_deg),
        }
    }

    /// Reading `i`, one that does not vouch for the speed, with the alarm state.
    pub fn reading(i: u32, r: &SpeedReading<f32>, alarm: bool) -> Self {
        let (kind, value) = reading_parity(r);
        Self::Reading {
            i,
            kind,
            value,
            alarm,
        }
    }
}

/// Writes the six timing bits as `0x........,` x6.
fn write_timing(f: &mut fmt::Formatter<'_>, t: &[u32; 6]) -> fmt::Result {
    for (k, b) in t.iter().enumerate() {
        if k > 0 {
            f.write_str(",")?;
        }
        write!(f, "{b:#010x}")?;
    }
    Ok(())
}

impl fmt::Display for ParityLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Table {
                i,
                rpm,
                force,
                jumped,
                timing,
            } => {
                write!(
                    f,
                    "parity table i={i} rpm={rpm:#010x} force={force:#010x} jumped={jumped} timing="
                )?;
                write_timing(f, timing)
            }
            Self::Jump(Some(rpm)) => write!(f, "parity jump rpm={rpm:#010x}"),
            Self::Jump(None) => f.write_str("parity jump rpm=none"),
            Self::Check {
                rpm,
                force,
                jumped,
                timing,
            } => {
                write!(
                    f,
                    "parity check rpm={rpm:#010x} force={force:#010x} jumped={jumped} timing="
                )?;
                write_timing(f, timing)
            }
            Self::Sample {
                i,
                rpm,
                force,
                speed,
                alarm,
                timing,
            } => {
                write!(
                    f,
                    "parity sample i={i} rpm={rpm:#010x} force={force:#010x} speed={speed:#010x} alarm={alarm} timing="
                )?;
                write_timing(f, timing)
            }
            Self::Reading {
                i,
                kind,
                value,
                alarm,
            } => write!(
                f,
                "parity reading i={i} kind={kind} value={value:#010x} alarm={alarm}"
            ),
        }
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for ParityLine {
    fn format(&self, f: defmt::Formatter<'_>) {
        match *self {
            Self::Table {
                i,
                rpm,
                force,
                jumped,
                timing: b,
            } => defmt::write!(
                f,
                "parity table i={=u32} rpm={=u32:#010x} force={=u32:#010x} jumped={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
                i, rpm, force, jumped, b[0], b[1], b[2], b[3], b[4], b[5]
            ),
            Self::Jump(Some(rpm)) => defmt::write!(f, "parity jump rpm={=u32:#010x}", rpm),
            Self::Jump(None) => defmt::write!(f, "parity jump rpm=none"),
            Self::Check {
                rpm,
                force,
                jumped,
                timing: b,
            } => defmt::write!(
                f,
                "parity check rpm={=u32:#010x} force={=u32:#010x} jumped={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
                rpm, force, jumped, b[0], b[1], b[2], b[3], b[4], b[5]
            ),
            Self::Sample {
                i,
                rpm,
                force,
                speed,
                alarm,
                timing: b,
            } => defmt::write!(
                f,
                "parity sample i={=u32} rpm={=u32:#010x} force={=u32:#010x} speed={=u32:#010x} alarm={=bool} timing={=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x},{=u32:#010x}",
                i, rpm, force, speed, alarm, b[0], b[1], b[2], b[3], b[4], b[5]
            ),
            Self::Reading {
                i,
                kind,
                value,
                alarm,
            } => defmt::write!(
                f,
                "parity reading i={=u32} kind={=str} value={=u32:#010x} alarm={=bool}",
                i, kind, value, alarm
            ),
        }
    }
}

/// The memory fields both images report (static sections from the linker, the stack
/// peak from the paint; see firmware/src/memory.rs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct MemoryFields {
    /// Flash: .vector_table + .text + .rodata + .data (load image).
    pub flash_bytes: u32,
    /// Static RAM: .data + .bss + .uninit.
    pub ram_static_bytes: u32,
    /// Peak stack.
    pub stack_peak_bytes: u32,
    /// RAM used: static + stack peak.
    pub ram_bytes: u32,
}

/// The QEMU demonstration image's last line: its memory and boot cost
/// (`product flash_bytes=.. ram_static_bytes=.. stack_peak_bytes=.. ram_bytes=.. boot_instr=.. max_instr_per_reading=..`;
/// the prefix `product` is kept for the log readers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ProductLine {
    /// The image's memory.
    pub memory: MemoryFields,
    /// Instructions of the boot (the prediction table).
    pub boot_instr: u64,
    /// Most instructions one reading took.
    pub max_instr_per_reading: u64,
}

impl fmt::Display for ProductLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = &self.memory;
        write!(
            f,
            "product flash_bytes={} ram_static_bytes={} stack_peak_bytes={} ram_bytes={} boot_instr={} max_instr_per_reading={}",
            m.flash_bytes, m.ram_static_bytes, m.stack_peak_bytes, m.ram_bytes, self.boot_instr, self.max_instr_per_reading
        )
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for ProductLine {
    fn format(&self, f: defmt::Formatter<'_>) {
        let m = &self.memory;
        defmt::write!(
            f,
            "product flash_bytes={=u32} ram_static_bytes={=u32} stack_peak_bytes={=u32} ram_bytes={=u32} boot_instr={=u64} max_instr_per_reading={=u64}",
            m.flash_bytes, m.ram_static_bytes, m.stack_peak_bytes, m.ram_bytes, self.boot_instr, self.max_instr_per_reading
        )
    }
}

/// The budget probes' last line: their image's memory, the chip model's instructions per
/// RHS and per revolution, and the real-time factor ([`realtime_factor`]).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BudgetLine {
    /// The image's memory.
    pub memory: MemoryFields,
    /// Instructions per RHS evaluation of the chip's model.
    pub instr_per_rhs: u64,
    /// Instructions per simulated revolution at [`CHIP_NOMINAL_RPM`].
    pub instr_per_rev: u64,
    /// [`realtime_factor`] of `instr_per_rev`.
    pub realtime_factor: f32,
}

impl fmt::Display for BudgetLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = &self.memory;
        write!(
            f,
            "budget flash_bytes={} ram_static_bytes={} stack_peak_bytes={} ram_bytes={} instr_per_rhs={} instr_per_rev={} realtime_factor={}",
            m.flash_bytes, m.ram_static_bytes, m.stack_peak_bytes, m.ram_bytes, self.instr_per_rhs, self.instr_per_rev, self.realtime_factor
        )
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for BudgetLine {
    fn format(&self, f: defmt::Formatter<'_>) {
        let m = &self.memory;
        defmt::write!(
            f,
            "budget flash_bytes={=u32} ram_static_bytes={=u32} stack_peak_bytes={=u32} ram_bytes={=u32} instr_per_rhs={=u64} instr_per_rev={=u64} realtime_factor={=f32}",
            m.flash_bytes, m.ram_static_bytes, m.stack_peak_bytes, m.ram_bytes, self.instr_per_rhs, self.instr_per_rev, self.realtime_factor
        )
    }
}

/// The reaction to a reading that does not vouch for the speed: the alarm state and the
/// level read back from the alarm pin
/// (`reaction kind=.. alarm=asserted|released pin=.. level=low|high`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReactionLine {
    /// [`SpeedReading::kind`] of the reading.
    pub kind: &'static str,
    /// Alarm asserted.
    pub asserted: bool,
    /// The alarm pin's name (e.g. "LED0").
    pub pin: &'static str,
    /// The pin read back low (asserted is low).
    pub low: bool,
}

impl ReactionLine {
    /// The alarm word of the line.
    pub fn alarm_word(&self) -> &'static str {
        if self.asserted {
            "asserted"
        } else {
            "released"
        }
    }

    /// The level word of the line.
    pub fn level_word(&self) -> &'static str {
        if self.low {
            "low"
        } else {
            "high"
        }
    }
}

impl fmt::Display for ReactionLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "reaction kind={} alarm={} pin={} level={}",
            self.kind,
            self.alarm_word(),
            self.pin,
            self.level_word()
        )
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for ReactionLine {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(
            f,
            "reaction kind={=str} alarm={=str} pin={=str} level={=str}",
            self.kind,
            self.alarm_word(),
            self.pin,
            self.level_word()
        )
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    #[test]
    fn parity_text_is_the_firmwares_format() {
        // The chip's defmt strings print `{=u32:#010x}` as 0x and eight hex digits and
        // bools as true/false: the host's text must be the same characters.
        let t = ParityLine::Table {
            i: 3,
            rpm: 0x43c8_0000,
            force: 0xbf80_0000,
            jumped: false,
            timing: [1, 2, 3, 0xa, 0xb, 0xffff_ffff],
        };
        assert_eq!(
            t.to_string(),
            "parity table i=3 rpm=0x43c80000 force=0xbf800000 jumped=false timing=0x00000001,0x00000002,0x00000003,0x0000000a,0x0000000b,0xffffffff"
        );
        assert_eq!(ParityLine::jump(None).to_string(), "parity jump rpm=none");
        assert_eq!(
            ParityLine::jump(Some(500.0)).to_string(),
            "parity jump rpm=0x43fa0000"
        );
        let r = ParityLine::reading(7, &SpeedReading::Lost, true);
        assert_eq!(
            r.to_string(),
            "parity reading i=7 kind=lost value=0x00000000 alarm=true"
        );
    }

    #[test]
    fn realtime_factor_is_the_clock_over_the_instructions() {
        // 168e6 Hz * 60 s / 800 rpm = 12.6e6 cycles a revolution.
        assert_eq!(realtime_factor(12_600_000), 1.0);
        assert_eq!(realtime_factor(6_300_000), 2.0);
        assert!(realtime_factor(0).is_finite());
    }
}
