//! PNG plots of a run against cam angle (`camsim run --plot DIR`), after the thesis's
//! figures (chapter VI): the follower (load) displacement, velocity and acceleration,
//! each over its theoretical curve with the deviation below; the pressure angle; the
//! motor, coupling and cam angular velocities; the contact force and stress; and the
//! output and drive torques.
//!
//! The cam angle axis is continuous over the revolutions (0 to 360 per revolution, in
//! degrees) with the revolution boundaries marked, and every jump interval (the follower
//! off the cam, Eq. V.20) is shaded. Long series are decimated to the first, lowest,
//! highest and last point of each pixel column, so peaks survive. Text uses DejaVu Sans,
//! embedded in the binary (no system fonts needed).

use std::ops::Range;

use anyhow::{anyhow, Result};
use camsim_core::{JumpInterval, Sample};
use camsim_scene_file::units::Unit;

use crate::units::Units;

use crate::figure::palette::{BLUE, DARK_GREY, GREEN, LIGHT_GREY, LIGHT_RED, ORANGE, RED};
use crate::figure::{
    self, At, Axis, Band, Colour, Figure, Legend, Marker, Panel, Series, Shape, Ticks,
};
use crate::output::AtomicDir;
use crate::sim::HostDeviation;

pub mod charts;
pub mod compare;
pub mod montecarlo;
pub mod sensitivity;
pub mod sweep;
pub mod tolerance;

/// Writes an RGB buffer of `size` pixels as the PNG `file` into the directory output
/// `out` (to the file's temporary: the caller commits `out`). Every plot is saved here.
pub fn save_png(out: &mut AtomicDir, file: &str, rgb: &[u8], size: (u32, u32)) -> Result<()> {
    let path = out.path(file)?;
    image::save_buffer_with_format(
        &path,
        rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| anyhow!("cannot write plot {}: {e}", out.dir().join(file).display()))
}

/// Size of a single-panel plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1200, 600);
/// Size of a follower-output plot (curves over the theoretical, deviation below), pixels.
pub const FOLLOWER_PLOT_SIZE: (u32, u32) = (1200, 800);
/// Size of the SVAJ plot (four panels), pixels.
pub const SVAJ_PLOT_SIZE: (u32, u32) = (1200, 1400);

/// Colours: the simulated curve, the theoretical, the second and third curves; a jump's
/// shading and its opacity; a revolution's boundary; a period's start.
const SIMULATED: Colour = BLUE;
const THEORY: Colour = RED;
const SECOND: Colour = ORANGE;
const THIRD: Colour = GREEN;
const JUMP_FILL: Colour = LIGHT_RED;
const JUMP_ALPHA: f64 = 0.45;
const REV_LINE: Colour = DARK_GREY;
const PERIOD_LINE: Colour = LIGHT_GREY;

/// What the plots need from each sample of a run: one column per quantity, in the
/// units of the plots (angles in degrees).
#[derive(Clone, Debug, Default)]
pub struct PlotData {
    /// Continuous cam angle θ_c, degrees (360 per revolution from the start).
    pub angle_deg: Vec<f64>,
    /// Follower (load) displacement, in.
    pub y: Vec<f64>,
    /// Theoretical displacement, in.
    pub y_theory: Vec<f64>,
    /// Follower (load) velocity, in/s.
    pub v: Vec<f64>,
    /// Theoretical velocity, in/s.
    pub v_theory: Vec<f64>,
    /// Follower (load) acceleration, in/s².
    pub a: Vec<f64>,
    /// Theoretical acceleration, in/s².
    pub a_theory: Vec<f64>,
    /// Pressure angle φ, degrees.
    pub pressure_angle_deg: Vec<f64>,
    /// Motor speed θ̇_m, rad/s.
    pub omega_m: Vec<f64>,
    /// Coupling speed θ̇_cp, rad/s.
    pub omega_cp: Vec<f64>,
    /// Cam speed θ̇_c, rad/s.
    pub omega_c: Vec<f64>,
    /// Contact force F_c (Eq. V.19), lb.
    pub contact_force: Vec<f64>,
    /// Maximum Hertz contact stress, psi.
    pub contact_stress: Vec<f64>,
    /// Output torque on the cam T_o (Eq. IV.1), lb·in.
    pub torque_out: Vec<f64>,
    /// Torque delivered by the drive, lb·in.
    pub torque_drive: Vec<f64>,
    /// Whether the follower touches the cam (false while it jumps, Eq. V.20).
    pub in_contact: Vec<bool>,
    /// Continuous cam angles, degrees, where a new program period (segment) begins.
    pub period_starts_deg: Vec<f64>,
    last_period: Option<(u32, usize)>,
}

impl PlotData {
    /// Records one sample of a run.
    pub fn push(&mut self, s: &Sample<f64>) {
        let p = &s.point;
        let angle = p.theta_c.to_degrees();
        let period = (s.revolution, s.segment);
        if self.last_period.is_some_and(|q| q != period) {
            self.period_starts_deg.push(angle);
        }
        self.last_period = Some(period);
        self.angle_deg.push(angle);
        self.y.push(p.load_displacement());
        self.y_theory.push(s.theory.y);
        self.v.push(p.load_velocity());
        self.v_theory.push(s.theory.v);
        self.a.push(p.load_acceleration());
        self.a_theory.push(s.theory.a);
        self.pressure_angle_deg.push(p.pressure_angle.to_degrees());
        self.omega_m.push(p.omega_m);
        self.omega_cp.push(p.omega_cp);
        self.omega_c.push(p.omega_c);
        self.contact_force.push(p.contact_force);
        self.contact_stress.push(s.contact_stress);
        self.torque_out.push(p.torque_out);
        self.torque_drive.push(p.torque_drive);
        self.in_contact.push(p.in_contact);
    }

