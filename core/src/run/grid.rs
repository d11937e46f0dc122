//! Output on a cam-angle grid: a run's samples at fixed cam angles (every `step_deg`
//! degrees, and at every program segment's start), taken from the solver's continuous
//! extension ([`crate::Dense`]) instead of at the steps the solver happens to take.
//!
//! Why: the solver's steps crowd where the dynamics are fast and thin out in dwells, so a
//! file of step samples is large (about 9 000 rows per revolution on the reference design)
//! and uneven; a designer wants the response at, say, every half degree, the same for every
//! run and every tolerance. The grid's samples are as accurate as the step's own nodes
//! (the extension is `O(h⁶)` between them, docs/MODEL.md §5.10), and asking for them does
//! not change the steps: the nodes are bit for bit those of [`crate::simulate`].

use core::ops::ControlFlow;

use crate::run::response::{GridPointKind, RunStart, RunState};
use crate::{
    CamModel, CamProgram, Dense, Error, LiftProfile, Observer, Real, Result, Sample, Scene,
    SolverSettings, SolverStats,
};

/// A cam-angle grid: every `step_deg` degrees from 0 in each revolution, plus the start
/// of every program segment and the run's end; or only the segment starts and the end
/// ([`AngleGrid::segment_starts`], what the per-period statistics need).
///
/// ```
/// use camsim_core::AngleGrid;
/// assert!(AngleGrid::new(0.5_f64).is_ok());
/// assert!(AngleGrid::new(0.0_f64).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleGrid<T> {
    step_deg: Option<T>,
}

impl<T: Real> AngleGrid<T> {
    /// The smallest grid step, degrees (a million points per revolution at 3.6e-4°).
    pub const MIN_STEP_DEG: f64 = 3.6e-4;

    /// A grid every `step_deg` degrees: finite, at least [`Self::MIN_STEP_DEG`], at most 360.
    pub fn new(step_deg: T) -> Result<Self> {
        if !(step_deg.is_finite()
            && step_deg >= T::from_f64(Self::MIN_STEP_DEG)
            && step_deg <= T::from_f64(360.0))
        {
            return Err(Error::InvalidParameter {
                field: "grid_step_deg",
                rule: "must be between 3.6e-4 and 360 degrees",
                value: step_deg.to_f64(),
            });
        }
        Ok(Self {
            step_deg: Some(step_deg),
        })
    }

    /// Only the segment starts and the run's end.
    pub fn segment_starts() -> Self {
        Self { step_deg: None }
    }

    /// The grid step, degrees (none for [`AngleGrid::segment_starts`]).
    pub fn step_deg(&self) -> Option<T> {
        self.step_deg
    }

    /// How many multiples of the step one revolution has below 360° (the segment starts
    /// that fall between them come on top; none without a step).
    pub fn points_per_revolution(&self) -> u64 {
        let Some(step) = self.step_deg else {
            return 0;
        };
        let q = T::from_f64(360.0) / step;
        // ceil(q) as -floor(-q); `as` saturates (the step is at least MIN_STEP_DEG).
        let n = (-(-q).floor()).to_f64();
        if n >= 1.0 {
            n as u64
        } else {
            1
        }
    }
}

/// One grid point: where it is, exactly as the grid defines it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct GridPoint<T> {
    /// Unwrapped cam angle, rad.
    theta: T,
    /// Revolution, from 1.
    revolution: u32,
    /// Angle within the revolution, degrees.
    within_deg: T,
    /// The program segment it is in (a segment's start belongs to that segment; the
    /// run's end to the last segment).
    segment: usize,
    /// What the point is.
    kind: GridPointKind,
}

/// Walks the grid's points in order, revolution after revolution, to the run's end.
struct Cursor<'a, T, const M: usize> {
    grid: AngleGrid<T>,
    program: &'a CamProgram<T, M>,
    /// Revolutions in the run.
    revolutions: u32,
    /// The run's end, rad (the end point's angle, exactly as the run ends).
    target: T,
    /// Revolution, from 0.
    rev: u32,
    /// Next multiple of the step.
    k: u32,
    /// Next segment start.
    j: usize,
}

impl<'a, T: Real, const M: usize> Cursor<'a, T, M> {
    fn new(grid: AngleGrid<T>, program: &'a CamProgram<T, M>, revolutions: u32, target: T) -> Self {
        Self {
            grid,
            program,
            revolutions,
            target,
            rev: 0,
            k: 0,
            j: 0,
        }
    }

