use super::text::signed_pct_1;
use super::*;
use camsim_core::{key, modal_analysis, rotational_system, Design, DriveLaw};

use crate::sim::{self, RunSpec};
use crate::study::montecarlo::LeftRange;
use std::collections::BTreeMap;

/// A change that rounds to zero reads 0.0 with no sign; any other keeps its sign.
/// Only cases that left the range with the follower on the cam fail; one case with
/// outputs, or one that jumped first, is an answer.
#[test]
fn a_study_fails_only_when_every_case_failed_without_a_separation() {
    let nw = |jump| NotWorkableCase {
        group: "mass",
        change_pct: -30,
        cam: "actual",
        jump,
        reason: "the model left its valid range at cam angle 1 deg".into(),
    };
    let e = all_failed(&[], &[nw(false), nw(false)]).unwrap_err();
    assert!(
        format!("{e}").contains("no case is workable")
            && format!("{e}").contains("mass -30 % on the actual cam"),
        "{e}"
    );
    assert!(all_failed(&[], &[nw(false), nw(true)]).is_ok());
    assert!(all_failed(&[], &[]).is_ok());
    let case = Case {
        group: "baseline",
        change_pct: 0,
        cam: "theoretical",
        outputs: Outputs {
            rms_displacement_in: 0.0.into(),
            rms_velocity_in_per_s: 0.0.into(),
            rms_acceleration_in_per_s2: 0.0.into(),
            rms_angular_velocity_rad_per_s: 0.0,
            contact_stress_avg_psi: 0.0.into(),
            jump: false,
        },
    };
    assert!(all_failed(&[case], &[nw(false)]).is_ok());
}

#[test]
fn a_change_that_rounds_to_zero_has_no_sign() {
    assert_eq!(signed_pct_1(-0.04), "0.0");
    assert_eq!(signed_pct_1(0.049), "0.0");
    assert_eq!(signed_pct_1(0.0), "0.0");
    assert_eq!(signed_pct_1(-0.06), "-0.1");
    assert_eq!(signed_pct_1(39.6), "+39.6");
    assert_eq!(signed_pct_1(-0.2), "-0.2");
}

/// Every numeric leaf of a design's serialization, by dotted key.
fn leaves(d: &Design<f64>) -> BTreeMap<String, f64> {
    fn walk(v: &serde_json::Value, path: &str, out: &mut BTreeMap<String, f64>) {
        match v {
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(x, &p, out);
                }
            }
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"), out);
                }
            }
            serde_json::Value::Number(n) => {
                out.insert(path.to_string(), n.as_f64().unwrap());
            }
            _ => {}
        }
    }
    let mut out = BTreeMap::new();
    walk(&serde_json::to_value(d).unwrap(), "", &mut out);
    out
}

/// The keys whose value differs between two designs, with the ratio new / old.
fn changed(a: &Design<f64>, b: &Design<f64>) -> BTreeMap<String, f64> {
    let (la, lb) = (leaves(a), leaves(b));
    assert_eq!(la.keys().collect::<Vec<_>>(), lb.keys().collect::<Vec<_>>());
    la.iter()
        .filter(|(k, v)| lb[*k] != **v)
        .map(|(k, v)| (k.clone(), lb[k] / v))
        .collect()
}

