//! Hertz contact, contact force, friction and return-spring preload across core and
//! the `camsim contact` command, checked against hand calculations.

use camsim::cmd::contact::{self, compute, Args, ContactReport};
use camsim_core::{
    bearing_normal_forces, contact_force, coulomb_friction, return_spring_preload,
    series_stiffness, spring_effective_mass, Error, HertzContact,
};
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// Eqs. V.9-V.11 for the reference pair, step by step, written out independently of
/// core (the thesis's own `r - sqrt(r^2 - b^2)`, fine in f64 to ~1e-10).
struct Hand {
    w: f64,
    k: f64,
}

fn hand(force: f64, r1: f64, r2: f64) -> Hand {
    // Steel on steel: C = (1 - nu^2)/E twice.
    let e = 30.0e6;
    let nu: f64 = 0.295;
    let c = 2.0 * (1.0 - nu * nu) / e;
    let t = 0.25;
    let (d1, d2) = (2.0 * r1, 2.0 * r2);
    // Eq. V.9.
    let w = 2.0 * ((2.0 * force / (PI * t)) * (c / (1.0 / d1 + 1.0 / d2))).sqrt();
    let b = w / 2.0;
    // Eq. V.10.
    let h1 = r1 - (r1 * r1 - b * b).sqrt();
    let h2 = r2.abs() - (r2 * r2 - b * b).sqrt();
    // Eq. V.11 with K = F / H.
    let k = if r2 > 0.0 {
        force / (h1 + h2)
    } else {
        force / (2.0 * (h1 - h2))
    };
    Hand { w, k }
}

#[test]
fn report_matches_hand_calculation_at_100_lb() {
    let r = compute(100.0).unwrap();
    assert_eq!(r.force_lb.in_inch(), 100.0);
    let unit = hand(1.0, 0.375, 1.5);
    let at = hand(100.0, 0.375, 1.5);
    // Numbers: C = 6.0865e-8 1/psi, 1/d1 + 1/d2 = 5/3 1/in, w(1 lb) = 6.09901e-4 in,
    // b = 3.04951e-4 in, h1 = 1.23995e-7 in, h2 = 3.09987e-8 in, K_h = 6.45197e6 lb/in.
    assert!(rel(unit.w, 6.099_012e-4) < 1e-6);
    assert!(rel(unit.k, 6.451_968e6) < 1e-6);
    assert!(rel(r.k_h_lb_per_in.in_inch(), unit.k) < 1e-8, "{r:?}");
    assert!(
        rel(r.k_h_at_force_lb_per_in.in_inch(), at.k) < 1e-8,
        "{r:?}"
    );
    assert!(rel(r.contact_width_in.in_inch(), at.w) < 1e-13, "{r:?}");
    // 2F / (pi b t) with b = w/2.
    let p = 2.0 * 100.0 / (PI * (at.w / 2.0) * 0.25);
    assert!(rel(r.max_stress_psi.in_inch(), p) < 1e-13, "{r:?}");
}

#[test]
fn max_stress_equals_textbook_line_contact_formula() {
    // b^2 = (2F/(pi t)) C / ((1/r1 + 1/r2)/2) = 4 F R*/(pi t E*), so
    // (2F/(pi b t))^2 = 4F^2/(pi^2 t^2) * pi t E*/(4 F R*) = F E*/(pi t R*).
    let e_star = 1.0 / (2.0 * (1.0 - 0.295f64 * 0.295) / 30.0e6);
    let r_star = 1.0 / (1.0 / 0.375 + 1.0 / 1.5);
    for f in [1.0, 37.0, 100.0, 1000.0] {
        let r = compute(f).unwrap();
        let textbook = (f * e_star / (PI * 0.25 * r_star)).sqrt();
        assert!(rel(r.max_stress_psi.in_inch(), textbook) < 1e-13, "F = {f}");
    }
}

