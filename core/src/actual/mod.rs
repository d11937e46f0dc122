//! The actual (machined) cam, IV.2 and Appendices B, C, E: random numbers, cubic splines,
//! waviness (FPR, VI.4.1), the actual contour and follower lift, and the exact envelope of
//! the roller circle on an actual contour (beyond the thesis).

pub(crate) mod deviation;
pub(crate) mod envelope;
pub(crate) mod follower_axis;
pub(crate) mod profile;
pub(crate) mod random;
pub(crate) mod sampled;
pub(crate) mod spline;
pub(crate) mod waviness;
