//! Issue 18: `--units si` converts the printed tables and the CSV files, not only the
//! JSON. The SI numbers are read back from the printed text and checked against the inch
//! text's numbers times factors written here from the definitions (1 in = 25.4 mm,
//! 1 lbf = 0.45359237 kg x 9.80665 m/s^2, 1 psi = 1 lbf/in^2), to the rounding of the
//! two printed values: run, sweep, montecarlo's statistics, design spring's answer, and
//! `--allowable-stress` read in MPa under `--units si`.
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

/// The text report of a study command (`argv` after `camsim`), run in this process in
/// `units`.
fn study_text(argv: &[&str], units: Units) -> String {
    use camsim::cmd::{compare, design, montecarlo, sensitivity, tolerance_study};
    units::set(units);
    let all: Vec<&str> = std::iter::once("camsim")
        .chain(argv.iter().copied())
        .collect();
    let text = match cli::parse_from(all).unwrap().command {
        Command::Montecarlo(a) => match montecarlo::execute(&a).unwrap() {
            montecarlo::Outcome::Study(r) => r.text(),
            montecarlo::Outcome::Shard(r) => r.text(),
        },
        Command::Compare(a) => compare::report(&a).unwrap().text(),
        Command::ToleranceStudy(a) => tolerance_study::report(&a).unwrap().text(),
        Command::Sensitivity(a) => sensitivity::report(&a).unwrap().text(),
        Command::Design(a) => match a.what {
            design::What::Spring(s) => design::spring(&s).unwrap().text(),
            design::What::Speed(m) => design::mc_search(&m, true).unwrap().text(),
            design::What::Tolerance(m) => design::mc_search(&m, false).unwrap().text(),
        },
        _ => panic!("not a study: {argv:?}"),
    };
    units::set(Units::Inch);
    text
}

/// The numbers of a line: its whitespace-, comma-, bracket-separated tokens that parse
/// (a trailing `+` or `-` of a search's tried value dropped).
fn numbers(line: &str) -> Vec<String> {
    line.split(|c: char| c.is_whitespace() || ",;()[]:".contains(c))
        .map(|t| t.trim_end_matches(['+', '-']))
        .filter(|t| t.parse::<f64>().is_ok())
        .map(str::to_string)
        .collect()
}

