//! `camsim laws` against closed forms for the coefficients `motion_laws.rs` leaves
//! unchecked: every signed extreme of every law, derived by hand from Appendix A.

use std::f64::consts::PI;

use camsim::cmd::laws::table;

/// `(name, cv, ca_max, ca_min, cj_max, cj_min)` in closed form, impulses excluded.
fn closed_forms() -> Vec<(&'static str, [f64; 5])> {
    let pi2 = PI * PI;
    let pi3 = pi2 * PI;
    // Double harmonic: a = (π²/2)(cos πu - cos 2πu) peaks at cos πu = 1/4 (9π²/16) and
    // ends at -π²; j = (π³/2) sin πu (4 cos πu - 1) is extreme where 8c² - c - 4 = 0.
    let dh_j = |c: f64| pi3 / 2.0 * (1.0 - c * c).sqrt() * (4.0 * c - 1.0);
    let (c_hi, c_lo) = ((1.0 + 129f64.sqrt()) / 16.0, (1.0 - 129f64.sqrt()) / 16.0);
    // Modified sine: k = π/(π + 4); the middle piece's jerk bottoms at u = 1/2.
    let k = PI / (PI + 4.0);
    // Modified trapezoidal: A = 8π/(2 + π).
    let amt = 8.0 * PI / (2.0 + PI);
    // 3-4-5: a = -120 w (1/4 - w²), w = u - 1/2; 4-5-6-7: a = -840 w (1/4 - w²)².
    let a345 = 10.0 / 3f64.sqrt();
    let a4567 = 84.0 / (5.0 * 5f64.sqrt());
    vec![
        ("straight-line", [1.0, 0.0, 0.0, 0.0, 0.0]),
        ("parabolic", [2.0, 4.0, -4.0, 0.0, 0.0]),
        ("cubic-1", [3.0, 12.0, -12.0, 24.0, 24.0]),
        ("cubic-2", [1.5, 6.0, -6.0, -12.0, -12.0]),
        ("shm", [PI / 2.0, pi2 / 2.0, -pi2 / 2.0, 0.0, -pi3 / 2.0]),
        (
            "double-harmonic",
            [
                3.0 * 3f64.sqrt() * PI / 8.0,
                9.0 * pi2 / 16.0,
                -pi2,
                dh_j(c_hi),
                dh_j(c_lo),
            ],
        ),
        (
            "cycloidal",
            [2.0, 2.0 * PI, -2.0 * PI, 4.0 * pi2, -4.0 * pi2],
        ),
        (
            "modified-sine",
            [
                4.0 * k,
                4.0 * PI * k,
                -4.0 * PI * k,
                16.0 * pi2 * k,
                -16.0 * pi2 * k / 3.0,
            ],
        ),
        (
            "trapezoidal",
            [2.0, 16.0 / 3.0, -16.0 / 3.0, 128.0 / 3.0, -128.0 / 3.0],
        ),
        (
            "modified-trapezoidal",
            [2.0, amt, -amt, 4.0 * PI * amt, -4.0 * PI * amt],
        ),
        ("3-4-5", [1.875, a345, -a345, 60.0, -30.0]),
        ("4-5-6-7", [2.1875, a4567, -a4567, 42.0, -52.5]),
    ]
}

#[test]
fn every_signed_extreme_matches_its_closed_form() {
    let rows = table();
    let forms = closed_forms();
    assert_eq!(rows.len(), forms.len());
    for (name, want) in forms {
        let r = rows
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("no row {name}"));
        let got = [r.cv, r.ca_max, r.ca_min, r.cj_max, r.cj_min];
        for (what, (g, w)) in ["cv", "ca_max", "ca_min", "cj_max", "cj_min"]
            .iter()
            .zip(got.iter().zip(want))
        {
            assert!(
                (g - w).abs() <= 1e-9 * (1.0 + w.abs()),
                "{name} {what}: got {g}, want {w}"
            );
        }
    }
}

#[test]
fn printed_modified_trapezoidal_peaks() {
    // Appendix A.3-2 prints the peaks as 4.888124 (acceleration) and 61.425977 (jerk).
    let rows = table();
    let mt = rows
        .iter()
        .find(|r| r.name == "modified-trapezoidal")
        .unwrap();
    assert!((mt.ca_max - 4.888124).abs() < 1e-6, "{}", mt.ca_max);
    assert!((mt.cj_max - 61.425977).abs() < 5e-6, "{}", mt.cj_max);
}