    /// The next point; after the end, the end again.
    fn next_point(&mut self) -> GridPoint<T> {
        let full = T::from_f64(360.0);
        // Two angles closer than this are one point (the step's multiples are computed,
        // the segment starts given: 0.5° · 180 may miss 90° by a rounding).
        let same = full * T::EPSILON * T::from_f64(16.0);
        let segs = self.program.segments();
        let last = segs.len().saturating_sub(1);
        loop {
            if self.rev >= self.revolutions {
                return GridPoint {
                    theta: self.target,
                    revolution: self.revolutions,
                    within_deg: full,
                    segment: last,
                    kind: GridPointKind::End,
                };
            }
            let a = self
                .grid
                .step_deg
                .map(|step| step * T::from_usize(self.k as usize))
                .filter(|a| *a < full - same);
            let b = segs.get(self.j).map(|s| s.start_deg);
            let (within, kind) = match (a, b) {
                (Some(a), Some(b)) if (a - b).abs() <= same => {
                    self.k = self.k.saturating_add(1);
                    self.j += 1;
                    (b, GridPointKind::SegmentStart)
                }
                (Some(a), Some(b)) if b < a => {
                    self.j += 1;
                    (b, GridPointKind::SegmentStart)
                }
                (Some(a), _) => {
                    self.k = self.k.saturating_add(1);
                    (a, GridPointKind::Step)
                }
                (None, Some(b)) => {
                    self.j += 1;
                    (b, GridPointKind::SegmentStart)
                }
                (None, None) => {
                    self.rev = self.rev.saturating_add(1);
                    self.k = 0;
                    self.j = 0;
                    continue;
                }
            };
            // The segment: the last one that starts at or before this angle.
            let segment = segs
                .iter()
                .rposition(|s| s.start_deg <= within + same)
                .unwrap_or(0);
            let theta = (full * T::from_usize(self.rev as usize) + within).to_radians();
            return GridPoint {
                theta,
                revolution: self.rev.saturating_add(1),
                within_deg: within,
                segment,
                kind,
            };
        }
    }
}

/// The time in `[t0, t2]` where the interpolated cam angle `theta` reaches `target`:
/// Newton's method on the scalar interpolant, kept inside a shrinking bracket (bisection
/// where a Newton step would leave it).
fn time_at<T: Real>(theta: &Dense<'_, T, 1>, target: T) -> T {
    let (mut lo, mut hi) = (theta.t_start(), theta.t_end());
    let [a, _, c] = theta.nodes();
    let (th0, th2) = (a[0], c[0]);
    let mut t = if th2 > th0 {
        lo + (hi - lo) * ((target - th0) / (th2 - th0)).clamp(T::ZERO, T::ONE)
    } else {
        lo
    };
    let mut v = [T::ZERO];
    for _ in 0..TIME_AT_ITERATIONS {
        theta.eval(t, &mut v);
        let g = v[0] - target;
        if g == T::ZERO {
            break;
        }
        if g < T::ZERO {
            lo = t;
        } else {
            hi = t;
        }
        theta.eval_derivative(t, &mut v);
        let newton = t - g / v[0];
        let next = if newton > lo && newton < hi && newton.is_finite() {
            newton
        } else {
            T::HALF * (lo + hi)
        };
        if (next - t).abs() <= T::EPSILON * t.abs().max(hi - lo) || hi - lo <= T::ZERO {
            t = next;
            break;
        }
        t = next;
    }
    t
}

/// The samples at a step's nodes after its start: England's midpoint and end
/// (`(Some(mid), end)`), or a pair's end (`(None, end)`); `None` if the extension had no
/// end (never).
fn step_nodes<T, S, const N: usize, P>(
    model: &CamModel<T, S, N, P>,
    d: &Dense<'_, T, N>,
    stress: bool,
    outputs: bool,
) -> Option<(Option<Sample<T>>, Sample<T>)>
where
    T: Real,
    S: Scene,
    P: LiftProfile<T>,
{
    let mut nodes: [Option<Sample<T>>; 2] = [None, None];
    for (slot, (t, yn)) in nodes.iter_mut().zip(d.inner_nodes()) {
        *slot = Some(model.sample_with(t, yn, stress, outputs));
    }
    match nodes {
        [Some(mid), Some(end)] => Some((Some(mid), end)),
        [Some(end), None] => Some((None, end)),
        _ => None,
    }
}

/// The cam angle and speed at a step's start, midpoint (zero without one) and end: the
/// nodes of the cam angle's own interpolant.
type AngleNodes<T> = ([[T; 1]; 3], [[T; 1]; 3]);

/// [`AngleNodes`] of a step from `start` through `inner` to `end`.
fn angle_nodes<T: Real>(
    start: &Sample<T>,
    inner: Option<&Sample<T>>,
    end: &Sample<T>,
) -> AngleNodes<T> {
    let (p0, p2) = (&start.point, &end.point);
    let (th_mid, om_mid) = inner.map_or((T::ZERO, T::ZERO), |m| (m.point.theta_c, m.point.omega_c));
    (
        [[p0.theta_c], [th_mid], [p2.theta_c]],
        [[p0.omega_c], [om_mid], [p2.omega_c]],
    )
}

