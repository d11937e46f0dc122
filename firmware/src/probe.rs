//! Panic and exit plumbing of a real board (feature `panic-probe`): no semihosting (a
//! semihosting call without a debugger attached is a HardFault).
//!
//! - A Rust panic goes to panic-probe: it logs the message over defmt
//!   (`print-defmt`), then executes `udf`, a HardFault. With `probe-rs run` attached,
//!   probe-rs catches the HardFault, prints the backtrace and exits non-zero; without a
//!   probe, the binary's own HardFault handler runs (the board binary drives its alarm
//!   output to the safe state there and stays put).
//! - [`exit_failure`] takes the same path; [`exit_success`] parks the core (a board's
//!   predictor never ends).

use panic_probe as _;

/// On a board: parks the core (sleeps forever; nothing on a board ends in success).
pub fn exit_success() -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}

/// On a board: a HardFault, as a panic (probe-rs reports it; the binary's handler
/// puts the outputs in their safe state).
pub fn exit_failure() -> ! {
    panic_probe::hard_fault()
}

/// defmt's own panics (`defmt::panic!`, `defmt::unwrap!`): already logged, a HardFault.
#[defmt::panic_handler]
fn defmt_panic() -> ! {
    panic_probe::hard_fault()
}
