//! `camsim profile`: the exported cam reads back as the cam it came from.
//!
//! Round trip: the surface's polar-radius CSV, read by `camsim run --measured`, is the
//! theoretical cam within the chordal error. The error measure is the largest |lift
//! deviation| of the read-back cam from the program over one revolution (the measured
//! profile's `max_abs_deviation_in`: the roller's exact envelope on the spline through
//! the exported points, 3600 knots), and the bound is `--chord-error`: the exported
//! points lie on the surface, and the chords between them stay within the bound, so a
//! roller on the polygon would read the lift within it; the spline through the points
//! is closer still. The run on the read-back cam then gives every period's RMS
//! displacement within the same bound of the theoretical run's.

use std::path::{Path, PathBuf};

use camsim::cli::{parse_from, Command};
use camsim::cmd::profile::{self, ProfileReport};
use camsim::export::read_dxf;
use camsim::measured::MeasuredProfile;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("camsim-profile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn export(args: &[&str]) -> ProfileReport {
    let mut argv = vec!["camsim", "profile"];
    argv.extend_from_slice(args);
    let cli = parse_from(argv).unwrap();
    let units = cli.units;
    let Command::Profile(a) = cli.command else {
        panic!("not profile")
    };
    // As the binary does: the drawing's length unit is the global --units.
    profile::report(&a, units).unwrap()
}

/// The largest |lift deviation| of the exported surface read back on the reference.
fn read_back(out: &Path) -> (f64, f64) {
    let m = camsim::measured::load(&out.join(profile::SURFACE_RADIUS_FILE)).unwrap();
    let (_, stats) = m.profile(&camsim_core::Design::<f64>::reference()).unwrap();
    (stats.max_abs_deviation_in, stats.rms_deviation_in)
}

