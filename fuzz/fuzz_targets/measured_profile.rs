//! The measured-profile path of `camsim run --measured FILE.csv`: the host's reader
//! (`camsim::measured::parse`) and the deviation it turns into on the reference design
//! (`Measured::profile`: a periodic spline, or the roller's exact envelope for radii).
//!
//! Asserts: no panic; a refusal is one line (the CLI prints it as the error); a profile
//! that builds is finite in value, slope, curvature and jerk at and between its knots.
#![no_main]

use camsim::measured::{self, MeasuredProfile};
use camsim_core::{Design, LiftProfile};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let parsed = match measured::parse(text) {
        Ok(m) => m,
        Err(e) => {
            let line = e.to_string();
            assert!(
                !line.contains('\n'),
                "a refusal on more than one line: {line:?}"
            );
            return;
        }
    };
    let design = Design::<f64>::reference();
    let Ok((dev, _stats)) = parsed.profile(&design) else {
        return;
    };
    for k in 0..720 {
        let theta = (k as f64 * 0.5).to_radians();
        let l = dev.follower(&design.program, theta);
        for v in [l.y, l.dy, l.d2y, l.d3y] {
            assert!(
                v.is_finite(),
                "non-finite lift at {} deg: {l:?}",
                k as f64 * 0.5
            );
        }
    }
});
