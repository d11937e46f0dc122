//! Shared code of the camsim firmware: the board adapters, what the boards share around
//! the chip's speed monitor (the fail-safe alarm output and the fault log lines:
//! [`monitor`]), the budget probes (linker sections, stack painting, SysTick instruction
//! counting), the model workload, the exception handlers and the panic/exit plumbing.
//! One concern per binary in `src/bin/`: `predictor` (the QEMU demonstration image), `budget` (the
//! instruction probes), `boot_fault` (the QEMU demonstration image's boot-failure path under test) and,
//! with feature `stm32f446`, `board_f446` (the Nucleo-F446RE).
//!
//! Failure paths depend on the defmt transport:
//! - `semihosting` (default, QEMU): a panic or HardFault is logged, then a semihosting
//!   exit with status 1 ends QEMU.
//! - `rtt` (a real board): never semihosting on a failure path (without a debugger
//!   attached a semihosting call faults again). Panics go through `panic-probe`
//!   (message logged with defmt, then `udf`, i.e. a HardFault); `probe-rs run` catches
//!   the HardFault (its vector catch is on by default), prints the backtrace and exits
//!   non-zero. Without a debugger the HardFault handler logs into the RTT buffer and
//!   parks the core (a board that must recover adds a watchdog).
//!
//! `unsafe` is confined to this crate (the core forbids it): linker-symbol
//! addresses, the stack paint/scan, the calibration loop and one MMIO register.
//! Each use carries a SAFETY comment.

#![no_std]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(missing_docs)]

#[cfg(all(feature = "semihosting", feature = "rtt"))]
compile_error!("choose one defmt transport: feature `semihosting` (default, QEMU) or `rtt` (real board, with --no-default-features)");

#[cfg(not(any(feature = "semihosting", feature = "rtt")))]
compile_error!("enable a defmt transport: feature `semihosting` (default) or `rtt`");

#[cfg(feature = "rtt")]
use defmt_rtt as _;
#[cfg(feature = "semihosting")]
use defmt_semihosting as _;

pub mod board;
pub mod memory;
pub mod monitor;
pub mod timing;
pub mod workload;

#[cfg(not(feature = "stm32f446"))]
use cortex_m_rt::{exception, ExceptionFrame};

/// Ends the program with success: a semihosting exit with status 0 (QEMU, or `probe-rs
/// run` with the `rtt` feature when a debugger is attached); otherwise parks the core.
pub fn exit_success() -> ! {
    // With `rtt`, a semihosting call without a debugger would fault: only with one attached.
    if cfg!(feature = "semihosting") || cortex_m::peripheral::DCB::is_debugger_attached() {
        cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_SUCCESS);
    }
    park()
}

/// Ends the program with failure: with `semihosting` a semihosting exit with status 1
/// (QEMU); with `rtt` a HardFault (`panic_probe::hard_fault`), which `probe-rs run`
/// reports as a failure, and which parks the core without a debugger.
pub fn exit_failure() -> ! {
    #[cfg(feature = "rtt")]
    {
        panic_probe::hard_fault()
    }
    #[cfg(not(feature = "rtt"))]
    {
        cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_FAILURE);
        park()
    }
}

/// Stops doing anything, for good (interrupts still run; a watchdog would reset).
fn park() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// Rust panics on QEMU: log the message with defmt, then exit with failure.
/// (With `rtt`, `panic-probe` is the panic handler.)
#[cfg(not(feature = "rtt"))]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit_failure()
}

#[cfg(feature = "rtt")]
use panic_probe as _;

/// defmt's own panics (`defmt::panic!`, `defmt::unwrap!`): already logged, exit with
/// failure (with `rtt` that is panic-probe's HardFault, without printing twice).
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    exit_failure()
}

/// Counts SysTick wraps for [`timing::InstrCounter`] (the QEMU binaries use it).
#[cfg(not(feature = "stm32f446"))]
#[exception]
fn SysTick() {
    timing::on_systick_wrap();
}

/// HardFault: log where, then end with failure. With `rtt`, `probe-rs run` normally halts
/// the core at the fault's entry before this runs; if this runs with a debugger attached
/// (vector catch off) it stops at a breakpoint, without one it parks the core. No
/// semihosting with `rtt`: without a debugger that would fault inside the fault handler.
/// The board binary (`stm32f446`) has its own, which first puts the alarm in its safe state.
#[cfg(not(feature = "stm32f446"))]
#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    defmt::error!(
        "HardFault at pc={=u32:#010x} lr={=u32:#010x}",
        ef.pc(),
        ef.lr()
    );
    #[cfg(feature = "rtt")]
    {
        if cortex_m::peripheral::DCB::is_debugger_attached() {
            cortex_m::asm::bkpt();
        }
        park()
    }
    #[cfg(not(feature = "rtt"))]
    {
        exit_failure()
    }
}
