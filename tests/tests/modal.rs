//! `camsim modal` (Section VI.2) against hand calculations of the 3-DOF systems.

// Modes are compared index by index across several parallel arrays.
#![allow(clippy::needless_range_loop)]

use camsim::cmd::modal::{self, analyse};

/// Roots of lambda^3 - a lambda^2 + b lambda - c = 0 with three real roots (trigonometric
/// formula), ascending.
fn cubic_roots(a: f64, b: f64, c: f64) -> [f64; 3] {
    // lambda = x + a/3: x^3 + p x + q = 0.
    let p = b - a * a / 3.0;
    let q = -2.0 * a * a * a / 27.0 + a * b / 3.0 - c;
    let r = 2.0 * (-p / 3.0).sqrt();
    let phi = ((3.0 * q / (p * r)).clamp(-1.0, 1.0)).acos() / 3.0;
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        *xk = r * (phi - 2.0 * std::f64::consts::PI * k as f64 / 3.0).cos() + a / 3.0;
    }
    x.sort_by(|u, v| u.partial_cmp(v).unwrap());
    x
}

/// Invariants of A = M^-1 K for diagonal M: trace, sum of principal 2x2 minors, determinant.
fn invariants(k: [[f64; 3]; 3], m: [f64; 3]) -> (f64, f64, f64) {
    let a: Vec<Vec<f64>> = (0..3)
        .map(|i| (0..3).map(|j| k[i][j] / m[i]).collect())
        .collect();
    let tr = a[0][0] + a[1][1] + a[2][2];
    let minors = a[0][0] * a[1][1] - a[0][1] * a[1][0] + a[0][0] * a[2][2] - a[0][2] * a[2][0]
        + a[1][1] * a[2][2]
        - a[1][2] * a[2][1];
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    (tr, minors, det)
}

#[test]
fn rotational_frequencies_match_the_hand_calculation() {
    let r = analyse().unwrap();
    let p = modal::reference_parameters().unwrap();
    assert_eq!(
        (
            p.i_m.in_inch(),
            p.i_cp.in_inch(),
            p.i_c.in_inch(),
            p.k_s1.in_inch(),
            p.k_s2.in_inch()
        ),
        (0.0291, 0.25, 0.0102, 2.0e5, 2.0e5)
    );
    let (m1, m2, m3, k1, k2): (f64, f64, f64, f64, f64) = (0.0291, 0.25, 0.0102, 2.0e5, 2.0e5);
    // Free-free chain: lambda (lambda^2 - S lambda + P) = 0 with
    // S = k1/m1 + (k1 + k2)/m2 + k2/m3, P = k1 k2 (m1 + m2 + m3) / (m1 m2 m3).
    let s = k1 / m1 + (k1 + k2) / m2 + k2 / m3;
    let p = k1 * k2 * (m1 + m2 + m3) / (m1 * m2 * m3);
    let d = (s * s - 4.0 * p).sqrt();
    let w = [0.0, ((s - d) / 2.0).sqrt(), ((s + d) / 2.0).sqrt()];
    assert_eq!(r.rotational_rad_s.len(), 3);
    assert_eq!(
        r.rotational_rad_s[0], 0.0,
        "rigid-body mode at zero frequency"
    );
    for j in 1..3 {
        assert!(
            (r.rotational_rad_s[j] / w[j] - 1.0).abs() < 1e-10,
            "mode {j}: {} vs {}",
            r.rotational_rad_s[j],
            w[j]
        );
        assert!((r.rotational_hz[j] - w[j] / (2.0 * std::f64::consts::PI)).abs() < 1e-6);
    }
    // The first nonzero frequency: about 2761 rad/s (439 Hz).
    assert!((2760.0..2762.0).contains(&r.rotational_rad_s[1]));
    // Rigid mode is a uniform rotation; its modal mass is the total inertia.
    let rot = &r.rotational;
    assert!(rot.modes[0].iter().all(|v| (v - 1.0).abs() < 1e-9));
    assert!((rot.modal_mass[0] - (m1 + m2 + m3)).abs() < 1e-12);
    assert_eq!(rot.modal_stiffness[0], 0.0);
    // Elastic modes: first row 1, x2/x1 = 1 - w^2 m1 / k1 (motor equation), and
    // omega^2 = modal stiffness / modal mass (Eq. VI.5).
    for j in 1..3 {
        assert_eq!(rot.modes[j][0], 1.0);
        let x2 = 1.0 - w[j] * w[j] * m1 / k1;
        assert!(
            (rot.modes[j][1] - x2).abs() < 1e-9 * x2.abs().max(1.0),
            "mode {j}"
        );
        assert!((rot.modal_stiffness[j] / rot.modal_mass[j] / (w[j] * w[j]) - 1.0).abs() < 1e-10);
    }
}