#[test]
fn each_group_moves_exactly_its_listed_parameters() {
    let d = Design::<f64>::reference();
    let f = 1.37;
    for g in Group::ALL {
        let s = scaled(&d, g, f);
        s.validate().unwrap();
        let c = changed(&d, &s);
        let mut want: Vec<&str> = g.keys().to_vec();
        want.sort_unstable();
        assert_eq!(
            c.keys().map(String::as_str).collect::<Vec<_>>(),
            want,
            "{g:?}"
        );
        for (k, r) in &c {
            assert!((r - f).abs() < 1e-15, "{g:?} {k}: ratio {r}");
        }
        // Neither the return spring nor the Hertz contact nor the program moves.
        assert_eq!(
            (s.k_rs, s.delta_rs, s.k_rs_modal),
            (d.k_rs, d.delta_rs, d.k_rs_modal)
        );
        assert_eq!(s.hertz, d.hertz);
        assert_eq!(s.geometry, d.geometry);
        assert_eq!(s.program, d.program);
        // A change of 0 is the baseline exactly.
        assert_eq!(scaled(&d, g, 1.0), d);
    }
    // Without the regulated drive the damping group has no feed-forward to move.
    let mut ideal = d.clone();
    ideal.drive = DriveLaw::ConstantCamSpeed;
    let c = changed(&ideal, &scaled(&ideal, Group::Damping, f));
    assert_eq!(c.len(), DAMPING_KEYS.len() - 1);
    assert!(!c.contains_key(key::DRIVE_T_STEADY));
    // The groups do not overlap.
    let mut all: Vec<&str> = Group::ALL.iter().flat_map(|g| g.keys().to_vec()).collect();
    all.sort_unstable();
    let n = all.len();
    all.dedup();
    assert_eq!(all.len(), n);
}

/// The rotational system (Eq. VI.7) is made of the groups' parameters alone: masses
/// times λ divide its natural frequencies by sqrt(λ); masses and stiffnesses times λ
/// leave them; stiffnesses times λ multiply them by sqrt(λ).
#[test]
fn natural_frequencies_scale_as_sqrt_of_stiffness_over_mass() {
    let omegas = |d: &Design<f64>| {
        let (k, m) = rotational_system(d.i_m, d.i_cp, d.i_c, d.k_s1, d.k_s2);
        modal_analysis(&k, &m).unwrap().omega
    };
    let d = Design::<f64>::reference();
    let w = omegas(&d);
    assert!(w[0].abs() < 1e-6 * w[2] && w[1] > 0.0, "{w:?}");
    for lambda in [0.7, 1.3] {
        let m = scaled(&d, Group::Mass, lambda);
        let mk = scaled(&m, Group::Stiffness, lambda);
        let k = scaled(&d, Group::Stiffness, lambda);
        for (got, want) in [
            (omegas(&m), 1.0 / lambda.sqrt()),
            (omegas(&mk), 1.0),
            (omegas(&k), lambda.sqrt()),
        ] {
            for i in 1..3 {
                let r = got[i] / w[i];
                assert!(
                    (r - want).abs() < 1e-12,
                    "lambda {lambda}: mode {i} ratio {r}, want {want}"
                );
            }
        }
    }
}

#[test]
fn elasticity_is_exact_for_a_power_law_and_undefined_at_zero() {
    for p in [-2.5, -1.0, 0.0, 0.5, 3.0] {
        let f = |x: f64| 7.0 * x.powf(p);
        let x = 3.3;
        let e = elasticity(f(x * 1.01), f(x * 0.99), 0.01).unwrap();
        assert!((e - p).abs() < 1e-10, "{p}: {e}");
    }
    assert_eq!(elasticity(0.0, 1.0, 0.01), None);
    assert_eq!(elasticity(1.0, f64::NAN, 0.01), None);
    assert_eq!(elasticity(1.0, 1.0, 0.0), None);
}

/// The preload F_p = K_t K_rs δ_rs / (K_t + K_rs) (Eq. V.18) through the per-key
/// perturbation: its elasticity on δ_rs is 1, on K_rs K_t / (K_t + K_rs), on K_rb
/// (K_t / K_rb)·K_rs / (K_t + K_rs), to the central difference's O(h²).
#[test]
fn preload_elasticities_match_their_closed_forms() {
    let d = Design::<f64>::reference();
    let fp = |name: &str, f: f64| key_scaled(&d, name, f).unwrap().preload().unwrap();
    let e = |name: &str| elasticity(fp(name, 1.01), fp(name, 0.99), 0.01).unwrap();
    let k_h = d.k_h_base().unwrap();
    let k_t = 1.0 / (1.0 / d.k_rb + 1.0 / k_h + 1.0 / d.k_vs);
    assert!((e(key::DELTA_RS) - 1.0).abs() < 1e-12);
    let want = k_t / (k_t + d.k_rs);
    assert!(
        (e(key::K_RS) - want).abs() < 1e-5,
        "{} {want}",
        e(key::K_RS)
    );
    let want = (k_t / d.k_rb) * d.k_rs / (k_t + d.k_rs);
    assert!(
        (e(key::K_RB) - want).abs() < 1e-5 * want.max(1e-3),
        "{} {want}",
        e(key::K_RB)
    );
}