#[test]
fn width_scales_as_sqrt_force_and_stiffness_is_nearly_constant() {
    let r1 = compute(1.0).unwrap();
    let r1000 = compute(1000.0).unwrap();
    assert!(
        rel(
            r1000.contact_width_in.in_inch(),
            r1.contact_width_in.in_inch() * 1000f64.sqrt()
        ) < 1e-13
    );
    assert_eq!(
        r1.k_h_at_force_lb_per_in.in_inch(),
        r1.k_h_lb_per_in.in_inch()
    );
    // h = (w^2/(8r))(1 + w^2/(16 r^2) + O(w^4/r^4)): H/F = a (1 + delta(F)) with
    // delta = (w^2/16) (r1^-3 + r2^-3) / (r1^-1 + r2^-1), so K drops by
    // delta(1000) - delta(1) ~ 1.34e-4 between 1 and 1000 lb.
    let w2 = r1000.contact_width_in.in_inch().powi(2);
    let delta = w2 / 16.0 * (0.375f64.powi(-3) + 1.5f64.powi(-3)) / (1.0 / 0.375 + 1.0 / 1.5);
    let change = (r1.k_h_lb_per_in.in_inch() - r1000.k_h_at_force_lb_per_in.in_inch())
        / r1.k_h_lb_per_in.in_inch();
    assert!(delta < 1.4e-4, "{delta}");
    assert!(
        change > 0.0 && change < 1.01 * delta && change > 0.99 * delta,
        "{change} vs {delta}"
    );
    // Monotone softening in between.
    let mut last = f64::INFINITY;
    for f in [1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0] {
        let k = compute(f).unwrap().k_h_at_force_lb_per_in.in_inch();
        assert!(k < last);
        last = k;
    }
}

#[test]
fn concave_vs_convex() {
    let h = HertzContact::steel(0.25);
    for r2 in [0.8, 1.5, 3.0, 20.0] {
        let vex = h.stiffness(0.375, r2).unwrap();
        let cave = h.stiffness(0.375, -r2).unwrap();
        // The hand form r - sqrt(r^2 - b^2) loses log10(r/h) digits (~1e-8 left at r2 = 20 in).
        assert!(
            rel(vex, hand(1.0, 0.375, r2).k) < 1e-7,
            "{}",
            rel(vex, hand(1.0, 0.375, r2).k)
        );
        assert!(
            rel(cave, hand(1.0, 0.375, -r2).k) < 1e-7,
            "{}",
            rel(cave, hand(1.0, 0.375, -r2).k)
        );
        // The printed factor 2 of the concave formula halves K_h (leading order).
        assert!(rel(cave / vex, 0.5) < 1e-5, "r2 = {r2}: {}", cave / vex);
        // A concave surface is wider in contact than a convex one of equal radius.
        assert!(h.width(1.0, 0.75, -2.0 * r2) > h.width(1.0, 0.75, 2.0 * r2));
    }
    let flat = h.stiffness(0.375, f64::INFINITY).unwrap();
    assert!(rel(flat, hand(1.0, 0.375, 1.0e12).k) < 1e-6);
    assert!(matches!(
        h.stiffness(0.375, -0.375),
        Err(Error::InvalidParameter { field: "r2", .. })
    ));
}

#[test]
fn json_keys_are_the_documented_ones() {
    let text = serde_json::to_string(&compute(100.0).unwrap()).unwrap();
    let inch = camsim::units::json(&text, camsim::units::Units::Inch).unwrap();
    let v: serde_json::Value = serde_json::from_str(&inch).unwrap();
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "base_radius_in",
            "contact_width_in",
            "force_lb",
            "k_h_at_force_lb_per_in",
            "k_h_lb_per_in",
            "max_stress_psi",
            "roller_radius_in",
            "thickness_in",
        ]
    );
    assert_eq!(v["force_lb"], 100.0);
    let table = contact::render_table(&compute(100.0).unwrap(), camsim::units::Units::Inch);
    assert!(table.contains("6.451968e6"), "{table}");
}

#[test]
fn bad_force_is_refused_with_one_line_naming_the_flag() {
    fn one_line<E: std::fmt::Display>(e: E) {
        let s = format!("{e:#}");
        assert!(s.contains("--force"), "{s}");
        assert!(s.contains("positive"), "{s}");
        assert!(!s.contains('\n'), "{s}");
    }
    for f in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        one_line(compute(f).unwrap_err());
    }
    // The command line: clap refuses with one line naming --force, the value and the rule.
    let usage = |args: &[&str]| {
        let argv = ["camsim", "contact"].iter().chain(args).copied();
        camsim::cli::usage_line(&camsim::cli::parse_from(argv).unwrap_err())
    };
    for t in ["-2", "NaN", "0", "inf"] {
        assert_eq!(
            usage(&["--force", t]),
            format!("invalid value '{t}' for '--force <LB>': must be positive and finite")
        );
    }
    for t in ["abc", ""] {
        assert_eq!(
            usage(&["--force", t]),
            format!("invalid value '{t}' for '--force <LB>': not a number")
        );
    }
    assert_eq!(
        usage(&[]),
        "the following required arguments were not provided: --force <LB>"
    );
    let cli = camsim::cli::parse_from(["camsim", "contact", "--force", "12.5"]).unwrap();
    match cli.command {
        camsim::cli::Command::Contact(a) => assert_eq!(a.force, 12.5),
        other => panic!("{other:?}"),
    }
    one_line(
        contact::run(
            Args {
                scene: None,
                force: -7.0,
                json: false,
            },
            camsim::units::Units::Inch,
        )
        .unwrap_err(),
    );
    let _: ContactReport = compute(5.0).unwrap();
}

