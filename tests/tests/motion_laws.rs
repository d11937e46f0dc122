//! `camsim laws`: the JSON shape and the peak coefficients against closed forms.

use std::f64::consts::PI;

use camsim::cmd::laws::{report, table, LawRow};
use camsim::report::Report;
use camsim_core::MotionLaw;

fn row<'a>(rows: &'a [LawRow], name: &str) -> &'a LawRow {
    rows.iter().find(|r| r.name == name).unwrap()
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol * (1.0 + want.abs()),
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn json_shape() {
    let report = report();
    let json = report.json().unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let obj = v.as_object().unwrap();
    assert_eq!(obj.len(), 1);
    let laws = obj["laws"].as_array().unwrap();
    assert_eq!(laws.len(), MotionLaw::ALL.len());
    let keys = [
        "name",
        "cv",
        "ca_max",
        "ca_min",
        "cj_max",
        "cj_min",
        "pressure_angle_max_deg",
    ];
    for (entry, law) in laws.iter().zip(MotionLaw::ALL) {
        let e = entry.as_object().unwrap();
        assert_eq!(e.len(), keys.len());
        assert_eq!(e["name"].as_str(), Some(law.name()));
        for k in &keys[1..] {
            assert!(e[*k].as_f64().unwrap().is_finite(), "{} {k}", law.name());
        }
    }
    // Keys in the documented order, as printed.
    assert!(json.starts_with(r#"{"laws":[{"name":"straight-line","cv":"#));
    for obj in json.split("},{") {
        let pos: Vec<usize> = keys
            .iter()
            .map(|k| obj.find(&format!("\"{k}\":")).unwrap())
            .collect();
        assert!(pos.windows(2).all(|w| w[0] < w[1]), "key order in {obj}");
    }
    // The text table lists every law.
    let text = report.text(camsim::units::Units::Inch);
    for law in MotionLaw::ALL {
        assert!(
            text.lines().any(|l| l.starts_with(law.name())),
            "{}",
            law.name()
        );
    }
}

#[test]
fn coefficients_match_closed_forms() {
    let rows = table();
    let tol = 1e-9;
    let cyc = row(&rows, "cycloidal");
    close(cyc.cv, 2.0, tol, "cycloidal cv");
    close(cyc.ca_max, 2.0 * PI, tol, "cycloidal ca");
    close(cyc.cj_min, -4.0 * PI * PI, tol, "cycloidal cj_min");
    let p345 = row(&rows, "3-4-5");
    close(p345.cv, 15.0 / 8.0, tol, "3-4-5 cv");
    // a = 60 u(1-u)(1-2u) peaks where u(1-u) = 1/6: 60 (1/6) (1/√3).
    close(p345.ca_max, 10.0 / 3f64.sqrt(), tol, "3-4-5 ca");
    close(p345.cj_min, 60.0 * (1.0 - 6.0 / 4.0), tol, "3-4-5 cj_min");
    let shm = row(&rows, "shm");
    close(shm.cv, PI / 2.0, tol, "shm cv");
    close(shm.ca_max, PI * PI / 2.0, tol, "shm ca");
    close(shm.cj_min, -PI.powi(3) / 2.0, tol, "shm cj");
    // Modified trapezoidal: s(1/2) = A (π + 2)/(16π) = 1/2.
    let amt = 8.0 * PI / (PI + 2.0);
    let mt = row(&rows, "modified-trapezoidal");
    close(mt.ca_max, amt, tol, "modified trapezoidal ca");
    close(mt.ca_min, -amt, tol, "modified trapezoidal ca_min");
    close(mt.cj_max, 4.0 * PI * amt, tol, "modified trapezoidal cj");
    close(
        mt.cv,
        amt * (0.25 + 1.0 / (2.0 * PI)),
        tol,
        "modified trapezoidal cv",
    );
    let ms = row(&rows, "modified-sine");
    close(ms.cv, 4.0 * PI / (PI + 4.0), tol, "modified sine cv");
    close(
        ms.ca_max,
        4.0 * PI * PI / (PI + 4.0),
        tol,
        "modified sine ca",
    );
    // Trapezoidal: s(1/2) = 3A/32 = 1/2, ramps of 1/8.
    let tr = row(&rows, "trapezoidal");
    close(tr.ca_max, 16.0 / 3.0, tol, "trapezoidal ca");
    close(tr.cj_max, 8.0 * 16.0 / 3.0, tol, "trapezoidal cj");
    let p4 = row(&rows, "4-5-6-7");
    close(p4.cv, 140.0 / 64.0, tol, "4-5-6-7 cv");
    close(p4.cj_max, 42.0, tol, "4-5-6-7 cj_max");
    close(p4.cj_min, -52.5, tol, "4-5-6-7 cj_min");
    let dh = row(&rows, "double-harmonic");
    close(
        dh.ca_min,
        -PI * PI,
        tol,
        "double harmonic ca_min (at the end)",
    );
    // Symmetric laws have ca_min = -ca_max.
    for law in MotionLaw::ALL.iter().filter(|l| l.is_symmetric()) {
        let r = row(&rows, law.name());
        close(r.ca_min, -r.ca_max, 1e-9, law.name());
    }
}

#[test]
fn pressure_angles() {
    let rows = table();
    let beta = 150f64.to_radians();
    let (h, ra) = (1.5, 1.875);
    // Straight line: constant slope h/β, largest where y = 0.
    close(
        row(&rows, "straight-line").pressure_angle_max_deg,
        (h / beta / ra).atan().to_degrees(),
        1e-9,
        "straight-line phi",
    );
    // Every law: a dense scan of tan φ = (h v/β)/(R_a + h s) over the rise alone (the
    // return is the rise mirrored in time, so it has the same extreme).
    for law in MotionLaw::ALL {
        let n = 200_000;
        let phi = (0..=n)
            .map(|k| {
                let x = law.eval(k as f64 / n as f64);
                (h * x.v / beta).atan2(ra + h * x.s)
            })
            .fold(0.0f64, f64::max)
            .to_degrees();
        let got = row(&rows, law.name()).pressure_angle_max_deg;
        assert!(
            got >= phi - 1e-9 && got - phi < 1e-6,
            "{}: {got} vs scan {phi}",
            law.name()
        );
    }
}
