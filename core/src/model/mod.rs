//! The eleven-degree-of-freedom model (Eqs. IV.1-IV.3): the reference design of VI.1 and
//! its scene keys, the scenes (state layouts fixed at compile time), the model itself, the
//! reduced followers' static condensation (docs/MODEL.md §10), modal analysis (VI.2).

pub(crate) mod design;
pub(crate) mod dynamics;
pub(crate) mod keys;
pub(crate) mod modal;
pub(crate) mod quasistatic;
pub(crate) mod scene;
