//! The figures of `camsim compare --plot DIR`: every workable law's value in each ranked
//! column (rankings.png), and revolution 2 of the best laws on the theoretical cam and
//! on one actual cam (responses.png).

use crate::figure::palette::{BLUE, MID_GREY, RED};
use crate::figure::{
    Axis, Bar, Entry, Figure, HAlign, Note, Panel, Series, Strip, Stroke, Swatch, Ticks, VAlign,
};
use crate::study::compare::{LawStudy, LawTraces, NotWorkable, HEADERS};
use crate::units::{Units, ACCELERATION, FORCE, STRESS, TORQUE};
use camsim_scene_file::units::Unit;

/// Panels a row in rankings.png.
const RANK_COLUMNS: usize = 3;
/// A bar's half height, of the distance between two laws.
const BAR_HALF: f64 = 0.38;

/// A ranked column's quantity and unit on a plot axis (`None`: dimensionless), and
/// which way is better.
fn rank_axis(col: &str) -> (&'static str, Option<Unit>, &'static str) {
    match col {
        "sensitivity_to_flexibility" => (
            "Σ acceleration RMS, theoretical cam",
            Some(ACCELERATION),
            "smaller is better",
        ),
        "sensitivity_to_tolerance" => (
            "Σ acceleration RMS, actual − theoretical",
            Some(ACCELERATION),
            "smaller is better",
        ),
        "shock_index" => ("Σ (RMS_I − RMS_II) / RMS_I", None, "smaller is better"),
        "torque_avg" => (
            "average torque over the rise",
            Some(TORQUE),
            "smaller is better",
        ),
        "torque_max" => ("largest |torque|", Some(TORQUE), "smaller is better"),
        "contact_force_min" => ("smallest contact force", Some(FORCE), "larger is better"),
        "contact_force_max" => ("largest contact force", Some(FORCE), "smaller is better"),
        "contact_stress_max" => ("largest contact stress", Some(STRESS), "smaller is better"),
        _ => (
            "sum of the ranks",
            None,
            "holding contact first, then smaller",
        ),
    }
}

/// The rankings: one bar chart a ranked column, the laws' values, the best bar in red
/// (the note of a lost contact in `units`).
pub fn rankings(laws: &[LawStudy], not_workable: &[NotWorkable], units: Units) -> Figure {
    let mut title =
        "Every workable law's value in each ranked column, revolution 2 (rank 1 in red)"
            .to_string();
    if !not_workable.is_empty() {
        let names: Vec<&str> = not_workable.iter().map(|n| n.name.as_str()).collect();
        title += &format!(
            "; not workable (left the model's valid range): {}",
            names.join(", ")
        );
    }
    let rows = HEADERS.len().div_ceil(RANK_COLUMNS);
    let panels = HEADERS
        .iter()
        .map(|(col, head)| rank_panel(laws, col, head, units))
        .collect();
    let mut fig = Figure::new(title, (1500, 420 * rows as u32 + 50), panels);
    fig.columns = RANK_COLUMNS;
    fig
}

