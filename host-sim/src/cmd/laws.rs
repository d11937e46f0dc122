//! `camsim laws`: peak dimensionless coefficients of every Appendix A motion law for a
//! unit rise over a unit angle, and the largest pressure angle each gives on the
//! reference cam (VI.1 geometry and timing, the law used for both rise and return).

use camsim_core::{CamGeometry, CamProgram, LawValue, MotionLaw, PeakScan, ScanEnds};
use serde::Serialize;

use crate::report::Report;

/// Command-line options.
#[derive(clap::Args, Debug)]
#[command(mut_arg("json", |a| a.help("Print JSON instead of a table")))]
#[command(mut_arg("plot", |a| a.help("Draw every law's normalized S, V, A and J against u = θ/β on one figure (laws.png) into DIR (created if missing; its parent must exist)")))]
#[command(mut_arg("force", |a| a.help("Replace an existing --plot file")))]
pub struct Args {
    /// What it prints and draws.
    #[command(flatten)]
    pub output: crate::args::OutputArgs,
}

/// The plot `--plot DIR` writes.
pub const PLOT_FILES: [&str; 1] = ["laws.png"];

/// Size of the laws plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1200, 1600);

/// Points of each curve over u in [0, 1].
const PLOT_POINTS: usize = 2000;

/// One colour a law (Tableau's 10 and two more), in the order of [`MotionLaw::ALL`].
const LAW_COLORS: [plotters::style::RGBColor; 12] = [
    plotters::style::RGBColor(31, 119, 180),
    plotters::style::RGBColor(255, 127, 14),
    plotters::style::RGBColor(44, 160, 44),
    plotters::style::RGBColor(214, 39, 40),
    plotters::style::RGBColor(148, 103, 189),
    plotters::style::RGBColor(140, 86, 75),
    plotters::style::RGBColor(227, 119, 194),
    plotters::style::RGBColor(127, 127, 127),
    plotters::style::RGBColor(188, 189, 34),
    plotters::style::RGBColor(23, 190, 207),
    plotters::style::RGBColor(0, 0, 0),
    plotters::style::RGBColor(255, 187, 120),
];

