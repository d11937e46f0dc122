//! Board adapters: everything that touches hardware, kept out of camsim-core and
//! camsim-chip.
//!
//! The predictor loop is the chip's speed monitor (`camsim_chip::ChipMonitor`: index
//! pulses -> core's `IndexPulse` -> a speed reading -> the table's prediction -> the
//! alarm's hysteresis), the same on every board and on the host (`camsim predict`). A
//! board supplies only its HAL glue:
//! - a [`camsim_core::CaptureTimer`]: the timer count latched at each index pulse (one per
//!   cam revolution), overruns, and the counter now (for the lost-speed timeout);
//! - an `embedded_hal::digital::OutputPin` for the jump alarm, wrapped in
//!   [`crate::monitor::FailSafeOutput`] (LOW = asserted, the safe state);
//! - its clocks, logging transport and failure path.
//!
//! [`qemu`] is the MPS2 AN386 (QEMU `mps2-an386`): the scripted machine's pulse train
//! (`camsim_chip::ScriptedPulseTrain`, with its faults) as the capture timer, the alarm on
//! the FPGA IO `LED0` register. `f446` (feature `stm32f446`, binary
//! `src/bin/board_f446.rs`) is the Nucleo-F446RE: TIM2 input capture on PA0, the alarm
//! on PA5.
//!
//! ## Where another board plugs in
//! Add `board/<name>.rs` behind a cargo feature, with the chip's HAL as an optional
//! dependency, and a binary like `board_f446.rs`:
//! - index pulse: route the index sensor (Hall, inductive or optical, one pulse per cam
//!   revolution) to a 32-bit timer's input-capture channel and implement
//!   `CaptureTimer` on it: `poll_capture` returns the latched count once per edge (and
//!   `CaptureEvent::Overrun` when the hardware's overcapture flag says an edge was lost),
//!   `now` the free-running count, `tick_hz` the timer's rate (the chip's configuration
//!   is for 1 MHz: `camsim_chip::CHIP_TICK_HZ`);
//! - call `ChipMonitor::step` in the main loop and drive the `FailSafeOutput` with the
//!   step's alarm; log with [`crate::monitor`]'s lines;
//! - logging and failures: build with `--no-default-features --features rtt` for defmt
//!   over RTT and panics through `panic-probe` (no semihosting on a failure path), and
//!   run with `probe-rs run --chip <chip>` (see docs/FIRMWARE.md, "A real board");
//! - memory: the chip's own origins with the budget's lengths (`build/board_memory.rs`).

pub mod qemu;

// Nucleo-F446RE (feature `stm32f446`, binary `board_f446`): TIM2 capture on PA0, alarm on PA5.
#[cfg(feature = "stm32f446")]
pub mod f446;