/// A sample interpolated at a grid point, labelled with the grid's exact revolution,
/// angle and segment.
fn grid_sample<T: Real>(mut s: Sample<T>, point: &GridPoint<T>) -> Sample<T> {
    s.revolution = point.revolution;
    s.angle_deg = point.within_deg;
    s.segment = point.segment;
    s
}

/// Most iterations of [`time_at`]: enough for bisection alone (taken when Newton's step
/// would leave the bracket) to shrink a step's interval by `2^-60`, below the relative
/// resolution of f64 (`2^-52`); Newton's steps converge in a few, and the loop ends on
/// its own tolerance long before.
const TIME_AT_ITERATIONS: u32 = 60;

/// [`crate::simulate`] with samples on a cam-angle grid as well: `observer` receives
/// exactly what [`crate::simulate`]'s would through [`Observer::observe`] (the start,
/// midpoint and end of every accepted step, bit for bit the same points), and through
/// [`Observer::observe_grid`] a sample at each of the grid's points up to the run's end
/// (its last revolution's 360°, [`GridPointKind::End`]), in time order with the
/// solver's samples. A grid sample comes from its step's continuous extension at the
/// time the interpolated cam angle reaches the point; its `revolution`, `angle_deg` and
/// `segment` are the grid's exact values. Validity checks, end of run and errors as
/// [`crate::simulate`]; the observer may stop the run from either method. The extension
/// costs one model evaluation per run more than [`crate::simulate`], and each grid
/// point one [`CamModel::sample`].
pub fn simulate_on_grid<T, S, const N: usize, P, O>(
    model: &CamModel<T, S, N, P>,
    settings: &SolverSettings<T>,
    revolutions: u32,
    grid: AngleGrid<T>,
    observer: &mut O,
) -> Result<SolverStats>
where
    T: Real,
    S: Scene,
    P: LiftProfile<T>,
    O: Observer<T>,
{
    let RunStart {
        mut solver,
        mut run,
        t_end,
        mut y,
    } = RunState::start(model, settings, revolutions)?;
    let program = &model.design().program;
    let mut cursor = Cursor::new(grid, program, revolutions, run.target());
    let mut next = cursor.next_point();
    let stress = observer.needs_stress();
    let outputs = observer.needs_outputs();
    let mut failed: Option<Error> = None;
    let mut start = model.sample_with(T::ZERO, &y, stress, outputs);
    let result = if run.take_sample(model, observer, &start).is_break() {
        Ok(solver.stats())
    } else {
        solver.integrate_dense(model, T::ZERO, &mut y, t_end, |d| {
            let Some((inner, end)) = step_nodes(model, d, stress, outputs) else {
                // Unreachable: every extension has an end.
                return ControlFlow::Continue(());
            };
            // Most steps hold no grid point (a segment-start grid has a handful a
            // revolution): nothing more to do than take the nodes.
            if next.theta > end.point.theta_c {
                if let Some(mid) = &inner {
                    if run.take_sample(model, observer, mid).is_break() {
                        return ControlFlow::Break(());
                    }
                }
                let flow = run.take_sample(model, observer, &end);
                start = end;
                return flow;
            }
            // The cam angle's own interpolant (the step's times always increase: the
            // solver's extension `d` was built on the same ones), of the same form as
            // the solver's.
            let (th, om) = angle_nodes(&start, inner.as_ref(), &end);
            let ([th0, th1, th2], [om0, om1, om2]) = (&th, &om);
            let theta = match &inner {
                Some(_) => Dense::new(
                    [d.t_start(), d.t_mid(), d.t_end()],
                    [th0, th1, th2],
                    [om0, om1, om2],
                ),
                None => Dense::cubic([d.t_start(), d.t_end()], [th0, th2], [om0, om2]),
            };
            let theta = match theta {
                Ok(theta) => theta,
                Err(e) => {
                    failed = Some(e);
                    return ControlFlow::Break(());
                }
            };
            let mut ys = [T::ZERO; N];
            for node in inner.iter().chain(core::iter::once(&end)) {
                // The grid's points before this node (the end when the node reaches it).
                let th_node = node.point.theta_c;
                while next.theta < th_node
                    || (next.kind == GridPointKind::End && next.theta <= th_node)
                {
                    let t = time_at(&theta, next.theta);
                    d.eval(t, &mut ys);
                    let s = grid_sample(model.sample_with(t, &ys, stress, outputs), &next);
                    let kind = next.kind;
                    if observer.observe_grid(&s, kind).is_break() {
                        run.stop();
                        return ControlFlow::Break(());
                    }
                    if kind == GridPointKind::End {
                        // Nothing after the end: the node reaching it ends the run.
                        break;
                    }
                    next = cursor.next_point();
                }
                if run.take_sample(model, observer, node).is_break() {
                    return ControlFlow::Break(());
                }
            }
            start = end;
            ControlFlow::Continue(())
        })
    };
    if let Some(e) = failed {
        return Err(e);
    }
    run.finish(model, settings, result)
}