/// Draws every law's s, ds/du, d²s/du² and d³s/du³ over u in [0, 1] (a unit rise over a
/// unit angle), four panels, one colour a law, the legend in a strip of its own above.
pub fn draw(dir: &mut crate::output::AtomicDir, file: &str) -> anyhow::Result<()> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("cannot draw plot {file}: {e}");
    let us: Vec<f64> = (0..=PLOT_POINTS)
        .map(|k| k as f64 / PLOT_POINTS as f64)
        .collect();
    type Pick = fn(&LawValue<f64>) -> f64;
    let panels: [(&str, Pick); 4] = [
        ("S: lift s (fraction of the rise)", |x| x.s),
        ("V: ds/du", |x| x.v),
        ("A: d²s/du²", |x| x.a),
        ("J: d³s/du³", |x| x.j),
    ];
    crate::plot::study::png(dir, file, PLOT_SIZE, |root| {
        let (title, rest) = root.split_vertically(50);
        crate::plot::draw_title(
            &title,
            "Motion laws (Appendix A), normalized: a unit rise over a unit angle, u = θ/β",
            24,
            14,
        )
        .map_err(|e| err(&e))?;
        let (legend, body) = rest.split_vertically(125);
        legend
            .draw(&Text::new(
                "Not drawn: the impulses at a velocity or acceleration jump (straight-line at its ends, parabolic and cubic-1 at mid-stroke).",
                (110, 96),
                (crate::plot::FONT, 15).into_font().color(&RGBColor(90, 90, 90)),
            ))
            .map_err(|e| err(&e))?;
        for (k, law) in MotionLaw::ALL.iter().enumerate() {
            let color = LAW_COLORS.get(k).copied().unwrap_or(BLACK);
            let x = 110 + (k % 4) as i32 * 270;
            let y = 12 + (k / 4) as i32 * 28;
            legend
                .draw(&PathElement::new(
                    vec![(x, y + 9), (x + 30, y + 9)],
                    color.stroke_width(3),
                ))
                .map_err(|e| err(&e))?;
            legend
                .draw(&Text::new(
                    law.name(),
                    (x + 38, y),
                    (crate::plot::FONT, 17).into_font().color(&BLACK),
                ))
                .map_err(|e| err(&e))?;
        }
        let areas = body.split_evenly((panels.len(), 1));
        let last = panels.len() - 1;
        for (p, ((desc, pick), area)) in panels.iter().zip(areas.iter()).enumerate() {
            let curves: Vec<Vec<(f64, f64)>> = MotionLaw::ALL
                .iter()
                .map(|law| us.iter().map(|&u| (u, pick(&law.eval(u)))).collect())
                .collect();
            let (lo, hi) = curves
                .iter()
                .flatten()
                .map(|p| p.1)
                .filter(|v| v.is_finite())
                .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
            let pad = 0.05 * (hi - lo).max(1e-9);
            let (y0, y1) = (lo - pad, hi + pad);
            let mut chart = ChartBuilder::on(area)
                .margin_left(10)
                .margin_right(25)
                .margin_top(8)
                .margin_bottom(4)
                .x_label_area_size(if p == last { 55 } else { 30 })
                .y_label_area_size(90)
                .build_cartesian_2d(0.0..1.0, y0..y1)
                .map_err(|e| err(&e))?;
            let yfmt = |v: &f64| crate::plot::fmt_tick(*v, y1 - y0);
            let xfmt = |v: &f64| format!("{v:.1}");
            let mut mesh = chart.configure_mesh();
            mesh.y_desc(*desc)
                .y_labels(8)
                .x_labels(11)
                .x_label_formatter(&xfmt)
                .y_label_formatter(&yfmt)
                .label_style((crate::plot::FONT, 16))
                .axis_desc_style((crate::plot::FONT, 18))
                .bold_line_style(RGBColor(215, 215, 215))
                .light_line_style(RGBColor(240, 240, 240));
            if p == last {
                mesh.x_desc("u = θ/β (fraction of the rise angle)");
            }
            mesh.draw().map_err(|e| err(&e))?;
            for (k, c) in curves.into_iter().enumerate() {
                let color = LAW_COLORS.get(k).copied().unwrap_or(BLACK);
                chart
                    .draw_series(LineSeries::new(c, color.stroke_width(2)))
                    .map_err(|e| err(&e))?;
            }
        }
        Ok(())
    })
}

/// One law's peak coefficients (unit rise over a unit angle) and reference-cam pressure angle.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LawRow {
    /// The law's name ([`MotionLaw::name`]).
    pub name: &'static str,
    /// Largest velocity coefficient, max ds/du.
    pub cv: f64,
    /// Largest acceleration coefficient, max d²s/du².
    pub ca_max: f64,
    /// Smallest acceleration coefficient, min d²s/du².
    pub ca_min: f64,
    /// Largest jerk coefficient, max d³s/du³ (impulses at jumps excluded).
    pub cj_max: f64,
    /// Smallest jerk coefficient, min d³s/du³ (impulses at jumps excluded).
    pub cj_min: f64,
    /// Largest pressure angle on the reference cam with this law for rise and return (deg).
    pub pressure_angle_max_deg: f64,
}

/// Grid intervals per unit of `u` (a power of two, a multiple of 8 so every junction is a
/// grid point).
const GRID: usize = 8 * 4096;
/// Cam-angle samples for the pressure-angle scan (before refinement).
const PHI_SAMPLES: usize = 36_000;