#[test]
fn the_exported_surface_reads_back_within_the_chordal_error() {
    let mut last = f64::INFINITY;
    for bound in [1e-3, 1e-4, 1e-5] {
        let out = dir(&format!("rt{bound:e}"));
        let b = format!("{bound}");
        let r = export(&["--out", out.to_str().unwrap(), "--chord-error", &b]);
        // The sampling kept its bound on every curve (measured independently).
        for c in &r.curves {
            assert!(c.max_chord_error <= bound, "{c:?}");
            assert!(c.max_chord_error > bound / 8.0, "needlessly fine: {c:?}");
        }
        let (max_dev, _) = read_back(&out);
        assert!(max_dev <= bound, "{bound}: {max_dev}");
        // A finer drawing reads back closer.
        assert!(max_dev < last, "{bound}: {max_dev} after {last}");
        last = max_dev;
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn the_read_back_run_is_the_theoretical_run_within_the_chordal_error() {
    let bound = 1e-4;
    let out = dir("run");
    export(&["--out", out.to_str().unwrap()]);
    let run = |extra: &[&str]| {
        let mut argv = vec!["camsim", "run", "--revolutions", "2"];
        argv.extend_from_slice(extra);
        let Command::Run(a) = parse_from(argv).unwrap().command else {
            panic!("not run")
        };
        camsim::cmd::run::report(&a, camsim::units::Units::Inch).unwrap()
    };
    let theory = run(&[]);
    let file = out.join(profile::SURFACE_RADIUS_FILE);
    let measured = run(&["--measured", file.to_str().unwrap()]);
    assert_eq!(theory.per_period.len(), measured.per_period.len());
    for (t, m) in theory.per_period.iter().zip(&measured.per_period) {
        let d = (t.rms_displacement.in_inch() - m.rms_displacement.in_inch()).abs();
        assert!(d <= bound, "{} {}: {d}", t.revolution, t.period);
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn an_exported_actual_cam_reads_back_as_that_cam() {
    let bound = 1e-4;
    let out = dir("actual");
    let r = export(&["--actual", "--seed", "3", "--out", out.to_str().unwrap()]);
    let a = r.actual.unwrap();
    let (max_dev, rms) = read_back(&out);
    // The machined cam's own deviation (tenths of a thou), read back within the bound.
    assert!(a.max_abs_deviation_in.in_inch() > 2.0 * bound, "{a:?}");
    assert!((max_dev - a.max_abs_deviation_in.in_inch()).abs() <= bound);
    assert!((rms - a.rms_deviation_in.in_inch()).abs() <= bound);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn the_dxf_holds_the_csv_curves_closed_with_units() {
    let out = dir("dxf");
    let r = export(&[
        "--out",
        out.to_str().unwrap(),
        "--units",
        "mm",
        "--cutter-radius",
        "12.7mm",
    ]);
    let s = read_dxf(&std::fs::read_to_string(out.join(profile::DXF_FILE)).unwrap()).unwrap();
    assert_eq!(s.insunits, Some(4));
    assert!(s.eof);
    // Surface, pitch, cutter, the centre point and the note's three TEXT lines.
    assert_eq!(s.entities, 7);
    let names: Vec<&str> = s.polylines.iter().map(|p| p.0.as_str()).collect();
    assert_eq!(names, ["SURFACE", "PITCH", "CUTTER"]);
    for (p, c) in s.polylines.iter().zip(&r.curves) {
        assert!(p.1, "{} not closed", p.0);
        assert_eq!(p.2.len(), c.points);
    }
    // The surface in mm: the base circle's 38.1 mm radius at cam angle 0 (a dwell).
    let (x, y) = s.polylines[0].2[0];
    assert!((x.hypot(y) - 38.1).abs() < 1e-9, "{x} {y}");
    // The cutter's centre is r_c - r_r = 3.175 mm outside the pitch curve there.
    let (x, y) = s.polylines[2].2[0];
    assert!(
        (x.hypot(y) - (38.1 + 9.525 + 3.175)).abs() < 1e-9,
        "{x} {y}"
    );
    // The CSV has the same points.
    let csv = std::fs::read_to_string(out.join(profile::SURFACE_FILE)).unwrap();
    let rows: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(rows[0], "cam_angle_deg,x_mm,y_mm,polar_angle_deg,radius_mm");
    assert_eq!(rows.len() - 1, r.curves[0].points);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_too_fine_chord_error_is_refused_by_name() {
    let Command::Profile(a) = parse_from(["camsim", "profile", "--chord-error", "1e-12"])
        .unwrap()
        .command
    else {
        panic!()
    };
    let e = profile::report(&a, camsim::units::Units::Inch)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("--chord-error 1e-12: needs more than 3600 points"),
        "{e}"
    );
}

/// The `#` lines of a file (or the DXF's TEXT values) hold the unit, the rotation
/// direction and the 0° datum: each of the three convention lines, verbatim.
fn has_conventions(text: &str, unit: &str) {
    for line in profile::conventions(if unit == "mm" {
        camsim::export::Units::Mm
    } else {
        camsim::export::Units::In
    }) {
        assert!(text.contains(&line), "{line:?} missing");
    }
    assert!(text.contains(&format!("({unit})")), "no unit {unit}");
    assert!(text.contains("counterclockwise") && text.contains("0 deg datum"));
}

#[test]
fn every_file_states_units_rotation_and_datum_and_headers_name_the_unit() {
    for (units, u) in [("si", "mm"), ("inch", "in")] {
        let out = dir(&format!("notes-{u}"));
        export(&[
            "--out",
            out.to_str().unwrap(),
            "--units",
            units,
            "--cutter-radius",
            "0.5",
        ]);
        for (file, header) in [
            (
                profile::SURFACE_RADIUS_FILE,
                format!("angle_deg,radius_{u}"),
            ),
            (
                profile::SURFACE_FILE,
                format!("cam_angle_deg,x_{u},y_{u},polar_angle_deg,radius_{u}"),
            ),
            (profile::PITCH_FILE, format!("cam_angle_deg,x_{u},y_{u}")),
            (profile::CUTTER_FILE, format!("cam_angle_deg,x_{u},y_{u}")),
        ] {
            let text = std::fs::read_to_string(out.join(file)).unwrap();
            let comments: String = text.lines().take_while(|l| l.starts_with('#')).collect();
            has_conventions(&comments, u);
            let first = text.lines().find(|l| !l.starts_with('#')).unwrap();
            assert_eq!(first, header, "{file}");
        }
        let dxf = std::fs::read_to_string(out.join(profile::DXF_FILE)).unwrap();
        let texts: String = dxf.lines().collect::<Vec<_>>().join("\n");
        assert!(dxf.contains("\nTEXT\n"));
        has_conventions(&texts, u);
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn an_si_surface_file_reads_back_as_the_inch_one_within_the_chordal_error() {
    let bound = 1e-4;
    let (si, inch) = (dir("si"), dir("inch"));
    export(&["--out", si.to_str().unwrap(), "--units", "si"]);
    export(&["--out", inch.to_str().unwrap(), "--units", "inch"]);
    let text = std::fs::read_to_string(si.join(profile::SURFACE_RADIUS_FILE)).unwrap();
    assert!(text.contains("\nangle_deg,radius_mm\n"));
    let (m_si, m_in) = (
        camsim::measured::load(&si.join(profile::SURFACE_RADIUS_FILE)).unwrap(),
        camsim::measured::load(&inch.join(profile::SURFACE_RADIUS_FILE)).unwrap(),
    );
    // The same points, in mm = 25.4 x in (each rounded to 10 decimals).
    assert_eq!(m_si.angles_deg.len(), m_in.angles_deg.len());
    let design = camsim_core::Design::<f64>::reference();
    let (lift_si, lift_in) = (
        m_si.deviation(&design).unwrap(),
        m_in.deviation(&design).unwrap(),
    );
    for k in 0..3600 {
        let th = (k as f64 * 0.1).to_radians();
        let d = (lift_si.deviation(th).y - lift_in.deviation(th).y).abs();
        assert!(d <= bound, "{k}: {d}");
    }
    let _ = (std::fs::remove_dir_all(&si), std::fs::remove_dir_all(&inch));
}

/// The data rows of a CSV (after its `#` lines and header), as numbers.
fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

/// `--every-deg D`: 360/D rows at k·D degrees. Each pitch.csv point lies at the roller
/// centre's radius R_prime + y(θ) (MODEL.md §1.2); each surface_radius.csv point is
/// where a roller on the pitch curve touches without cutting in (its least distance to
/// the pitch curve is the roller radius). Read back by `run --measured`, the cam is the
/// program's to the spline's fourth order: halving D divides the error by about 16
/// (asserted at least 8), and at 1° it is within the default chordal error.
#[test]
fn every_deg_writes_uniform_rows_that_read_back_at_fourth_order() {
    let design = camsim_core::Design::<f64>::reference();
    let g = design.geometry;
    let mut last = f64::INFINITY;
    for deg in [4.0, 2.0, 1.0] {
        let out = dir(&format!("every{deg}"));
        let r = export(&[
            "--out",
            out.to_str().unwrap(),
            "--every-deg",
            &format!("{deg}"),
        ]);
        assert_eq!(r.every_deg, Some(deg));
        let n = (360.0 / deg) as usize;
        let pitch = csv_rows(&out.join(profile::PITCH_FILE));
        let radius = csv_rows(&out.join(profile::SURFACE_RADIUS_FILE));
        assert_eq!((pitch.len(), radius.len()), (n, n));
        for (k, (p, s)) in pitch.iter().zip(&radius).enumerate() {
            let a = k as f64 * deg;
            assert!((p[0] - a).abs() < 1e-9 && (s[0] - a).abs() < 1e-9, "{k}");
            let y = design.program.follower(a.to_radians()).y;
            assert!(
                (p[1].hypot(p[2]) - (g.prime_radius() + y)).abs() < 1e-9,
                "{k}"
            );
            if deg == 4.0 {
                // The least distance from the surface point to the pitch curve.
                let q = (s[1] * a.to_radians().sin(), s[1] * a.to_radians().cos());
                let least = (-3000..=3000)
                    .map(|j| {
                        let t = (a + j as f64 * 0.01).to_radians();
                        let (x, y) = g.pitch_point(t, design.program.follower(t).y);
                        (x - q.0).hypot(y - q.1)
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!((least - g.roller_radius).abs() < 1e-6, "{k}: {least}");
            }
        }
        let (max_dev, _) = read_back(&out);
        assert!(max_dev * 8.0 < last, "{deg}: {max_dev} after {last}");
        last = max_dev;
        let _ = std::fs::remove_dir_all(&out);
    }
    assert!(last <= profile::DEFAULT_CHORD_ERROR_IN, "{last}");
}

#[test]
fn an_every_deg_that_does_not_divide_360_into_4_to_3600_steps_is_refused_by_name() {
    for (d, rule) in [
        ("7", "must divide 360"),
        ("0.05", "into 4 to 3600 steps"),
        ("120", "into 4 to 3600 steps"),
        ("-1", "positive"),
        ("1mm", "not a number of degrees"),
    ] {
        let e = parse_from(["camsim", "profile", "--every-deg", d])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("'{d}' for '--every-deg <DEG>'")) && e.contains(rule),
            "{d}: {e}"
        );
    }
}
