//! The cam-timing and jump predictor: what a machine feeds it, the alarm, the steady-state
//! observer and the boot-time table; the cam speed from a once-per-revolution index pulse.

pub(crate) mod index_pulse;
pub(crate) mod predict;