#[test]
fn every_per_key_key_moves_one_number_by_its_factor() {
    let d = Design::<f64>::reference();
    let keys = per_key_keys(&d).unwrap();
    // Every design key but ω0, the drive's reference speed, the modal spring rate
    // and the free play (0).
    assert_eq!(keys.len(), key::DESIGN_KEYS.len() - 4);
    for (name, _, value) in keys {
        let s = key_scaled(&d, name, 1.01).unwrap();
        let c = changed(&d, &s);
        assert_eq!(c.len(), 1, "{name}: {c:?}");
        let (k, r) = c.iter().next().unwrap();
        assert_eq!(k, name);
        assert!((r - 1.01).abs() < 1e-15);
        assert_eq!(leaves(&d)[name], value);
    }
    assert!(key_scaled(&d, "no_such_key", 1.01).is_err());
    assert!(key_scaled(&d, key::K_RB, -1.0).is_err());
}

#[test]
fn combined_rms_is_the_duration_weighted_mean_square() {
    // (1 s at RMS 3, 3 s at RMS 1): sqrt((9 + 3) / 4).
    assert!((combine_rms(&[(1.0, 3.0), (3.0, 1.0)]) - 3f64.sqrt()).abs() < 1e-15);
    assert_eq!(combine_rms(&[]), 0.0);
}

/// Revolution 2's RMS deviations combined from the per-period statistics equal the
/// same integrals taken directly over the revolution (which also cover the few steps
/// that straddle a period boundary, a few of some thousands).
#[test]
fn combined_rms_matches_the_direct_integral_of_the_revolution() {
    let mut spec = RunSpec::reference();
    spec.dofs.horizontal = false;
    let out = outputs(&spec).unwrap();
    let mut s = spec.clone();
    s.revolutions = REVOLUTION;
    let mut direct = RevolutionIntegrals::new(REVOLUTION, s.design.omega0);
    sim::run(&s, &mut direct).unwrap();
    let m = direct.means();
    let period = 2.0 * std::f64::consts::PI / s.design.omega0;
    assert!(
        (direct.duration / period - 1.0).abs() < 0.05,
        "{}",
        direct.duration
    );
    for (i, v) in out.values()[..3].iter().enumerate() {
        assert!(
            (v / m[i] - 1.0).abs() < 2e-3,
            "output {i}: {v} against {}",
            m[i]
        );
    }
    // The cam's speed deviation and stress come from the direct integrals.
    assert_eq!(out.rms_angular_velocity_rad_per_s, m[3]);
    assert_eq!(out.contact_stress_avg_psi.in_inch(), m[4]);
    // On the base circle the stress is tens of thousands of psi: a positive average
    // below the largest per-period stress.
    let stress = out.contact_stress_avg_psi.in_inch();
    assert!(stress > 1e4 && stress < 3e5);
    // The same run again: the same numbers (the baseline is a change of 0).
    assert_eq!(outputs(&spec).unwrap(), out);
}

