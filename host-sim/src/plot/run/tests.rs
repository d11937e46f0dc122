//! The run's figures: their files, their SI values, the PNGs written and the errors.

use std::path::Path;

use anyhow::Result;
use camsim_core::JumpInterval;

use super::*;
use crate::output::Plan;
use crate::plot::axis::AngleAxis;
use crate::plot::{FOLLOWER_PLOT_SIZE, PLOT_SIZE};

/// What `camsim run --plot DIR --force` does with the plots.
fn write_all(dir: &Path, data: &PlotData, jumps: &[JumpInterval<f64>]) -> Result<()> {
    let mut out = Plan::new(true).dir("--plot", dir, &FILES)?.open()?;
    draw_all(&mut out, data, jumps, Units::Inch)?;
    out.commit().map(|_| ())
}

#[test]
fn the_declared_files_are_the_figures() {
    let d = PlotData::default();
    let files: Vec<&str> = figures(&d, &AngleAxis::new(&d, &[]))
        .iter()
        .map(|f| f.0)
        .collect();
    assert_eq!(files, FILES);
}

#[test]
fn si_series_are_the_inch_series_times_the_definition_and_titles_name_si() {
    use crate::units::Units;
    let d = synthetic();
    let axis = AngleAxis::new(&d, &[]);
    let in_units = |u| -> Vec<RunFigure> {
        figures(&d, &axis)
            .into_iter()
            .map(|(f, fig)| (f, fig.in_units(u)))
            .collect()
    };
    let (inch, si) = (in_units(Units::Inch), in_units(Units::Si));
    // 1 in = 25.4 mm; 1 lbf = 0.45359237 kg x 9.80665 m/s^2; 1 psi = 1 lbf/in^2;
    // 1 lb in = 1 lbf x 0.0254 m.
    let lbf = 0.453_592_37 * 9.806_65;
    let expect = [
        ("displacement.png", 25.4, "mm"),
        ("velocity.png", 25.4, "mm/s"),
        ("acceleration.png", 25.4, "mm/s²"),
        ("pressure_angle.png", 1.0, "deg"),
        ("contact_force.png", lbf, "(N)"),
        ("contact_stress.png", lbf / (25.4 * 25.4), "MPa"),
        ("torque.png", lbf * 0.0254, "N·m"),
    ];
    for (file, factor, unit) in expect {
        let find = |figs: &[RunFigure]| {
            figs.iter()
                .position(|f| f.0 == file)
                .unwrap_or_else(|| panic!("{file} missing"))
        };
        let (fi, fs) = (&inch[find(&inch)].1, &si[find(&si)].1);
        assert!(
            fs.panels[0].y.label().contains(unit),
            "{file}: {}",
            fs.panels[0].y.label()
        );
        for (pi, ps) in fi.panels.iter().zip(&fs.panels) {
            for (ci, cs) in pi.series.iter().zip(&ps.series) {
                let values = |s: &Series| -> Vec<f64> { s.points.iter().map(|p| p.1).collect() };
                let (ci, cs) = (Curve { values: values(ci) }, Curve { values: values(cs) });
                assert!(!ci.values.is_empty());
                // Relative to the series' scale (a deviation is a difference of
                // scaled values: its rounding is of their size).
                let big = ci.values.iter().fold(0.0f64, |m, v| m.max(v.abs())) * factor;
                for (a, b) in ci.values.iter().zip(&cs.values) {
                    assert!(
                        (b - a * factor).abs() <= 1e-12 * big,
                        "{file}: {b} vs {a} x {factor}"
                    );
                }
            }
        }
    }
    assert!(inch[0].1.panels[0].y.label().contains("(in)"));
    assert!(inch[7].1.panels[0].y.label().contains("lb·in"));
}

/// A curve's values.
struct Curve {
    values: Vec<f64>,
}

