//! `camsim laws`: peak dimensionless coefficients of every Appendix A motion law for a
//! unit rise over a unit angle, and the largest pressure angle each gives on the
//! reference cam (VI.1 geometry and timing, the law used for both rise and return).

use camsim_core::{CamGeometry, CamProgram, LawValue, MotionLaw, PeakScan, ScanEnds};
use serde::Serialize;

use crate::figure::{palette, Axis, Entry, Figure, Panel, Series, Strip, Stroke, Swatch, Ticks};
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

/// Every law's s, ds/du, d²s/du² and d³s/du³ over u in [0, 1] (a unit rise over a
/// unit angle), four panels, one colour a law, the legend in a strip of its own above.
pub fn figure() -> Figure {
    let us: Vec<f64> = (0..=PLOT_POINTS)
        .map(|k| k as f64 / PLOT_POINTS as f64)
        .collect();
    type Pick = fn(&LawValue<f64>) -> f64;
    let quantities: [(&str, Pick); 4] = [
        ("S: lift s (fraction of the rise)", |x| x.s),
        ("V: ds/du", |x| x.v),
        ("A: d²s/du²", |x| x.a),
        ("J: d³s/du³", |x| x.j),
    ];
    let colour = |k: usize| palette::SERIES.get(k).copied().unwrap_or(palette::BLACK);
    let panels = quantities
        .iter()
        .enumerate()
        .map(|(p, (title, pick))| {
            let last = p + 1 == quantities.len();
            let x = Axis::plain(
                if last {
                    "u = θ/β (fraction of the rise angle)"
                } else {
                    ""
                },
                "",
            );
            let mut y = Axis::plain(title, "");
            y.zero = true;
            let mut panel = Panel::new(x.range(0.0, 1.0).ticks(Ticks::Auto(10)), y);
            for (k, law) in MotionLaw::ALL.iter().enumerate() {
                let points = us.iter().map(|&u| (u, pick(&law.eval(u)))).collect();
                panel
                    .series
                    .push(Series::line(None, points, Stroke::solid(colour(k), 2)));
            }
            panel
        })
        .collect();
    let title = "Motion laws (Appendix A), normalized: a unit rise over a unit angle, u = θ/β";
    let mut fig = Figure::new(title, PLOT_SIZE, panels);
    fig.strip = Strip {
        entries: MotionLaw::ALL
            .iter()
            .enumerate()
            .map(|(k, law)| Entry {
                swatch: Swatch::Line(Stroke::solid(colour(k), 3), None),
                text: law.name().to_string(),
            })
            .collect(),
        columns: 4,
        note: Some("Not drawn: the impulses at a velocity or acceleration jump (straight-line at its ends, parabolic and cubic-1 at mid-stroke).".into()),
    };
    fig
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

    fn text(&self, _units: crate::units::Units) -> String {
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
pub fn run(args: Args, units: crate::units::Units) -> anyhow::Result<()> {
    if let Some(d) = &args.output.plot {
        let mut plan = crate::output::Plan::new(args.output.force);
        let mut dir = plan.dir("--plot", d, &PLOT_FILES)?.open()?;
        crate::figure::draw(&mut dir, PLOT_FILES[0], &figure(), crate::units::current())?;
        dir.commit()?;
    }
    crate::report::print(&report(), args.output.json, units)
}