/// `--per-key`'s bookkeeping on a model whose outputs are power laws of the keys:
/// each elasticity is its exponent, whatever the thread count, and the ranking
/// follows the onset's magnitude.
#[test]
fn per_key_recovers_the_exponents_of_a_power_law_model_and_ranks_by_the_onset() {
    let eval = |d: &Design<f64>| -> Result<KeyOutcome> {
        let out = Outputs {
            rms_displacement_in: (d.k_rs.powf(0.5) * d.m_l.powf(-2.0)).into(),
            rms_velocity_in_per_s: d.rho.powf(1.5).into(),
            rms_acceleration_in_per_s2: 3.0.into(),
            rms_angular_velocity_rad_per_s: d.k_s1.powf(-0.25),
            contact_stress_avg_psi: d.hertz.youngs_1.powf(0.5).into(),
            jump: false,
        };
        // No onset when the roller is light (a key without one ranks last).
        let onset = (d.m_r >= 0.00013).then(|| 900.0 * (d.k_rs / d.rho).sqrt() * d.e1.powf(0.1));
        Ok(Ok((out, onset)))
    };
    let d = Design::<f64>::reference();
    let one = per_key_with(&d, 1, false, eval).unwrap();
    let two = per_key_with(&d, 2, false, eval).unwrap();
    assert_eq!(one, two);
    assert_eq!(one.len(), per_key_keys(&d).unwrap().len());
    let get = |k: &str| one.iter().find(|x| x.key == k).unwrap().elasticity.clone();
    let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-9;
    assert!(close(get(key::K_RS).rms_displacement_in, 0.5));
    assert!(close(get(key::M_L).rms_displacement_in, -2.0));
    assert!(close(get(key::RHO).rms_velocity_in_per_s, 1.5));
    assert!(close(get(key::K_S1).rms_angular_velocity_rad_per_s, -0.25));
    assert!(close(get(key::ROLLER_YOUNGS).contact_stress_avg_psi, 0.5));
    assert!(close(get(key::K_RS).jump_onset_rpm, 0.5));
    assert!(close(get(key::RHO).jump_onset_rpm, -0.5));
    assert!(close(get(key::E1).jump_onset_rpm, 0.1));
    assert!(close(get(key::C_MB).jump_onset_rpm, 0.0));
    assert!(close(get(key::C_MB).rms_acceleration_in_per_s2, 0.0));
    // The roller's mass at −1 % has no onset: no elasticity, ranked last.
    assert_eq!(get(key::M_R).jump_onset_rpm, None);
    assert_eq!(one.last().unwrap().key, key::M_R);
    // Ranked by |onset|: ρ and K_rs tie at 0.5, ρ first by its larger other
    // elasticity (1.5 against K_rs's 0.5), then e1 (0.1).
    let top: Vec<&str> = one.iter().take(3).map(|k| k.key).collect();
    assert_eq!(top, [key::RHO, key::K_RS, key::E1]);
    // A failing evaluation names the key.
    let e = per_key_with(&d, 1, false, |_| -> Result<KeyOutcome> {
        anyhow::bail!("boom")
    })
    .unwrap_err();
    assert!(format!("{e:#}").contains("times 1.01: boom"), "{e:#}");
}

/// A key whose perturbed design leaves the model's valid range (docs/MODEL.md
/// §3.20) has no elasticity and says why, at which factor and whether it jumped
/// first; so does one the design check refuses at −1 % (a cantilever 1.885 in long
/// clears the roller at full lift by 0.01 in, 0.99 of it by −0.009 in); they rank
/// last; the others keep their exponents; only a study of no workable key fails.
/// The reference with a cantilever 0.01 in longer than the roller's reach at full lift.
fn design_at_the_edge() -> Design<f64> {
    let mut d = Design::<f64>::reference();
    d.e2 = d.program.max_lift() + d.geometry.roller_radius + 0.01;
    d.validate().unwrap();
    d
}

/// A stand-in study of known exponents: a softer k_s2 than `base`'s leaves the range,
/// a heavier load jumps and then leaves it; the others give rms y ∝ k_rs^0.5 and an
/// onset ∝ rho^-0.5.
fn stand_in(base: &Design<f64>, d: &Design<f64>) -> Result<KeyOutcome> {
    let (k_s2, m_l) = (base.k_s2, base.m_l);
    {
        if d.k_s2 < k_s2 {
            return Ok(Err(LeftRange {
                separated: false,
                reason: "twist beyond its bound".into(),
            }));
        }
        if d.m_l > m_l {
            return Ok(Err(LeftRange {
                separated: true,
                reason: "thrown off".into(),
            }));
        }
        let out = Outputs {
            rms_displacement_in: d.k_rs.powf(0.5).into(),
            rms_velocity_in_per_s: 1.0.into(),
            rms_acceleration_in_per_s2: 1.0.into(),
            rms_angular_velocity_rad_per_s: 1.0,
            contact_stress_avg_psi: 1.0.into(),
            jump: false,
        };
        Ok(Ok((out, Some(900.0 * d.rho.powf(-0.5)))))
    }
}

