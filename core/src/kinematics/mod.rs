//! Kinematics: Appendix A motion laws, cam programs, cam geometry (V.1-V.4, V.12, E.6), and the
//! lift the model's roller rides on (the program, or the program plus a deviation).

pub(crate) mod geometry;
pub(crate) mod lift;
pub(crate) mod motion;
pub(crate) mod program;
pub(crate) mod table;