/// Montecarlo's statistics tables: (section, row name) and the row's five statistics.
fn moments_rows(text: &str) -> Vec<((String, String), Vec<String>)> {
    let mut section = String::new();
    let mut rows = Vec::new();
    for l in text.lines() {
        if !l.starts_with(' ') {
            section = l.split(':').next().unwrap_or("").to_string();
            continue;
        }
        if l.trim_start().starts_with("mean") {
            continue;
        }
        let (label, rest) = l.split_at(19);
        let name = label.trim().split(',').next().unwrap().to_string();
        rows.push((
            (section.clone(), name),
            rest.split_whitespace().map(str::to_string).collect(),
        ));
    }
    rows
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

    // --- montecarlo: every statistic of every table, 4 cams.
    let mc = ["montecarlo", "--samples", "4", "--threads", "2"];
    let (inch, si) = (study_text(&mc, Units::Inch), study_text(&mc, Units::Si));
    let (ri, rs) = (moments_rows(&inch), moments_rows(&si));
    assert_eq!(ri.len(), 4 * 13 + 6 + 2, "{inch}");
    assert_eq!(ri.len(), rs.len(), "{si}");
    let factor = |name: &str| match name {
        "rms_y" | "rms_v" | "rms_a" | "sum rms_a" | "rms lift dev" => IN_MM,
        "T_avg" | "T_max" | "T_min" => LBIN_NM,
        "Fc_min" | "Fc_max" | "Fc_avg" => LBF_N,
        "stress" => PSI_MPA,
        "aord_m" | "aord_cp" | "aord_c" | "FPR" => 1.0,
        other => panic!("row {other}"),
    };
    let mut checked = 0;
    for ((ki, a), (ks, b)) in ri.iter().zip(&rs) {
        assert_eq!(ki, ks);
        assert_eq!((a.len(), b.len()), (5, 5), "{ki:?}");
        for (x, y) in a.iter().zip(b) {
            agrees(x, y, factor(&ki.1), &format!("montecarlo {ki:?}"));
            checked += 1;
        }
    }
    assert_eq!(checked, 5 * 60);
    assert!(si.contains("  rms_a, mm/s^2 "), "{si}");
    assert!(si.contains("  stress, MPa "), "{si}");
    assert!(si.contains("eccentricity 0.0254 mm,"), "{si}");
    let mut texts = vec![("montecarlo", inch, si)];

    // --- design spring: the rate, the preload, the spring's weight, the bracket and
    // every rate tried.
    let ds = ["design", "spring", "--actual", "--quick"];
    let (inch, si) = (study_text(&ds, Units::Inch), study_text(&ds, Units::Si));
    let lines = |t: &str| -> Vec<Vec<String>> { t.lines().take(6).map(numbers).collect() };
    let (li, ls) = (lines(&inch), lines(&si));
    // camsim design spring: K at preload length L (preload F; coils, weight, surge).
    let k = LBF_N / IN_MM;
    let lb_kg = 0.453_592_37;
    let head = [k, IN_MM, LBF_N, 1.0, lb_kg, 1.0];
    assert_eq!((li[0].len(), ls[0].len()), (6, 6), "{inch}{si}");
    for (f, (x, y)) in head.iter().zip(li[0].iter().zip(&ls[0])) {
        agrees(x, y, *f, "design spring's answer");
    }
    assert!(
        ls[0].len() == 6 && si.contains(" N/mm at preload length 12.7 mm"),
        "{si}"
    );
    // bracket: fails at K, passes at K (width K).
    assert!(inch.lines().nth(1).unwrap().contains("bracket"), "{inch}");
    assert_eq!(li[1].len(), 3);
    for (x, y) in li[1].iter().zip(&ls[1]) {
        agrees(x, y, k, "design spring's bracket");
    }
    let tried = |t: &str| numbers(t.lines().find(|l| l.contains("rates tried")).unwrap());
    let (ti, ts) = (tried(&inch), tried(&si));
    assert!(ti.len() >= 4 && ti.len() == ts.len(), "{inch}{si}");
    for (x, y) in ti.iter().zip(&ts) {
        agrees(x, y, k, "a rate tried");
    }
    texts.push(("design spring", inch, si));

    // --- no inch unit left in the SI text of the five studies; the check fires on
    // their inch text.
    for argv in [
        &["compare", "--quick"][..],
        &["tolerance-study", "--quick"],
        &["sensitivity", "--quick"],
        &[
            "design",
            "tolerance",
            "--quick",
            "--samples",
            "4",
            "--p-max",
            "0.6",
        ],
    ] {
        texts.push((
            argv[0],
            study_text(argv, Units::Inch),
            study_text(argv, Units::Si),
        ));
    }
    for (name, inch, si) in &texts {
        assert_eq!(inch_label(si), None, "{name}");
        assert!(inch_label(inch).is_some(), "{name}: the check cannot fail");
    }

    // --- --allowable-stress reads MPa with --units si, psi with inch; the note speaks
    // the family's units.
    let verdict = |units: Units, extra: &[&str]| -> String {
        units::set(units);
        let mut argv = vec!["camsim", "run", "--revolutions", "1"];
        argv.extend_from_slice(extra);
        let Command::Run(a) = cli::parse_from(argv).unwrap().command else {
            panic!("not run")
        };
        let text = run::report(&a).unwrap().text();
        units::set(Units::Inch);
        text.lines()
            .find(|l| l.contains("of the allowable"))
            .unwrap()
            .to_string()
    };
    let si = verdict(Units::Si, &["--allowable-stress", "1000"]);
    // 1000 MPa in psi, from the definitions.
    let psi = format!("{:.0}", 1000.0 / PSI_MPA);
    let inch = verdict(Units::Inch, &["--allowable-stress", &psi]);
    assert!(
        si.contains("of the allowable 1000.00 MPa (--allowable-stress)"),
        "{si}"
    );
    assert!(
        inch.contains(&format!("of the allowable {psi} psi (--allowable-stress)")),
        "{inch}"
    );
    // The same allowable: the same percentage of it.
    let pct = |l: &str| {
        l.split(": ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .to_string()
    };
    assert_eq!(pct(&si), pct(&inch), "{si}\n{inch}");
    let note = verdict(Units::Si, &[]);
    assert!(note.contains("S_C = 2.76 H_B - 70 MPa"), "{note}");
    assert!(note.contains("--allowable-stress MPA"), "{note}");
    // The scene key's other family may be named (`(or _psi)`), no psi value or option.
    assert!(
        !note.contains(" psi") && !note.contains("kpsi") && !note.contains("PSI"),
        "{note}"
    );
    let note = verdict(Units::Inch, &[]);
    assert!(note.contains("S_C = 0.4 H_B - 10 kpsi") && note.contains("--allowable-stress PSI"));
}