#[test]
fn per_key_reports_keys_that_leave_the_range_and_goes_on() {
    let d = design_at_the_edge();
    let keys = per_key_with(&d, 2, false, |x| stand_in(&d, x)).unwrap();
    assert_eq!(keys.len(), per_key_keys(&d).unwrap().len());
    let row = |k: &str| keys.iter().find(|x| x.key == k).unwrap();
    let nw = |k: &str| row(k).not_workable.clone().unwrap();
    assert_eq!((nw(key::K_S2).factor, nw(key::K_S2).jump), (0.99, false));
    assert_eq!(nw(key::K_S2).reason, "twist beyond its bound");
    assert_eq!((nw(key::M_L).factor, nw(key::M_L).jump), (1.01, true));
    let e2 = nw(key::E2);
    assert_eq!((e2.factor, e2.jump), (0.99, false));
    assert!(
        e2.reason.contains("design check refuses") && e2.reason.contains(key::E2),
        "{}",
        e2.reason
    );
    assert_eq!(
        nw(key::K_S2).text(),
        "not workable at x0.99: twist beyond its bound"
    );
    assert!(nw(key::M_L)
        .text()
        .starts_with("jumps, then the model left"));
    for k in [key::K_S2, key::M_L, key::E2] {
        assert_eq!(row(k).elasticity, Elasticities::default(), "{k}");
    }
    let n = keys.len();
    let mut last: Vec<&str> = keys[n - 3..].iter().map(|k| k.key).collect();
    last.sort_unstable();
    let mut want = [key::K_S2, key::M_L, key::E2];
    want.sort_unstable();
    assert_eq!(last, want);
    assert!((row(key::K_RS).elasticity.rms_displacement_in.unwrap() - 0.5).abs() < 1e-9);
    assert!((row(key::RHO).elasticity.jump_onset_rpm.unwrap() + 0.5).abs() < 1e-9);
    assert_eq!(keys[0].key, key::RHO);
    // JSON: no elasticity numbers, the reason beside them.
    let j = serde_json::to_value(row(key::K_S2)).unwrap();
    assert_eq!(j["elasticity"], serde_json::json!({}));
    assert_eq!(j["not_workable"]["reason"], "twist beyond its bound");
    assert!(serde_json::to_value(row(key::K_RS))
        .unwrap()
        .get("not_workable")
        .is_none());
}

/// Every key out of range: the study fails, naming why.
#[test]
fn per_key_with_no_workable_key_fails_naming_why() {
    let d = design_at_the_edge();
    let e = per_key_with(&d, 1, false, |_| -> Result<KeyOutcome> {
        Ok(Err(LeftRange {
            separated: false,
            reason: "stalled".into(),
        }))
    })
    .unwrap_err();
    let msg = format!("{e:#}");
    assert!(
        msg.contains("no key is workable") && msg.contains("stalled"),
        "{msg}"
    );
}

/// Elasticities have no unit: an SI report gives the same numbers under the same keys.
#[test]
fn elasticities_are_not_converted_under_si() {
    let e = super::per_key::Elasticities {
        rms_displacement_in: Some(0.5),
        rms_velocity_in_per_s: Some(-1.0),
        rms_acceleration_in_per_s2: Some(2.0),
        rms_angular_velocity_rad_per_s: Some(0.25),
        contact_stress_avg_psi: Some(0.75),
        jump_onset_rpm: Some(-0.125),
    };
    let text = serde_json::to_string(&serde_json::json!({ "elasticity": e })).unwrap();
    let inch = crate::units::json(&text, crate::units::Units::Inch).unwrap();
    let si = crate::units::json(&text, crate::units::Units::Si).unwrap();
    assert_eq!(inch, si);
    let v: serde_json::Value = serde_json::from_str(&si).unwrap();
    assert_eq!(v["elasticity"]["rms_displacement_deviation"], 0.5);
    assert_eq!(v["elasticity"]["contact_stress_average"], 0.75);
}
