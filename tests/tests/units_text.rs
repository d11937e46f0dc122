//! Issue 18: `--units si` converts the printed tables and the CSV files, not only the
//! JSON. The SI numbers are read back from the printed text and checked against the inch
//! text's numbers times factors written here from the definitions (1 in = 25.4 mm,
//! 1 lbf = 0.45359237 kg x 9.80665 m/s^2), to the rounding of the two printed values.
//!
//! The unit family is one process-wide setting (`--units`), so everything here runs in
//! one test, one command after the other.

use camsim::cli::{self, Command};
use camsim::cmd::run;
use camsim::report::Report;
use camsim::units::{self, Units};

const IN_MM: f64 = 25.4;
const LBF_N: f64 = 0.453_592_37 * 9.806_65;
const PSI_MPA: f64 = LBF_N / (IN_MM * IN_MM);
const LBIN_NM: f64 = LBF_N * IN_MM / 1000.0;

fn run_text(units: Units) -> String {
    units::set(units);
    let argv = [
        "camsim",
        "run",
        "--rpm",
        "500",
        "--start",
        "static",
        "--revolutions",
        "2",
    ];
    let Command::Run(a) = cli::parse_from(argv).unwrap().command else {
        panic!("not run")
    };
    let text = run::report(&a).unwrap().text();
    units::set(Units::Inch);
    text
}

/// The half-unit of the last printed digit of `s` (`8.672` -> 0.0005; `1.995e-3` ->
/// 0.0005e-3).
fn half_ulp(s: &str) -> f64 {
    let (mant, exp) = match s.split_once('e') {
        Some((m, e)) => (m, e.parse::<i32>().unwrap()),
        None => (s, 0),
    };
    let decimals = mant.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    0.5 * 10f64.powi(exp - decimals)
}

/// `si` printed equals `inch` printed times `factor`, to the two printings' rounding.
fn agrees(inch: &str, si: &str, factor: f64, what: &str) {
    let (a, b): (f64, f64) = (inch.parse().unwrap(), si.parse().unwrap());
    let tol = half_ulp(si) + half_ulp(inch) * factor.abs() + 1e-12 * b.abs();
    assert!(
        (b - a * factor).abs() <= tol,
        "{what}: SI {si} vs inch {inch} x {factor} = {} (tolerance {tol})",
        a * factor
    );
}

/// The rows of revolution `rev`'s per-period table: whitespace-split fields.
fn period_rows(text: &str, rev: u32) -> Vec<Vec<String>> {
    let mut lines = text
        .lines()
        .skip_while(|l| *l != format!("revolution {rev}"))
        .skip(2);
    let mut rows = Vec::new();
    for l in lines.by_ref() {
        if l.trim().is_empty() {
            break;
        }
        rows.push(l.split_whitespace().map(str::to_string).collect());
    }
    rows
}

/// A unit of the inch family left in text printed in SI: a token that is an inch unit
/// (`lb`, `psi`, `lb/in`, `in/s^2`, ...), or `in` after a number (`1.5 in`).
fn inch_label(text: &str) -> Option<String> {
    const INCH: [&str; 12] = [
        "lb",
        "psi",
        "hp",
        "lb/in",
        "in/s",
        "in/s2",
        "in/s^2",
        "in/rad^2",
        "lb*in/rad",
        "lb*in*s^2",
        "lb*s^2/in",
        "in^2",
    ];
    for line in text.lines() {
        let tokens: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || ",;()[]:".contains(c))
            .filter(|t| !t.is_empty())
            .collect();
        for (i, t) in tokens.iter().enumerate() {
            let after_number =
                i > 0 && tokens[i - 1].trim_start_matches('±').parse::<f64>().is_ok();
            if INCH.contains(t) || (*t == "in" && after_number) {
                return Some(format!("`{t}` in: {line}"));
            }
        }
    }
    None
}

/// Runs `argv` as the binary does (its stdout goes to the test's).
fn main(argv: &[&str]) -> u8 {
    let code = cli::main_from(argv.iter().copied());
    units::set(Units::Inch);
    code
}