/// One ranked column's bar chart.
fn rank_panel(laws: &[LawStudy], col: &str, head: &str, units: Units) -> Panel {
    let (what, unit, better) = rank_axis(col);
    let v: Vec<f64> = laws
        .iter()
        .map(|l| l.values.get(col).unwrap_or(0.0))
        .collect();
    let lo = v.iter().copied().fold(0.0f64, f64::min);
    let hi = v.iter().copied().fold(0.0f64, f64::max);
    let pad = 0.08 * (hi - lo).max(1e-12);
    let mut x = match unit {
        Some(u) => Axis::of(what, u),
        None => Axis::plain(what, ""),
    }
    .range(lo - pad, hi + pad)
    .ticks(Ticks::Auto(5));
    x.thousands = true;
    let names = laws.iter().map(|l| l.name.clone()).collect();
    let y = Axis::plain("", "")
        .range(-0.5, laws.len() as f64 - 0.5)
        .ticks(Ticks::Named(names));
    let mut p = Panel::new(x, y);
    p.caption = Some(format!("{head}: {better}"));
    for (i, (l, &v)) in laws.iter().zip(&v).enumerate() {
        let colour = if l.ranks.get(col) == Some(1) {
            RED
        } else {
            BLUE
        };
        let y = i as f64;
        p.bars.push(Bar {
            x: (0.0, v),
            y: (y - BAR_HALF, y + BAR_HALF),
            colour,
            edge: None,
        });
        if col == "contact_force_min" && v <= 0.0 {
            // A law that jumps has no bar here: say so.
            let unit = units.axis(FORCE).1;
            p.notes.push(Note::new(
                (0.02 * (hi + pad), y + 0.25),
                format!("0 {unit}: contact lost"),
                HAlign::Left,
                VAlign::Below,
            ));
        }
    }
    p
}

/// The responses: a row a law, its theoretical cam (grey) under its actual cam
/// (colour); the acceleration deviation on the left, the contact force on the right,
/// each column on one scale so the laws compare.
pub fn responses(traces: &[LawTraces]) -> Figure {
    let rows = traces.len().max(1);
    let range = |acc: bool| {
        let (lo, hi) = traces
            .iter()
            .flat_map(|t| t.1.iter().chain(&t.2))
            .map(|p| if acc { p.1 } else { p.2 })
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let (lo, hi) = if lo < hi { (lo, hi) } else { (-1.0, 1.0) };
        (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
    };
    let mut panels = Vec::new();
    for (k, t) in traces.iter().enumerate() {
        for acc in [true, false] {
            panels.push(response_panel(t, acc, range(acc), k + 1 == traces.len()));
        }
    }
    let title =
        "Revolution 2 on the theoretical cam and on one actual cam (sample 0 of --seed), by law";
    let mut fig = Figure::new(title, (1500, 90 + 300 * rows as u32), panels);
    fig.columns = 2;
    fig.strip = Strip {
        entries: vec![
            Entry {
                swatch: Swatch::Line(Stroke::solid(MID_GREY, 2), None),
                text: "theoretical cam".into(),
            },
            Entry {
                swatch: Swatch::Line(Stroke::solid(BLUE, 2), None),
                text: "one actual cam (sample 0; for the spread over many cams: camsim montecarlo)"
                    .into(),
            },
        ],
        columns: 0,
        note: None,
    };
    fig
}

/// One law's acceleration deviation (`acc`) or contact force against cam angle.
fn response_panel(t: &LawTraces, acc: bool, (lo, hi): (f64, f64), last: bool) -> Panel {
    let major = (0..=12).map(|k| 30.0 * f64::from(k)).collect();
    let minor = (0..=24).map(|k| 15.0 * f64::from(k)).collect();
    let x = Axis::plain(
        if last { "cam angle θ" } else { "" },
        if last { "deg" } else { "" },
    )
    .range(0.0, 360.0)
    .ticks(Ticks::At { major, minor });
    let y = if acc {
        Axis::of("a − a_rigid", ACCELERATION)
    } else {
        Axis::of("Fc", FORCE)
    };
    let mut p = Panel::new(x, y.range(lo, hi).ticks(Ticks::Auto(5)));
    let what = if acc {
        "load acceleration − the law's rigid acceleration"
    } else {
        "contact force"
    };
    p.caption = Some(format!("{}: {what}", t.0));
    for (trace, stroke) in [
        (&t.1, Stroke::solid(MID_GREY, 2)),
        (&t.2, Stroke::solid(BLUE, 1)),
    ] {
        let points = trace
            .iter()
            .map(|q| (q.0, if acc { q.1 } else { q.2 }))
            .collect();
        p.series.push(Series::line(None, points, stroke));
    }
    p
}
