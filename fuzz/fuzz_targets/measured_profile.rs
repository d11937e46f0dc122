//! The measured-profile path: CSV rows of cam angle (deg) and follower lift (in) into
//! the core's cubic spline, the smooth lift with slope and curvature a measured profile
//! feeds the model.
//!
//! PLACEHOLDER READER: `camsim run --measured FILE.csv` has no reader yet. Until it
//! lands, `read_rows` below reads the rows with the `csv` crate (the one host-sim
//! writes its `--csv` files with); when the reader exists, replace `read_rows` by a
//! call to it (and keep the spline checks) so this target fuzzes the real thing.
//!
//! Asserts: no panic; a spline that builds is finite at and between its knots for
//! lifts and angles in a physical range and reproduces the lift at each knot.
#![no_main]

use camsim_core::CubicSpline;
use libfuzzer_sys::fuzz_target;

/// Most points a profile may have here (0.1 deg steps over a revolution fit).
const POINTS: usize = 4096;

/// PLACEHOLDER for the measured-profile reader: `angle_deg,lift_in` rows, an optional
/// header, `#` comments; `None` for anything it cannot read as two numbers a row.
fn read_rows(data: &[u8]) -> Option<(Vec<f64>, Vec<f64>)> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(data);
    let (mut angles, mut lifts) = (Vec::new(), Vec::new());
    for (i, record) in reader.records().enumerate() {
        let record = record.ok()?;
        if record.len() != 2 {
            return None;
        }
        let (a, l) = (record.get(0)?, record.get(1)?);
        match (a.parse::<f64>(), l.parse::<f64>()) {
            (Ok(a), Ok(l)) => {
                angles.push(a);
                lifts.push(l);
            }
            // A header on the first line only.
            _ if i == 0 => {}
            _ => return None,
        }
        if angles.len() > POINTS {
            return None;
        }
    }
    Some((angles, lifts))
}

fn check(spline: &CubicSpline<f64, POINTS>, angles: &[f64], lifts: &[f64], physical: bool) {
    for (k, (&x, &y)) in angles.iter().zip(lifts).enumerate() {
        let at = spline.eval(x);
        let tol = 1e-9 * (1.0 + y.abs());
        assert!(
            !physical || (at.y - y).abs() <= tol || spline.is_periodic() && k + 1 == angles.len(),
            "knot {k}: S({x}) = {} for a lift of {y}",
            at.y
        );
        if physical {
            for v in [at.y, at.dy, at.d2y, at.d3y] {
                assert!(v.is_finite(), "non-finite at knot {k} ({x}): {at:?}");
            }
            if let Some(&next) = angles.get(k + 1) {
                let mid = spline.eval(0.5 * (x + next));
                for v in [mid.y, mid.dy, mid.d2y, mid.d3y] {
                    assert!(
                        v.is_finite(),
                        "non-finite between knots {k} and {}: {mid:?}",
                        k + 1
                    );
                }
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((angles, lifts)) = read_rows(data) else {
        return;
    };
    // A physical profile: angles within a few revolutions, lifts within +-100 in, knots at
    // least 1e-6 deg apart (the measured profile's reader will check such ranges).
    let physical = angles.iter().all(|a| a.abs() <= 1e4)
        && lifts.iter().all(|l| l.abs() <= 100.0)
        && angles.windows(2).all(|w| w[1] - w[0] >= 1e-6);
    let rad: Vec<f64> = angles.iter().map(|a| a.to_radians()).collect();
    if let Ok(s) = CubicSpline::<f64, POINTS>::natural(&rad, &lifts) {
        check(&s, &rad, &lifts, physical);
    }
    if let Ok(s) = CubicSpline::<f64, POINTS>::periodic(&rad, &lifts) {
        check(&s, &rad, &lifts, physical);
        // Wrapped: one period later is the same point.
        if physical {
            if let (Some(&x0), Some(&xn)) = (rad.first(), rad.last()) {
                let p = xn - x0;
                let (a, b) = (s.eval(x0 + 0.3 * p), s.eval(x0 + 1.3 * p));
                assert!(
                    (a.y - b.y).abs() <= 1e-6 * (1.0 + a.y.abs()),
                    "{a:?} vs {b:?}"
                );
            }
        }
    }
});
