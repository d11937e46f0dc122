//! Board adapters: everything that touches hardware, kept out of camsim-core.
//!
//! A board supplies three things to the predictor loop (`src/bin/predictor.rs`):
//! - a [`camsim_core::SpeedSource<f32>`]: measured cam speed in rpm, one sample per revolution;
//! - an `embedded_hal::digital::InputPin` for the once-per-revolution index pulse;
//! - an `embedded_hal::digital::OutputPin` driving the jump alarm (lamp, relay, PLC input).
//!
//! [`qemu`] is the MPS2 AN386 (QEMU `mps2-an386`): a scripted speed profile, a fake
//! index pulse, and the alarm on the FPGA IO `LED0` register.
//!
//! ## Where a real board plugs in
//! `f446` (feature `stm32f446`, binary `src/bin/board_f446.rs`) is a worked example: TIM2
//! capture -> `camsim_core::IndexPulse` -> prediction -> a fail-safe alarm pin.
//! Add `board/<name>.rs` behind a cargo feature, with the chip's HAL as an optional
//! dependency, and select it in the binary instead of `qemu`:
//! - index pulse -> rpm: route the index sensor (Hall or optical, one pulse per cam
//!   revolution) to a timer input-capture channel. In the capture interrupt, take the
//!   captured count difference `d` between consecutive pulses and push
//!   `60 * f_timer / d` (rpm) into a `heapless::spsc::Queue<f32, 8>`; `SpeedSource::next_rpm`
//!   pops it (`None` while empty). Reject `d == 0` and captures that overflowed.
//! - the index `InputPin` is the same pin read as a GPIO (the loop uses it to stay in step
//!   with the revolutions; with capture interrupts it can be dropped);
//! - the alarm `OutputPin` is any HAL GPIO output (`embedded-hal` 1.0 pins work as-is);
//! - logging and failures: build with `--no-default-features --features rtt` for defmt
//!   over RTT and panics through `panic-probe` (no semihosting on a failure path), and
//!   run with `probe-rs run --chip <chip>` (see the firmware README, "A real board");
//! - memory: the chip's own `memory.x` regions (keep the 128K/32K budget, or change the
//!   root memory.x deliberately).

pub mod qemu;

// Nucleo-F446RE (feature `stm32f446`, binary `board_f446`): TIM2 capture on PA0, alarm on PA5.
#[cfg(feature = "stm32f446")]
pub mod f446;