/// Supremum of `f(law(u))` over `[0, 1]`: dense grid, then golden section between the
/// best point's neighbours ([`PeakScan`]), keeping the best value seen (so a one-sided
/// limit at an acceleration jump is approached, and a maximum at a junction is kept).
fn sup(law: MotionLaw, f: impl Fn(LawValue<f64>) -> f64) -> f64 {
    let scan = PeakScan {
        start: 0.0,
        // Exact: GRID is a power of two, so the grid points are exactly k / GRID.
        step: 1.0 / GRID as f64,
        points: GRID + 1,
        ends: ScanEnds::Clamped,
        iterations: 100,
    };
    scan.maximize(|u| f(law.eval(u)))
        .map_or(f64::NEG_INFINITY, |p| p.value)
}

/// The table `camsim laws` prints, one row per law in the order of [`MotionLaw::ALL`].
pub fn table() -> Vec<LawRow> {
    let geometry = CamGeometry::<f64>::reference();
    MotionLaw::ALL
        .iter()
        .map(|&law| {
            let program = CamProgram::<f64>::with_laws(law, law);
            let (phi, _) = geometry.max_pressure_angle(&program, PHI_SAMPLES);
            // `+ 0.0` turns a -0 (a maximum of -sin at u = 0) into 0.
            LawRow {
                name: law.name(),
                cv: sup(law, |x| x.v) + 0.0,
                ca_max: sup(law, |x| x.a) + 0.0,
                ca_min: -sup(law, |x| -x.a) + 0.0,
                cj_max: sup(law, |x| x.j) + 0.0,
                cj_min: -sup(law, |x| -x.j) + 0.0,
                pressure_angle_max_deg: phi.to_degrees(),
            }
        })
        .collect()
}

/// Everything `camsim laws` prints: `{"laws":[{"name":..,"cv":..,..}, ..]}` with
/// `--json` (compact, keys in field order), the table without.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct LawsReport {
    /// One row per law, in the order of [`MotionLaw::ALL`].
    pub laws: Vec<LawRow>,
}

/// Computes the report.
pub fn report() -> LawsReport {
    LawsReport { laws: table() }
}

impl Report for LawsReport {
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }

    fn text(&self) -> String {
        use std::fmt::Write;
        let rows = &self.laws;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Motion laws (Appendix A): peak coefficients for a unit rise over a unit angle,"
        );
        let _ = writeln!(
            s,
            "y = h s(theta/beta): dy/dtheta = cv h/beta, d2y/dtheta2 = ca h/beta^2, d3y/dtheta3 = cj h/beta^3."
        );
        let l = |x: f64| crate::units::given(crate::units::LENGTH, x);
        let _ = writeln!(
            s,
            "phi_max: largest pressure angle on the reference cam (R_b {} {u}, r_r {} {u}, lift {} {u},",
            l(1.5),
            l(0.375),
            l(1.5),
            u = crate::units::symbol(crate::units::LENGTH)
        );
        let _ = writeln!(
            s,
            "rise 30-180 deg and return 210-360 deg both with the law)."
        );
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "{:<22}{:>9}{:>10}{:>10}{:>11}{:>11}{:>13}",
            "law", "cv", "ca_max", "ca_min", "cj_max", "cj_min", "phi_max_deg"
        );
        for r in rows {
            let _ = writeln!(
                s,
                "{:<22}{:>9.4}{:>10.4}{:>10.4}{:>11.4}{:>11.4}{:>13.3}",
                r.name, r.cv, r.ca_max, r.ca_min, r.cj_max, r.cj_min, r.pressure_angle_max_deg
            );
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Only finite values inside the stroke are listed: the impulses at a velocity or acceleration"
        );
        let _ = writeln!(
            s,
            "jump (straight-line at its ends, parabolic and cubic-1 at mid-stroke, and any law whose"
        );
        let _ = writeln!(
            s,
            "end acceleration is not 0 against a dwell) are not representable and are excluded."
        );
        s
    }
}

/// Runs the command.
pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(d) = &args.output.plot {
        let mut plan = crate::output::Plan::new(args.output.force);
        let mut dir = plan.dir("--plot", d, &PLOT_FILES)?.open()?;
        draw(&mut dir, PLOT_FILES[0])?;
        dir.commit()?;
    }
    crate::report::print(&report(), args.output.json)
}
