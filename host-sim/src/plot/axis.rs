//! The cam angle axis every run, profile and SVAJ plot shares (`AngleAxis`: its
//! range, ticks, revolutions, jumps and period starts), the panel against it, and the
//! renderer's helpers: decimation of long series, log axes' key points, tick labels.

use std::ops::Range;

use camsim_core::JumpInterval;

use super::run::PlotData;
use super::{JUMP_ALPHA, JUMP_FILL, PERIOD_LINE, REV_LINE};
use crate::figure::{self, At, Axis, Band, Legend, Marker, Panel, Series, Shape, Ticks};

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
pub(super) fn angle_panel(axis: &AngleAxis, y: Axis, curves: Vec<Series>, labelled: bool) -> Panel {
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

/// The cam angle axis shared by every plot: range, ticks, and the marks on it.
pub(super) struct AngleAxis {
    pub(super) range: Range<f64>,
    pub(super) ticks: Vec<f64>,
    /// Revolution boundaries strictly inside the range, degrees.
    pub(super) revolutions: Vec<f64>,
    /// Whether the axis is a run's (revolutions counted and labelled) rather than one
    /// revolution of the cam's shape (the SVAJ plot).
    pub(super) run: bool,
    /// Jump intervals on the continuous axis, degrees.
    pub(super) jumps: Vec<(f64, f64)>,
    /// Period starts (excluding revolution boundaries), degrees.
    pub(super) periods: Vec<f64>,
}

impl AngleAxis {
    pub(super) fn new(d: &PlotData, jumps: &[JumpInterval<f64>]) -> Self {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::run::tests::synthetic;

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
}
