//! `camsim laws --plot`'s figure as data: every law's normalised S, V, A and J against
//! u = θ/β.

use camsim_core::{LawValue, MotionLaw};

use crate::figure::{palette, Axis, Entry, Figure, Panel, Series, Strip, Stroke, Swatch, Ticks};

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