/// A synthetic two-revolution run: a cycloidal-like rise and return with a small
/// vibration on top of the theoretical curves, sampled every 0.05 degrees.
pub(in crate::plot) fn synthetic() -> PlotData {
    let mut d = PlotData::default();
    let n = 14_400;
    for i in 0..n {
        let deg = 720.0 * i as f64 / n as f64;
        let th = deg.to_radians();
        let yt = 0.5 * (1.0 - th.cos());
        let vt = 0.5 * th.sin() * 80.0;
        let at = 0.5 * th.cos() * 6400.0;
        let wob = (th * 40.0).sin();
        d.angle_deg.push(deg);
        d.y.push(yt + 0.01 * wob);
        d.y_theory.push(yt);
        d.v.push(vt + 2.0 * wob);
        d.v_theory.push(vt);
        d.a.push(at + 300.0 * wob);
        d.a_theory.push(at);
        d.pressure_angle_deg.push(25.0 * th.sin());
        d.omega_m.push(83.8 + 0.2 * wob);
        d.omega_cp.push(83.8 + 0.3 * wob);
        d.omega_c.push(83.8 + 0.5 * wob);
        d.contact_force.push(100.0 + 50.0 * th.cos());
        d.contact_stress.push(80_000.0 + 20_000.0 * th.cos());
        d.torque_out.push(40.0 * th.sin());
        d.torque_drive.push(40.0 * th.sin() + 5.0 * wob);
        d.in_contact.push(true);
    }
    d.period_starts_deg = vec![90.0, 180.0, 270.0, 360.0, 450.0, 540.0, 630.0];
    d
}

fn tmp_dir(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("camsim-plot-{}-{name}", std::process::id()))
}

/// Width and height from a PNG's signature and IHDR chunk.
fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    const SIG: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.get(..8)? != SIG || bytes.get(12..16)? != b"IHDR" {
        return None;
    }
    let w = u32::from_be_bytes(bytes.get(16..20)?.try_into().ok()?);
    let h = u32::from_be_bytes(bytes.get(20..24)?.try_into().ok()?);
    Some((w, h))
}

#[test]
fn writes_every_plot_as_png_of_the_expected_size() {
    let dir = tmp_dir("all").join("nested");
    let _ = std::fs::remove_dir_all(&dir);
    // DIR may be new, its parent must exist (the output plan checks it).
    std::fs::create_dir_all(tmp_dir("all")).unwrap();
    let d = synthetic();
    let jumps = [JumpInterval {
        revolution: 2,
        start_deg: 100.0,
        end_deg: 130.0,
    }];
    write_all(&dir, &d, &jumps).unwrap();
    let expected = [
        ("displacement.png", FOLLOWER_PLOT_SIZE),
        ("velocity.png", FOLLOWER_PLOT_SIZE),
        ("acceleration.png", FOLLOWER_PLOT_SIZE),
        ("pressure_angle.png", PLOT_SIZE),
        ("angular_velocity.png", PLOT_SIZE),
        ("contact_force.png", PLOT_SIZE),
        ("contact_stress.png", PLOT_SIZE),
        ("torque.png", PLOT_SIZE),
    ];
    for (file, size) in expected {
        let bytes = std::fs::read(dir.join(file)).unwrap();
        assert_eq!(png_size(&bytes), Some(size), "{file}");
        assert!(
            bytes.len() > 10_000,
            "{file} is suspiciously small: {} bytes",
            bytes.len()
        );
    }
    let n = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(n, expected.len());
    std::fs::remove_dir_all(tmp_dir("all")).unwrap();
}

#[test]
fn errors_name_the_path() {
    // A regular file where the directory should be.
    let base = tmp_dir("err");
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base).unwrap();
    let file = base.join("not_a_dir");
    std::fs::write(&file, b"x").unwrap();
    let e = write_all(&file.join("sub"), &synthetic(), &[]).unwrap_err();
    assert!(format!("{e:#}").contains("not_a_dir"), "{e:#}");
    // A directory where a plot file should be.
    let dir = base.join("out");
    std::fs::create_dir_all(dir.join("velocity.png")).unwrap();
    let e = write_all(&dir, &synthetic(), &[]).unwrap_err();
    assert!(format!("{e:#}").contains("velocity.png"), "{e:#}");
    std::fs::remove_dir_all(&base).unwrap();
}

/// A run without samples has nothing to draw: the plots are refused with an error
/// naming the file and the empty panel, and no file is left behind.
#[test]
fn empty_data_is_refused_naming_the_plot() {
    let dir = tmp_dir("empty");
    let _ = std::fs::remove_dir_all(&dir);
    let e = write_all(&dir, &PlotData::default(), &[]).unwrap_err();
    let msg = format!("{e:#}");
    assert!(
        msg.contains("displacement.png") && msg.contains("has no finite value"),
        "{msg}"
    );
    assert!(!dir.join("displacement.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
