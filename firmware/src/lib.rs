//! Shared code of the camsim firmware: the board adapters, the budget probes
//! (linker sections, stack painting, SysTick instruction counting), the model
//! workload, and the panic/exit plumbing. One binary per file in `src/bin/`.
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

// A real board (feature `panic-probe`): panic-probe's handler and exits that need no
// semihosting (src/probe.rs). Otherwise (QEMU) the semihosting ones below.
#[cfg(feature = "panic-probe")]
mod probe;
#[cfg(feature = "panic-probe")]
pub use probe::{exit_failure, exit_success};

#[cfg(not(feature = "panic-probe"))]
use cortex_m_semihosting::debug;

/// Ends the program with success (QEMU exits with status 0 through semihosting).
#[cfg(not(feature = "panic-probe"))]
pub fn exit_success() -> ! {
    debug::exit(debug::EXIT_SUCCESS);
    // Only reached on a board without a debugger attached: park the core.
    loop {
        cortex_m::asm::wfi();
    }
}

/// Ends the program with failure (QEMU exits with status 1 through semihosting).
#[cfg(not(feature = "panic-probe"))]
pub fn exit_failure() -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}

/// Rust panics: log the message with defmt, then exit with failure.
#[cfg(not(feature = "panic-probe"))]
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic: {}", defmt::Display2Format(info));
    exit_failure()
}

/// defmt's own panics (`defmt::panic!`, `defmt::unwrap!`): already logged, exit with failure.
#[cfg(not(feature = "panic-probe"))]
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    exit_failure()
}