#[test]
fn translational_frequencies_match_the_characteristic_cubic() {
    let r = analyse().unwrap();
    // The reference design's values (VI.1 and docs/MODEL.md §5.1, §5.2): M_f and K_f at the nominal
    // follower position, K_rs = 100 lb/in of the modal analysis.
    let p = modal::reference_parameters().unwrap();
    let (mr, mf, ml) = (p.m_r.in_inch(), p.m_f.in_inch(), p.m_l.in_inch());
    let (krb, kf, krs) = (p.k_rb.in_inch(), p.k_f.in_inch(), p.k_rs.in_inch());
    assert_eq!((mr, ml, krb, krs), (0.00013, 3.428e-3, 1.5e6, 100.0));
    assert!((mf / 0.007764 - 1.0).abs() < 1e-12, "M_f = {mf}");
    assert!((kf / 1.265e6 - 1.0).abs() < 1e-12, "K_f = {kf}");
    assert_eq!(r.parameters, p);
    let k = [
        [krb, -krb, 0.0],
        [-krb, krb + kf + krs, -kf],
        [0.0, -kf, kf],
    ];
    let (a, b, c) = invariants(k, [mr, mf, ml]);
    let lam = cubic_roots(a, b, c);
    for j in 0..3 {
        let w = lam[j].sqrt();
        assert!(
            (r.translational_rad_s[j] / w - 1.0).abs() < 1e-8,
            "mode {j}: {} vs {w}",
            r.translational_rad_s[j]
        );
    }
    // The lowest mode is the whole chain bouncing on the return spring:
    // omega_1 ~ sqrt(K_rs / (M_r + M_f + M_l)) (the other springs are 1e4 times stiffer).
    let w_bounce = (krs / (mr + mf + ml)).sqrt();
    assert!(
        (r.translational_rad_s[0] / w_bounce - 1.0).abs() < 1e-4,
        "{} vs {w_bounce}",
        r.translational_rad_s[0]
    );
    let t = &r.translational;
    for j in 0..3 {
        assert_eq!(t.normalized_by[j], 0);
        assert_eq!(t.modes[j][0], 1.0);
        let w2 = r.translational_rad_s[j].powi(2);
        // Roller equation: K_rb (x1 - x2) = w^2 M_r x1, so x2 = 1 - w^2 M_r / K_rb.
        let x2 = 1.0 - w2 * mr / krb;
        assert!(
            (t.modes[j][1] - x2).abs() < 1e-9 * x2.abs().max(1.0),
            "mode {j}"
        );
        assert!((t.modal_stiffness[j] / t.modal_mass[j] / w2 - 1.0).abs() < 1e-9);
    }
}

#[test]
fn json_has_the_documented_keys_and_ascending_arrays() {
    // The keys as printed: the parameters' measures named by their unit (units::convert).
    let v = camsim::units::convert(
        serde_json::to_value(analyse().unwrap()).unwrap(),
        camsim::units::Units::Inch,
    );
    for key in [
        "rotational_rad_s",
        "translational_rad_s",
        "rotational_hz",
        "translational_hz",
    ] {
        let arr: Vec<f64> = v[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key}"))
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(arr.len(), 3, "{key}");
        assert!(
            arr.windows(2).all(|w| w[0] < w[1]),
            "{key} ascending: {arr:?}"
        );
    }
    for sys in ["rotational", "translational"] {
        assert_eq!(v[sys]["modes"].as_array().unwrap().len(), 3);
        assert_eq!(v[sys]["modal_stiffness"].as_array().unwrap().len(), 3);
    }
    assert_eq!(v["parameters"]["k_rs_lb_per_in"].as_f64(), Some(100.0));
    // The table renders every mode.
    let table = modal::render_table(&analyse().unwrap(), camsim::units::Units::Inch);
    assert_eq!(table.matches("rigid body").count(), 1);
    assert!(table.contains("Eq. VI.6") && table.contains("Eq. VI.7"));
}
