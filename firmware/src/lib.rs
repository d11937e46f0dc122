//! Shared code of the camsim firmware: the board adapters, the budget probes
//! (linker sections, stack painting, SysTick instruction counting), the model
//! workload, the exception handlers and the panic/exit plumbing. One concern per
//! binary in `src/bin/`: `predictor` (the product) and `budget` (the instruction probes).
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
pub mod timing;
pub mod workload;

use cortex_m_rt::{exception, ExceptionFrame};

/// Ends the program with success (QEMU exits with status 0 through semihosting).
pub fn exit_success() -> ! {
    cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_SUCCESS);
    // Only reached on a board without a debugger attached: park the core.
    park()
}

/// Ends the program with failure (QEMU exits with status 1 through semihosting).
pub fn exit_failure() -> ! {
    cortex_m_semihosting::debug::exit(cortex_m_semihosting::debug::EXIT_FAILURE);
    park()
}

/// Stops doing anything, for good.
fn park() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// Rust panics: log the message with defmt, then exit with failure.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit_failure()
}

/// defmt's own panics (`defmt::panic!`, `defmt::unwrap!`): already logged, exit with failure.
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    exit_failure()
}

/// Counts SysTick wraps for [`timing::InstrCounter`] (both binaries use it).
#[exception]
fn SysTick() {
    timing::on_systick_wrap();
}

/// HardFault: log where, then exit with failure.
#[exception]
unsafe fn HardFault(ef: &ExceptionFrame) -> ! {
    defmt::error!(
        "HardFault at pc={=u32:#010x} lr={=u32:#010x}",
        ef.pc(),
        ef.lr()
    );
    exit_failure()
}