    /// The intervals (continuous cam angle, degrees) where the samples show the follower
    /// off the cam: from the first sample off contact to the first one back on (or the
    /// last sample).
    pub fn off_cam_intervals(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut start = None;
        let mut last = None;
        for (&x, &on) in self.angle_deg.iter().zip(&self.in_contact) {
            match (start, on) {
                (None, false) => start = Some(x),
                (Some(a), true) => {
                    out.push((a, x));
                    start = None;
                }
                _ => {}
            }
            last = Some(x);
        }
        if let (Some(a), Some(b)) = (start, last) {
            out.push((a, b));
        }
        out
    }

    /// Number of recorded samples.
    pub fn len(&self) -> usize {
        self.angle_deg.len()
    }

    /// Whether no sample was recorded.
    pub fn is_empty(&self) -> bool {
        self.angle_deg.is_empty()
    }
}

/// One run plot: its file and its figure.
type RunFigure = (&'static str, Figure);

/// The cam angle axis of a panel: its ticks at whole multiples of a degree step, light
/// lines halfway; labelled on the lowest panel only.
fn angle_axis(axis: &AngleAxis, labelled: bool) -> Axis {
    let minor = axis
        .ticks
        .windows(2)
        .flat_map(|w| match w {
            [a, b] => vec![*a, 0.5 * (a + b)],
            _ => Vec::new(),
        })
        .chain(axis.ticks.last().copied())
        .collect();
    let unit = if axis.run {
        "deg, continuous over revolutions"
    } else {
        "deg"
    };
    let mut x = Axis::plain("cam angle θ", unit)
        .range(axis.range.start, axis.range.end)
        .ticks(Ticks::At {
            major: axis.ticks.clone(),
            minor,
        });
    x.labelled = labelled;
    x
}

/// A panel against cam angle: `curves` over the jump intervals (shaded), the period
/// starts (dotted) and the revolution boundaries (dashed, labelled); the legend inside,
/// room kept for the jump entry even without jumps, so a jump never rescales the plot.
fn angle_panel(axis: &AngleAxis, y: Axis, curves: Vec<Series>, labelled: bool) -> Panel {
    let mut p = Panel::new(angle_axis(axis, labelled), y);
    p.legend = Legend::Inside {
        rows: curves.len() + 1,
    };
    for (k, &(a, b)) in axis.jumps.iter().enumerate() {
        p.bands.push(Band {
            label: (k == 0).then(|| "jump (follower off the cam)".to_string()),
            colour: JUMP_FILL,
            alpha: JUMP_ALPHA,
            shape: Shape::Span(a, b),
        });
    }
    let line = |x, stroke, text| Marker {
        at: At::X(x),
        stroke,
        text,
        label: None,
    };
    for &x in &axis.periods {
        p.markers
            .push(line(x, Some(figure::Stroke::dotted(PERIOD_LINE, 1)), None));
    }
    if axis.run {
        p.markers
            .push(line(axis.range.start, None, Some("rev 1".to_string())));
    }
    for (k, &x) in axis.revolutions.iter().enumerate() {
        let text = Some(format!("rev {}", k + 2));
        p.markers
            .push(line(x, Some(figure::Stroke::dashed(REV_LINE, 2)), text));
    }
    p.series = curves;
    p
}

/// A follower output figure: simulated over theoretical, and their difference below.
fn follower_figure(
    axis: &AngleAxis,
    xs: &[f64],
    (title, quantity, unit): (&str, &str, Unit),
    sim: &[f64],
    theory: &[f64],
) -> Figure {
    let dev: Vec<f64> = sim.iter().zip(theory).map(|(s, t)| s - t).collect();
    let curves = vec![
        Series::of("simulated", xs, sim, figure::Stroke::solid(SIMULATED, 2)),
        Series::of(
            "theoretical (rigid system at ω₀)",
            xs,
            theory,
            figure::Stroke::dashed(THEORY, 2),
        ),
    ];
    let deviation = vec![Series::of(
        "simulated − theoretical",
        xs,
        &dev,
        figure::Stroke::solid(SIMULATED, 1),
    )];
    let mut fig = Figure::new(
        title,
        FOLLOWER_PLOT_SIZE,
        vec![
            angle_panel(axis, Axis::of(quantity, unit), curves, false),
            angle_panel(axis, Axis::of("deviation", unit), deviation, true),
        ],
    );
    fig.row_weights = vec![3, 2];
    fig
}

/// A one-panel figure against cam angle.
fn single(axis: &AngleAxis, title: &str, y: Axis, curves: Vec<Series>) -> Figure {
    Figure::new(title, PLOT_SIZE, vec![angle_panel(axis, y, curves, true)])
}

/// Every figure `draw_all` writes, in order, with its file; the values in the inch
/// family, each axis naming its quantity.
fn figures(d: &PlotData, axis: &AngleAxis) -> Vec<RunFigure> {
    use crate::units::ACCELERATION;
    use camsim_scene_file::units::{LENGTH, SPEED};
    let xs = &d.angle_deg;
    let follower = |title, q: &str, u, sim: &[f64], th: &[f64]| {
        follower_figure(axis, xs, (title, q, u), sim, th)
    };
    let mut v = vec![
        (
            FILES[0],
            follower(
                "Follower (load) displacement",
                "displacement y",
                LENGTH,
                &d.y,
                &d.y_theory,
            ),
        ),
        (
            FILES[1],
            follower(
                "Follower (load) velocity",
                "velocity",
                SPEED,
                &d.v,
                &d.v_theory,
            ),
        ),
        (
            FILES[2],
            follower(
                "Follower (load) acceleration",
                "acceleration",
                ACCELERATION,
                &d.a,
                &d.a_theory,
            ),
        ),
    ];
    v.extend(FILES.iter().skip(3).copied().zip(drive_figures(d, axis)));
    v
}

/// The pressure angle, drive train, contact and torque figures, in [`FILES`]' order.
fn drive_figures(d: &PlotData, axis: &AngleAxis) -> Vec<Figure> {
    use crate::units::FORCE;
    use camsim_scene_file::units::{STRESS, TORQUE};
    let s = |label: &str, v: &[f64], c, w| {
        Series::of(label, &d.angle_deg, v, figure::Stroke::solid(c, w))
    };
    let one = |title, y, curves| single(axis, title, y, curves);
    vec![
        one(
            "Pressure angle φ",
            Axis::plain("pressure angle φ", "deg"),
            vec![s("φ", &d.pressure_angle_deg, SIMULATED, 2)],
        ),
        one(
            "Angular velocities of the drive train",
            Axis::plain("angular velocity", "rad/s"),
            vec![
                s("motor", &d.omega_m, SECOND, 4),
                s("coupling", &d.omega_cp, THIRD, 2),
                s("cam", &d.omega_c, SIMULATED, 1),
            ],
        ),
        one(
            "Cam-follower contact force F_c",
            Axis::of("contact force Fc", FORCE),
            vec![s("F_c", &d.contact_force, SIMULATED, 2)],
        ),
        one(
            "Maximum Hertz contact stress",
            Axis::of("contact stress", STRESS),
            vec![s("stress", &d.contact_stress, SIMULATED, 2)],
        ),
        one(
            "Cam torque",
            Axis::of("torque", TORQUE),
            vec![
                s("output torque T_o", &d.torque_out, SIMULATED, 2),
                s("drive torque", &d.torque_drive, SECOND, 2),
            ],
        ),
    ]
}

/// The cam angle axis shared by every plot: range, ticks, and the marks on it.
struct AngleAxis {
    range: Range<f64>,
    ticks: Vec<f64>,
    /// Revolution boundaries strictly inside the range, degrees.
    revolutions: Vec<f64>,
    /// Whether the axis is a run's (revolutions counted and labelled) rather than one
    /// revolution of the cam's shape (the SVAJ plot).
    run: bool,
    /// Jump intervals on the continuous axis, degrees.
    jumps: Vec<(f64, f64)>,
    /// Period starts (excluding revolution boundaries), degrees.
    periods: Vec<f64>,
}

impl AngleAxis {
    fn new(d: &PlotData, jumps: &[JumpInterval<f64>]) -> Self {
        let (lo, hi) = finite_bounds(d.angle_deg.iter().copied()).unwrap_or((0.0, 360.0));
        let start = (lo / 360.0).floor() * 360.0;
        let mut end = (hi / 360.0).ceil() * 360.0;
        if end <= start {
            end = start + 360.0;
        }
        let span = end - start;
        let step = [
            5.0, 10.0, 15.0, 30.0, 45.0, 60.0, 90.0, 180.0, 360.0, 720.0, 1440.0, 3600.0,
        ]
        .into_iter()
        .find(|s| span / s <= 16.0)
        .unwrap_or(span / 8.0);
        let ticks: Vec<f64> = (0..)
            .map(|k| start + step * f64::from(k))
            .take_while(|t| *t <= end + 1e-9)
            .collect();
        let revolutions: Vec<f64> = (1..)
            .map(|k| start + 360.0 * f64::from(k))
            .take_while(|r| *r < end - 1e-9)
            .collect();
        // The run's jump list (it may be truncated to its capacity) and the samples'
        // own contact flags, merged.
        let listed = jumps.iter().map(|j| {
            let base = (f64::from(j.revolution) - 1.0) * 360.0;
            (base + j.start_deg, base + j.end_deg)
        });
        let mut all: Vec<(f64, f64)> = listed
            .chain(d.off_cam_intervals())
            .filter_map(|(a, b)| {
                let (a, b) = (a.min(b).max(start), a.max(b).min(end));
                (a.is_finite() && b.is_finite() && b >= a).then_some((a, b))
            })
            .collect();
        all.sort_by(|p, q| p.0.total_cmp(&q.0));
        let jumps = merge_intervals(all, 0.0);
        let periods = d
            .period_starts_deg
            .iter()
            .copied()
            .filter(|p| p.is_finite() && *p > start && *p < end)
            .filter(|p| revolutions.iter().all(|r| (r - p).abs() > 0.5))
            .collect();
        Self {
            range: start..end,
            ticks,
            revolutions,
            run: true,
            jumps,
            periods,
        }
    }
}

/// Merges sorted intervals that overlap or are less than `gap` apart.
fn merge_intervals(sorted: Vec<(f64, f64)>, gap: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(sorted.len());
    for (a, b) in sorted {
        match out.last_mut() {
            Some(last) if a <= last.1 + gap => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

/// Smallest and largest finite value, if any.
fn finite_bounds(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    v.filter(|x| x.is_finite()).fold(None, |acc, x| match acc {
        None => Some((x, x)),
        Some((lo, hi)) => Some((lo.min(x), hi.max(x))),
    })
}

/// Reduces a polyline to at most four points per pixel column (first, lowest, highest,
/// last, in their original order), so the drawn line and its extremes are unchanged.
/// Non-finite points break the line: each returned run is a connected polyline.
pub fn decimate(
    xs: &[f64],
    ys: &[f64],
    x_range: Range<f64>,
    columns: usize,
) -> Vec<Vec<(f64, f64)>> {
    let n = xs.len().min(ys.len());
    let span = x_range.end - x_range.start;
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut run: Vec<(f64, f64)> = Vec::new();
    let simple =
        n <= 4 * columns.max(1) || span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    let scale = columns.max(1) as f64 / span;
    // Current column: its index and the (index, point) of first, min, max, last.
    type Pt = (usize, (f64, f64));
    let mut bucket: Option<(i64, Pt, Pt, Pt, Pt)> = None;
    let flush = |bucket: &mut Option<(i64, Pt, Pt, Pt, Pt)>, run: &mut Vec<(f64, f64)>| {
        if let Some((_, first, min, max, last)) = bucket.take() {
            let mut pts = [first, min, max, last];
            pts.sort_by_key(|p| p.0);
            let mut prev = None;
            for (i, p) in pts {
                if prev != Some(i) {
                    run.push(p);
                    prev = Some(i);
                }
            }
        }
    };
    for (i, (&x, &y)) in xs.iter().zip(ys).enumerate().take(n) {
        if !(x.is_finite() && y.is_finite()) {
            flush(&mut bucket, &mut run);
            if !run.is_empty() {
                runs.push(std::mem::take(&mut run));
            }
            continue;
        }
        if simple {
            run.push((x, y));
            continue;
        }
        let col = ((x - x_range.start) * scale).floor() as i64;
        let pt = (i, (x, y));
        match bucket.as_mut() {
            Some((c, _, min, max, last)) if *c == col => {
                if y < min.1 .1 {
                    *min = pt;
                }
                if y > max.1 .1 {
                    *max = pt;
                }
                *last = pt;
            }
            _ => {
                flush(&mut bucket, &mut run);
                bucket = Some((col, pt, pt, pt, pt));
            }
        }
    }
    flush(&mut bucket, &mut run);
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// A log axis's key points: `m · 10^k` for each mantissa `m` (1 ≤ m < 10) of `mantissas`,
/// within `[lo, hi]` (a part in 10⁹ either way, for ends computed with `powf`), ascending.
/// The renderer's log axes tick at these (a decade's end once: a label drawn twice
/// reads bold).
pub fn log_key_points(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let mut v = Vec::new();
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
        return v;
    }
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    for k in first..=last {
        for m in mantissas {
            let x = m * 10f64.powi(k);
            if x >= lo * (1.0 - 1e-9) && x <= hi * (1.0 + 1e-9) {
                v.push(x);
            }
        }
    }
    v
}

/// Formats a y tick: plain decimals sized to the axis span, scientific for very large or small values.
pub(crate) fn fmt_tick(v: f64, span: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    // Small ticks by their own size; large ones by the axis's span too, so one axis
    // never mixes 500000 with 1.00e6.
    let mag = v.abs().max(span.abs() / 10.0);
    if mag < 1e-3 || v.abs().max(span.abs()) >= 1e6 {
        return format!("{v:.2e}");
    }
    // The tick step for about 8 labels: the smallest 1, 2 or 5 x 10^k >= span / 8.
    let rough = span.abs() / 8.0;
    let decimals = if rough > 0.0 {
        let p = 10f64.powf(rough.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * p)
            .find(|s| *s >= rough * (1.0 - 1e-9))
            .unwrap_or(p * 10.0);
        (-(step.log10() + 1e-9).floor()).clamp(0.0, 8.0) as usize
    } else {
        2
    };
    format!("{v:.decimals$}")
}

/// The files `--plot DIR` writes, in the order they are drawn.
pub const FILES: [&str; 8] = [
    "displacement.png",
    "velocity.png",
    "acceleration.png",
    "pressure_angle.png",
    "angular_velocity.png",
    "contact_force.png",
    "contact_stress.png",
    "torque.png",
];

/// The file of the profile deviation plot (actual and measured cams).
pub const PROFILE_FILE: &str = "profile_deviation.png";

/// The files `--plot DIR` writes for an actual or measured cam: [`FILES`] and
/// [`PROFILE_FILE`].
pub const FILES_WITH_PROFILE: [&str; 9] = [
    FILES[0],
    FILES[1],
    FILES[2],
    FILES[3],
    FILES[4],
    FILES[5],
    FILES[6],
    FILES[7],
    PROFILE_FILE,
];

/// Points of the profile plot over one revolution (0.05°).
const PROFILE_SAMPLES: usize = 7200;

/// The profile deviation figure: the lift deviation `e(θ)` over one revolution and,
/// below it, its slope `de/dθ` (whose local extrema FPR counts), with the run's period
/// starts of the first revolution (`periods`) marked.
fn profile_figure(dev: &HostDeviation, periods: Vec<f64>) -> Figure {
    let step = 360.0 / PROFILE_SAMPLES as f64;
    let mut axis_data = PlotData::default();
    let (mut e, mut de) = (Vec::new(), Vec::new());
    for k in 0..=PROFILE_SAMPLES {
        let deg = k as f64 * step;
        let p = dev.deviation(deg.to_radians());
        axis_data.angle_deg.push(deg);
        e.push(p.y);
        de.push(p.dy);
    }
    axis_data.period_starts_deg = periods;
    let axis = AngleAxis::new(&axis_data, &[]);
    let xs = &axis_data.angle_deg;
    let e = Series::of("e(θ)", xs, &e, figure::Stroke::solid(SIMULATED, 1));
    let de = Series::of(
        "de/dθ (FPR counts its extrema)",
        xs,
        &de,
        figure::Stroke::solid(SECOND, 1),
    );
    use camsim_scene_file::units::LENGTH;
    Figure::new(
        "Profile deviation of the actual cam (lift − program)",
        FOLLOWER_PLOT_SIZE,
        vec![
            angle_panel(&axis, Axis::of("lift deviation e", LENGTH), vec![e], false),
            angle_panel(
                &axis,
                Axis::of("de/dθ", crate::units::LENGTH_PER_RAD),
                vec![de],
                true,
            ),
        ],
    )
}

/// Draws the profile deviation plot ([`PROFILE_FILE`]) into `out`; `data` gives the
/// period starts of the run's first revolution.
pub fn draw_profile(
    out: &mut AtomicDir,
    data: &PlotData,
    dev: &HostDeviation,
    units: Units,
) -> Result<()> {
    let periods = data
        .period_starts_deg
        .iter()
        .copied()
        .filter(|p| *p > 0.0 && *p < 360.0)
        .collect();
    figure::draw(out, PROFILE_FILE, &profile_figure(dev, periods), units)
}

/// Points of the SVAJ plot over one revolution (0.05°).
const SVAJ_SAMPLES: usize = 7200;

/// The SVAJ figure of `design`'s program (DYNACAM's S, V, A, J diagram): lift,
/// velocity, acceleration and jerk against cam angle, the derivatives in time at the
/// design's speed ω0 (v = ω dy/dθ, a = ω² d²y/dθ², j = ω³ d³y/dθ³), the segment
/// boundaries marked.
fn svaj_figure(design: &camsim_core::Design<f64>) -> Figure {
    let w = design.omega0;
    let rpm = camsim_core::rad_per_s_to_rpm(w);
    let mut axis_data = PlotData::default();
    let (mut s, mut v, mut a, mut j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..=SVAJ_SAMPLES {
        let deg = k as f64 * 360.0 / SVAJ_SAMPLES as f64;
        let f = design.program.follower(deg.to_radians());
        axis_data.angle_deg.push(deg);
        s.push(f.y);
        v.push(f.dy * w);
        a.push(f.d2y * w * w);
        j.push(f.d3y * w * w * w);
    }
    axis_data.period_starts_deg = design
        .program
        .segments()
        .iter()
        .map(|g| g.start_deg)
        .filter(|d| *d > 0.0 && *d < 360.0)
        .collect();
    let mut axis = AngleAxis::new(&axis_data, &[]);
    axis.run = false;
    let xs = &axis_data.angle_deg;
    use crate::units::{ACCELERATION, JERK};
    use camsim_scene_file::units::{LENGTH, SPEED};
    let panel = |title: String, label: &str, values: &[f64], c, unit, last| {
        let curve = Series::of(label, xs, values, figure::Stroke::solid(c, 2));
        angle_panel(&axis, Axis::of(&title, unit), vec![curve], last)
    };
    Figure::new(
        format!("SVAJ of the cam program at {rpm:.0} rpm (grey lines: segment boundaries)"),
        SVAJ_PLOT_SIZE,
        vec![
            panel("lift s".into(), "lift s", &s, SIMULATED, LENGTH, false),
            panel(
                format!("velocity v at {rpm:.0} rpm"),
                "velocity v",
                &v,
                SECOND,
                SPEED,
                false,
            ),
            panel(
                format!("acceleration a at {rpm:.0} rpm"),
                "acceleration a",
                &a,
                THEORY,
                ACCELERATION,
                false,
            ),
            panel(
                format!("jerk j at {rpm:.0} rpm"),
                "jerk j",
                &j,
                THIRD,
                JERK,
                true,
            ),
        ],
    )
}

/// Draws the SVAJ plot of `design`'s program as `file` into `out`.
pub fn draw_svaj(
    out: &mut AtomicDir,
    design: &camsim_core::Design<f64>,
    file: &'static str,
    units: Units,
) -> Result<()> {
    figure::draw(out, file, &svaj_figure(design), units)
}

/// Draws every plot of a run ([`FILES`]) as PNG into the directory output `out` (each
/// file to its temporary: the caller commits `out`).
pub fn draw_all(
    out: &mut AtomicDir,
    data: &PlotData,
    jumps: &[JumpInterval<f64>],
    units: Units,
) -> Result<()> {
    let axis = AngleAxis::new(data, jumps);
    for (file, fig) in figures(data, &axis) {
        figure::draw(out, file, &fig, units)?;
    }
    Ok(())
}

/// Draws a run's figures ([`FILES`]) and, for an actual or measured cam, its profile's
/// ([`PROFILE_FILE`]) into `out`, returned for the caller to commit.
pub fn draw_run(
    mut out: AtomicDir,
    data: &PlotData,
    jumps: &[JumpInterval<f64>],
    profile: Option<&HostDeviation>,
    units: Units,
) -> Result<AtomicDir> {
    draw_all(&mut out, data, jumps, units)?;
    if let Some(dev) = profile {
        draw_profile(&mut out, data, dev, units)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::Plan;
    use std::path::Path;

    /// 1-2-5 key points over four decades, the ends included, each exactly once; none
    /// for a range that is not positive.
    #[test]
    fn log_key_points_are_each_decade_s_mantissas_once() {
        let v = log_key_points(0.05, 200.0, &[1.0, 2.0, 5.0]);
        let want = [
            0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0,
        ];
        assert_eq!(v.len(), want.len(), "{v:?}");
        for (a, b) in v.iter().zip(want) {
            assert!((a / b - 1.0).abs() < 1e-12, "{a} against {b}");
        }
        // Ends computed with powf land a part in 1e15 off: still in.
        let v = log_key_points(10f64.powf(-8.0), 10f64.powf(-4.0), &[1.0]);
        assert_eq!(v.len(), 5, "{v:?}");
        assert!(log_key_points(0.0, 10.0, &[1.0]).is_empty());
        assert!(log_key_points(10.0, 1.0, &[1.0]).is_empty());
    }

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
                    let values =
                        |s: &Series| -> Vec<f64> { s.points.iter().map(|p| p.1).collect() };
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

    /// An RGB buffer, its size and its panels' plotting areas.
    type Rendered = (Vec<u8>, (u32, u32), Vec<figure::render::PixelArea>);

    /// The figure number `fig_index` of a run drawn into an RGB buffer: the buffer, its
    /// size and each panel's plotting area.
    fn render_to_buffer(
        fig_index: usize,
        data: &PlotData,
        jumps: &[JumpInterval<f64>],
    ) -> Result<Rendered> {
        let axis = AngleAxis::new(data, jumps);
        let (_, fig) = figures(data, &axis)
            .into_iter()
            .nth(fig_index)
            .ok_or_else(|| anyhow!("no such figure"))?;
        let fig = fig.in_units(crate::units::Units::Inch);
        let (buf, areas) = figure::render::render(&fig)?;
        Ok((buf, fig.size, areas))
    }

    /// A synthetic two-revolution run: a cycloidal-like rise and return with a small
    /// vibration on top of the theoretical curves, sampled every 0.05 degrees.
    fn synthetic() -> PlotData {
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

    /// Pixel (r, g, b) at (x, y) of an RGB buffer.
    fn px(buf: &[u8], w: u32, x: i32, y: i32) -> [u8; 3] {
        let i = (y as usize * w as usize + x as usize) * 3;
        [buf[i], buf[i + 1], buf[i + 2]]
    }

    #[test]
    fn jump_shading_covers_the_interval_and_nothing_else() {
        let d = synthetic();
        // Revolution 2, 100..130 deg -> 460..490 on the 0..720 axis.
        let jumps = [JumpInterval {
            revolution: 2,
            start_deg: 100.0,
            end_deg: 130.0,
        }];
        for fig in [3, 5] {
            let (plain, (w, _), areas) = render_to_buffer(fig, &d, &[]).unwrap();
            let (shaded, _, areas2) = render_to_buffer(fig, &d, &jumps).unwrap();
            assert_eq!(areas, areas2);
            let (xr, yr) = areas[0].clone();
            let col =
                |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
            let (c0, c1) = (col(460.0), col(490.0));
            // Inside the interval most of the plotting area's pixels changed (all but
            // those under the curves and grid lines drawn on top).
            let mut changed_inside = 0;
            let mut total_inside = 0;
            for x in c0 + 2..c1 - 1 {
                for y in yr.clone() {
                    total_inside += 1;
                    if px(&plain, w, x, y) != px(&shaded, w, x, y) {
                        changed_inside += 1;
                    }
                }
            }
            assert!(
                changed_inside * 10 > total_inside * 8,
                "fig {fig}: {changed_inside}/{total_inside}"
            );
            // A white background pixel inside turns pinkish: red stays high, green/blue drop.
            let y_mid = (yr.start + yr.end) / 2;
            let x_mid = (c0 + c1) / 2;
            let (p, s) = (px(&plain, w, x_mid, y_mid), px(&shaded, w, x_mid, y_mid));
            if p == [255, 255, 255] {
                assert!(s[0] >= 250 && s[1] < 235 && s[2] < 235, "fig {fig}: {s:?}");
            }
            // Left of the interval (away from the legend) nothing changed.
            for x in xr.start..c0 - 3 {
                for y in yr.clone() {
                    assert_eq!(
                        px(&plain, w, x, y),
                        px(&shaded, w, x, y),
                        "fig {fig}: pixel ({x}, {y}) changed"
                    );
                }
            }
        }
    }

    #[test]
    fn a_short_jump_is_still_visible() {
        let d = synthetic();
        let jumps = [JumpInterval {
            revolution: 1,
            start_deg: 200.0,
            end_deg: 200.01,
        }];
        let (plain, (w, _), areas) = render_to_buffer(5, &d, &[]).unwrap();
        let (shaded, _, _) = render_to_buffer(5, &d, &jumps).unwrap();
        let (xr, yr) = areas[0].clone();
        // The shading is at least 3 px wide about 200°: the column there, to a pixel's rounding.
        let col = xr.start + ((200.0 / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let changed = (col - 1..=col + 1)
            .map(|c| {
                (yr.start..yr.end)
                    .filter(|&y| px(&plain, w, c, y) != px(&shaded, w, c, y))
                    .count()
            })
            .max()
            .unwrap_or(0);
        assert!(changed * 2 > (yr.end - yr.start) as usize, "{changed}");
    }

    #[test]
    fn curves_change_pixels_where_the_data_differ() {
        let d = synthetic();
        let mut bumped = d.clone();
        // Dent the simulated displacement between 500 and 520 degrees only (staying
        // inside the y range, so the axes do not change).
        for (x, y) in bumped.angle_deg.iter().zip(bumped.y.iter_mut()) {
            if (500.0..520.0).contains(x) {
                *y -= 0.3;
            }
        }
        let (a, (w, _), areas) = render_to_buffer(0, &d, &[]).unwrap();
        let (b, _, _) = render_to_buffer(0, &bumped, &[]).unwrap();
        let (xr, _) = areas[0].clone();
        let col =
            |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let (c0, c1) = (col(500.0), col(520.0));
        let mut changed_cols = std::collections::BTreeSet::new();
        for (top_x, top_y) in areas.iter().map(|a| (a.0.clone(), a.1.clone())) {
            for x in top_x {
                for y in top_y.clone() {
                    if px(&a, w, x, y) != px(&b, w, x, y) {
                        changed_cols.insert(x);
                    }
                }
            }
        }
        // The bump is drawn in both panels (curve and deviation) and the deviation
        // panel's y range changes, so pixels change; in the top panel the changes are
        // only at the bump (with the line's width either side).
        assert!(!changed_cols.is_empty());
        let (tx, ty) = areas[0].clone();
        for x in tx {
            for y in ty.clone() {
                if px(&a, w, x, y) != px(&b, w, x, y) {
                    assert!(
                        (c0 - 3..=c1 + 3).contains(&x),
                        "top panel changed at column {x}, bump at {c0}..{c1}"
                    );
                }
            }
        }
        let top_changes = (c0..c1).filter(|&x| changed_cols.contains(&x)).count();
        assert!(top_changes as i32 >= (c1 - c0) / 2, "{top_changes}");
    }

    #[test]
    fn sharp_spikes_stay_inside_the_plotting_area() {
        // A fast, large vibration between 80 and 100 degrees (a few samples per period,
        // like the contact ringing of a real run): drawn as one wide polyline, the miter
        // joins at its reversals shoot far out of the plot.
        let mut d = synthetic();
        for (x, a) in d.angle_deg.iter().zip(d.a.iter_mut()) {
            if (80.0..100.0).contains(x) {
                *a += 1e5
                    * (x * 2.0 * std::f64::consts::PI / 0.17).sin()
                    * (1.0 - (x - 90.0).abs() / 10.0);
            }
        }
        let (buf, (w, h), areas) = render_to_buffer(2, &d, &[]).unwrap();
        let (xr, yr) = areas[0].clone();
        let col =
            |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let (c0, c1) = (col(80.0), col(100.0));
        // Nothing but white above the top panel's plotting area over the vibration.
        for x in c0..c1 {
            for y in 0..yr.start - 1 {
                assert_eq!(
                    px(&buf, w, x, y),
                    [255, 255, 255],
                    "pixel ({x}, {y}) above the plot"
                );
            }
        }
        // Nor any curve colour below the bottom panel's plotting area.
        let bottom = areas.last().unwrap().1.end;
        for x in c0..c1 {
            for y in bottom + 1..h as i32 {
                let p = px(&buf, w, x, y);
                assert!(
                    !(p[2] > 150 && p[0] < 100),
                    "curve pixel ({x}, {y}) below the plot: {p:?}"
                );
            }
        }
        // The vibration itself is drawn up to near the top of the plotting area.
        let top = (yr.start..yr.end).find(|&y| {
            (c0..c1).any(|x| {
                let p = px(&buf, w, x, y);
                p[2] > 150 && p[0] < 100
            })
        });
        assert!(
            top.is_some_and(|t| t < yr.start + (yr.end - yr.start) / 4),
            "{top:?}"
        );
    }

    #[test]
    fn decimation_keeps_extremes_and_bounds_the_point_count() {
        let n = 1_000_000;
        let xs: Vec<f64> = (0..n).map(|i| 720.0 * i as f64 / n as f64).collect();
        let mut ys: Vec<f64> = xs.iter().map(|x| x.to_radians().sin()).collect();
        ys[123_457] = 50.0;
        ys[765_433] = -40.0;
        let runs = decimate(&xs, &ys, 0.0..720.0, 1000);
        assert_eq!(runs.len(), 1);
        let run = &runs[0];
        assert!(run.len() <= 4 * 1001, "{}", run.len());
        let max = run.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let min = run.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!((max, min), (50.0, -40.0));
        // Order is preserved and the end points are kept.
        assert!(run.windows(2).all(|w| w[0].0 <= w[1].0));
        assert_eq!(run.first().copied(), Some((xs[0], ys[0])));
        assert_eq!(run.last().copied(), Some((xs[n - 1], ys[n - 1])));
    }

    #[test]
    fn decimation_splits_at_non_finite_values() {
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let ys = [0.0, 1.0, f64::NAN, 3.0, 4.0];
        let runs = decimate(&xs, &ys, 0.0..4.0, 100);
        assert_eq!(
            runs,
            vec![vec![(0.0, 0.0), (1.0, 1.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn angle_axis_spans_whole_revolutions_and_places_jumps() {
        let d = synthetic();
        let jumps = [
            JumpInterval {
                revolution: 2,
                start_deg: 350.0,
                end_deg: 370.0,
            },
            JumpInterval {
                revolution: 1,
                start_deg: 10.0,
                end_deg: 20.0,
            },
        ];
        let a = AngleAxis::new(&d, &jumps);
        assert_eq!(a.range, 0.0..720.0);
        assert_eq!(a.revolutions, vec![360.0]);
        assert_eq!(a.ticks.first(), Some(&0.0));
        assert_eq!(a.ticks.last(), Some(&720.0));
        // Sorted; the carried-over jump is clipped at the end of the axis.
        assert_eq!(a.jumps, vec![(10.0, 20.0), (710.0, 720.0)]);
        // The period start at the revolution boundary is not drawn twice.
        assert!(!a.periods.contains(&360.0));
        assert_eq!(a.periods.len(), 6);
    }

    #[test]
    fn off_cam_intervals_come_from_the_contact_flags_and_merge_with_the_list() {
        let mut d = synthetic();
        // Off the cam from 100 to 150 degrees and from 700 degrees to the end.
        for (x, c) in d.angle_deg.iter().zip(d.in_contact.iter_mut()) {
            *c = !((100.0..150.0).contains(x) || *x >= 700.0);
        }
        let iv = d.off_cam_intervals();
        assert_eq!(iv.len(), 2);
        assert_eq!(iv[0], (100.0, 150.0));
        assert_eq!(iv[1].0, 700.0);
        assert_eq!(iv[1].1, *d.angle_deg.last().unwrap());
        // A listed jump overlapping the first interval merges with it; a separate one stays.
        let jumps = [
            JumpInterval {
                revolution: 1,
                start_deg: 140.0,
                end_deg: 160.0,
            },
            JumpInterval {
                revolution: 2,
                start_deg: 0.0,
                end_deg: 5.0,
            },
        ];
        let a = AngleAxis::new(&d, &jumps);
        assert_eq!(a.jumps.len(), 3);
        assert_eq!(a.jumps[0], (100.0, 160.0));
        assert_eq!(a.jumps[1], (360.0, 365.0));
        assert_eq!(a.jumps[2].0, 700.0);
    }

    #[test]
    fn samples_off_the_cam_are_shaded_without_a_jump_list() {
        let d = synthetic();
        let mut off = d.clone();
        for (x, c) in off.angle_deg.iter().zip(off.in_contact.iter_mut()) {
            *c = !(460.0..490.0).contains(x);
        }
        let (plain, (w, _), areas) = render_to_buffer(6, &d, &[]).unwrap();
        let (shaded, _, _) = render_to_buffer(6, &off, &[]).unwrap();
        let (xr, yr) = areas[0].clone();
        let x_mid = xr.start + ((475.0 / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
        let changed = (yr.start..yr.end)
            .filter(|&y| px(&plain, w, x_mid, y) != px(&shaded, w, x_mid, y))
            .count();
        assert!(changed * 10 > (yr.end - yr.start) as usize * 8, "{changed}");
    }

    #[test]
    fn tick_labels_have_as_many_decimals_as_the_step_needs() {
        assert_eq!(fmt_tick(0.2, 1.2), "0.2"); // step 0.2
        assert_eq!(fmt_tick(1.0, 1.2), "1.0");
        assert_eq!(fmt_tick(0.005, 0.02), "0.005"); // step 0.005
        assert_eq!(fmt_tick(-0.01, 0.02), "-0.010");
        assert_eq!(fmt_tick(90_000.0, 40_000.0), "90000"); // step 5000
        assert_eq!(fmt_tick(83.6, 1.2), "83.6");
        assert_eq!(fmt_tick(0.0, 1.0), "0");
        assert_eq!(fmt_tick(2.5e7, 1e7), "2.50e7");
        // One format on an axis spanning millions (the SVAJ jerk).
        assert_eq!(fmt_tick(500_000.0, 3.5e6), "5.00e5");
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
}
