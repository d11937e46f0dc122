//! Forces: Hertz contact and jump (V.9-V.11, V.19-V.20) with the damping at the roller
//! (V.13), return spring (V.17-V.18), slide-bearing friction (V.15-V.16), the motor law.

pub(crate) mod coil_spring;
pub(crate) mod contact;
pub(crate) mod drive;
pub(crate) mod spring;