fn csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn si_text_and_csv_are_the_inch_numbers_converted() {
    // --- run: the per-period table, column by column.
    let (inch, si) = (run_text(Units::Inch), run_text(Units::Si));
    assert!(
        si.contains("units: mm, N, s; torque N m; stress MPa;"),
        "{si}"
    );
    assert!(inch.contains("units: in, lb, s; torque lb in; stress psi;"));
    // period, rms_y, rms_v, rms_a, T_avg, T_max, T_min, Fc_min, Fc_max, Fc_avg, stress.
    let factors = [
        IN_MM, IN_MM, IN_MM, LBIN_NM, LBIN_NM, LBIN_NM, LBF_N, LBF_N, LBF_N, PSI_MPA,
    ];
    let (ri, rs) = (period_rows(&inch, 2), period_rows(&si, 2));
    assert_eq!(ri.len(), 4, "{inch}");
    assert_eq!(rs.len(), 4, "{si}");
    let mut checked = 0;
    for (a, b) in ri.iter().zip(&rs) {
        assert_eq!(a[0], b[0]);
        for (k, f) in factors.iter().enumerate() {
            agrees(
                &a[k + 1],
                &b[k + 1],
                *f,
                &format!("{} column {}", a[0], k + 1),
            );
            checked += 1;
        }
        // AORD and the jump flag are the same numbers in either family.
        assert_eq!(a[11..], b[11..]);
    }
    assert_eq!(checked, 40);
    // The verdict: the smallest contact force and the pitch-curve radius.
    let after = |t: &str, key: &str| -> String {
        let i = t.find(key).unwrap_or_else(|| panic!("{key}: {t}")) + key.len();
        t[i..].split_whitespace().next().unwrap().to_string()
    };
    agrees(
        &after(&inch, "smallest contact force "),
        &after(&si, "smallest contact force "),
        LBF_N,
        "smallest contact force",
    );
    agrees(
        &after(&inch, "smallest pitch-curve radius "),
        &after(&si, "smallest pitch-curve radius "),
        IN_MM,
        "pitch-curve radius",
    );
    assert_eq!(
        after(&si, "smallest pitch-curve radius ").len(),
        "47.625".len()
    );
    assert!(si.contains(" N/mm, "), "{si}");
    assert_eq!(inch_label(&si), None);
    // The inch text still names its units (the check can fail).
    assert!(inch_label(&inch).is_some());

    // --- sweep: its table and its CSV, inch and SI.
    let d = std::env::temp_dir().join(format!("camsim-units-text-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let (ci, cs) = (d.join("inch.csv"), d.join("si.csv"));
    let sweep = |units: &str, path: &std::path::Path| {
        let p = path.to_str().unwrap();
        main(&[
            "camsim",
            "--units",
            units,
            "sweep",
            "--rpm",
            "600:800:2",
            "--csv",
            p,
        ])
    };
    assert_eq!(sweep("inch", &ci), 0);
    assert_eq!(sweep("si", &cs), 0);
    let ((hi, ri), (hs, rs)) = (csv(&ci), csv(&cs));
    assert_eq!(
        hs,
        [
            "rpm",
            "jump",
            "min_contact_force_n",
            "peak_contact_force_n",
            "rms_acceleration_deviation_mm_per_s2",
            "peak_cam_torque_n_m",
            "peak_contact_stress_mpa",
            "peak_drive_power_kw",
        ]
    );
    assert_eq!(hi[2], "min_contact_force_lb");
    let hp_kw = 550.0 * 12.0 * IN_MM / 1000.0 * LBF_N / 1000.0;
    let factors = [1.0, 1.0, LBF_N, LBF_N, IN_MM, LBIN_NM, PSI_MPA, hp_kw];
    assert_eq!(ri.len(), 2);
    for (a, b) in ri.iter().zip(&rs) {
        for (k, f) in factors.iter().enumerate() {
            let (x, y): (f64, f64) = (a[k].parse().unwrap(), b[k].parse().unwrap());
            assert!(
                (y - x * f).abs() <= 1e-12 * y.abs(),
                "{}: {y} vs {x} x {f}",
                hs[k]
            );
        }
    }

    // --- run --csv: the header names mm, N; the values convert.
    let (ci, cs) = (d.join("run-inch.csv"), d.join("run-si.csv"));
    let run_csv = |units: &str, path: &std::path::Path| {
        let p = path.to_str().unwrap();
        main(&[
            "camsim",
            "--units",
            units,
            "run",
            "--rpm",
            "500",
            "--start",
            "static",
            "--revolutions",
            "1",
            "--csv-every-deg",
            "30",
            "--csv",
            p,
        ])
    };
    assert_eq!(run_csv("inch", &ci), 0);
    assert_eq!(run_csv("si", &cs), 0);
    let ((hi, ri), (hs, rs)) = (csv(&ci), csv(&cs));
    assert_eq!(hi.len(), hs.len());
    for (name, inch_name, f) in [
        ("y5_mm", "y5_in", IN_MM),
        ("v_y5_mm_per_s", "v_y5_in_s", IN_MM),
        ("a_y5_mm_per_s2", "a_y5_in_s2", IN_MM),
        ("k_h_n_per_mm", "k_h_lb_in", LBF_N / IN_MM),
        ("contact_force_n", "contact_force_lb", LBF_N),
        ("torque_out_n_m", "torque_out_lb_in", LBIN_NM),
        ("contact_stress_mpa", "contact_stress_psi", PSI_MPA),
        ("theta_c_rad", "theta_c_rad", 1.0),
    ] {
        let (i, j) = (
            hi.iter().position(|h| h == inch_name).unwrap(),
            hs.iter()
                .position(|h| h == name)
                .unwrap_or_else(|| panic!("{name}: {hs:?}")),
        );
        assert_eq!(i, j);
        for (a, b) in ri.iter().zip(&rs) {
            let (x, y): (f64, f64) = (a[i].parse().unwrap(), b[j].parse().unwrap());
            assert!(
                (y - x * f).abs() <= 1e-12 * y.abs().max(1e-300),
                "{name}: {y} vs {x}"
            );
        }
    }
    assert!(
        !hs.iter().any(|h| h.ends_with("_in") || h.ends_with("_lb")),
        "{hs:?}"
    );
    std::fs::remove_dir_all(&d).unwrap();

    // --- every other converted text: no inch unit left.
    units::set(Units::Si);
    let texts = [
        ("laws", camsim::cmd::laws::report().text()),
        (
            "modal",
            camsim::cmd::modal::render_table(&camsim::cmd::modal::analyse().unwrap()),
        ),
        (
            "contact",
            camsim::cmd::contact::render_table(&camsim::study::contact::compute(100.0).unwrap()),
        ),
    ];
    units::set(Units::Inch);
    for (name, text) in texts {
        assert_eq!(inch_label(&text), None, "{name}");
    }
    // ... which in inch do name inch units.
    assert!(inch_label(&camsim::cmd::laws::report().text()).is_some());
}