/// VI.1 preload: K_t of K_rb, K_h(unit force, base circle), K_vs; Eq. V.18.
#[test]
fn reference_preload_and_static_equilibrium() {
    let kh = compute(1.0).unwrap().k_h_lb_per_in.in_inch();
    let (krb, kvs) = (1.5e6, 1.48e6);
    let kt = series_stiffness(&[krb, kh, kvs]);
    assert!(rel(kt, krb * kh * kvs / (kh * kvs + krb * kvs + krb * kh)) < 1e-14);
    let p = return_spring_preload(kt, 60.0, 0.5).unwrap();
    // K_t = 667853.75 lb/in (40-digit check), F_p = 30 K_t/(K_t + 60) = 29.997305 lb.
    assert!(rel(kt, 667_853.748_680_766) < 1e-12);
    assert!(rel(p.force, 30.0 * kt / (kt + 60.0)) < 1e-14);
    assert!(rel(p.force, 29.997_305_04) < 1e-9);
    // The series elements share the preload: their deflections add up to Delta.
    let sum = p.force / krb + p.force / kh + p.force / kvs;
    assert!(rel(sum, p.compression) < 1e-13);
    // On the base circle (phi = 0) with the preload carried and no extra overlap,
    // the contact force is F_p (Eq. V.19 with y + y1 - y2 = 0).
    let c = contact_force(kh, 0.0, p.force, 0f64.cos());
    assert!(c.in_contact && c.force == p.force);
    // Lifting the roller by F_p/K_h (y2 = F_p/K_h, y = y1 = 0) takes the contact exactly
    // to the jump boundary.
    let c = contact_force(kh, 0.0 + 0.0 - p.force / kh, p.force, 1.0);
    assert!(c.force.abs() < 1e-9 * p.force);
    let c = contact_force(kh, -1.0e-3, p.force, 1.0);
    assert!(!c.in_contact && c.force == 0.0);
}

#[test]
fn f32_chain_agrees_with_f64() {
    let h32 = HertzContact::<f32>::steel(0.25);
    let kh32 = h32.stiffness(0.375, 1.5).unwrap();
    let kt32 = series_stiffness(&[1.5e6f32, kh32, 1.48e6]);
    let p32 = return_spring_preload(kt32, 60.0f32, 0.5).unwrap();
    let kh64 = compute(1.0).unwrap().k_h_lb_per_in.in_inch();
    assert!(rel(f64::from(kh32), kh64) < 2e-6, "{kh32} vs {kh64}");
    assert!(rel(f64::from(p32.force), 29.997_305_04) < 1e-6);
    assert!(
        rel(
            f64::from(h32.max_stress(100.0, 0.75, 3.0)),
            compute(100.0).unwrap().max_stress_psi.in_inch()
        ) < 1e-6
    );
}

#[test]
fn bearing_friction_opposes_the_follower() {
    // Fig. V.2 with F_c = 100 lb at phi = 20 deg, A = 2 in, B = 3 in, mu = 0.08.
    let phi = 20f64.to_radians();
    let (n1, n2) = bearing_normal_forces(100.0, phi.sin(), 2.0, 3.0);
    let lateral = 100.0 * phi.sin();
    assert!(rel(n1, lateral * 5.0 / 3.0) < 1e-14);
    assert!(rel(n2, lateral * 2.0 / 3.0) < 1e-14);
    let v_s = 1.0e-3;
    let up = coulomb_friction(0.08, n1, 10.0, v_s) + coulomb_friction(0.08, n2, 10.0, v_s);
    assert!(rel(up, -0.08 * (n1 + n2)) < 1e-14);
    let down = coulomb_friction(0.08, n1, -10.0, v_s) + coulomb_friction(0.08, n2, -10.0, v_s);
    assert_eq!(down, -up);
    // Continuous through zero velocity: neighbours within slope * dv.
    let (a, b) = (
        coulomb_friction(0.08, n1, -1e-9, v_s),
        coulomb_friction(0.08, n1, 1e-9, v_s),
    );
    assert!((a - b).abs() <= 2.0 * 0.08 * n1 / v_s * 1e-9 * 1.000_001);
    assert!(rel(spring_effective_mass(3.0e-4), 1.0e-4) < 1e-15);
}
