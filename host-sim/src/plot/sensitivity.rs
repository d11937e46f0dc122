//! The figure of `camsim sensitivity --plot DIR` (sensitivity.png): a row of bar charts
//! a cam (theoretical, actual), one chart an output, the change of the output from the
//! baseline (%) for each group and change; a case that separates where the baseline
//! does not is marked "jump", a case that left the model's valid range is named instead
//! of its bar.

use crate::figure::palette::{BLACK, RED};
use crate::figure::{
    At, Axis, Bar, Colour, Entry, Figure, HAlign, Marker, Note, Panel, Strip, Stroke, Swatch,
    Ticks, VAlign,
};
use crate::study::sensitivity::{
    fmt_value, output_unit, pct, Case, Group, SensitivityReport, OUTPUTS,
};
use crate::units::Units;

/// Size of the plot, pixels.
const PLOT_SIZE: (u32, u32) = (2000, 1000);
/// The cams, a row each.
const CAMS: [&str; 2] = ["theoretical", "actual"];
/// The chart's title of each output, in [`OUTPUTS`]' order.
const PLOT_TITLES: [&str; 5] = [
    "RMS load displacement deviation",
    "RMS load velocity deviation",
    "RMS load acceleration deviation",
    "RMS cam speed deviation",
    "average contact stress",
];
/// A group's band is 1 high; its bars share 0.8 of it.
const BARS_HEIGHT: f64 = 0.8;
/// The x range's room beyond the longest bar, for its "jump" mark (a fraction of it).
const ROOM: f64 = 1.25;
/// The lines between the groups (black at 20 % on white).
const SEPARATOR: Colour = Colour(204, 204, 204);

/// A change's colour: shades of blue for decreases, of red for increases.
fn colour(change: i32) -> Colour {
    match change {
        c if c <= -30 => Colour(31, 90, 180),
        c if c < 0 => Colour(140, 180, 230),
        c if c < 30 => Colour(240, 160, 150),
        _ => Colour(200, 40, 40),
    }
}

/// The figure.
pub fn figure(r: &SensitivityReport, units: Units) -> Figure {
    let changes = changes_of(r);
    let title = format!(
        "camsim sensitivity (VI.4.3): change of each revolution-{} output from the baseline, %, when a group changes (at {:.0} rpm)",
        r.revolution, r.rpm
    );
    let mut panels = Vec::new();
    let mut row_titles = Vec::new();
    for cam in CAMS {
        let base = r.baseline.iter().find(|c| c.cam == cam);
        row_titles.push(row_title(r, cam, base));
        for oi in 0..OUTPUTS.len() {
            panels.push(panel(r, cam, base, oi, &changes, units));
        }
    }
    let mut fig = Figure::new(title, PLOT_SIZE, panels);
    fig.columns = OUTPUTS.len();
    fig.row_titles = row_titles;
    let mut entries: Vec<Entry> = changes
        .iter()
        .map(|&c| Entry {
            swatch: Swatch::Fill(colour(c), 1.0),
            text: format!("group changed by {c:+} %"),
        })
        .collect();
    entries.push(Entry {
        swatch: Swatch::Blank,
        text: "\"jump\": the follower separates in that case".into(),
    });
    fig.strip = Strip::row(entries);
    fig
}

/// The changes of the study's cases, ascending (those that left the range too).
fn changes_of(r: &SensitivityReport) -> Vec<i32> {
    let left = r.not_workable.iter().filter(|n| n.group != "baseline");
    let mut v: Vec<i32> = r
        .cases
        .iter()
        .map(|c| c.change_pct)
        .chain(left.map(|n| n.change_pct))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The title of a cam's row of charts: the cam, and how its baseline ended.
fn row_title(r: &SensitivityReport, cam: &str, base: Option<&Case>) -> String {
    let p = &r.actual_profile;
    let title = match cam {
        "actual" => format!(
            "actual cam (sample 0 of seed {}, {} intervals, FPR {}){}",
            p.seed,
            p.intervals,
            p.fpr,
            if base.is_some_and(|b| b.outputs.jump) {
                ": the follower separates at the baseline already"
            } else {
                ""
            }
        ),
        _ => "theoretical cam".to_string(),
    };
    match r
        .not_workable
        .iter()
        .find(|n| n.cam == cam && n.group == "baseline")
    {
        Some(n) => format!("{title}: the baseline {}", n.verdict()),
        None => title,
    }
}

/// The marks of a cam's cases that left the model's valid range: (group index, change,
/// text).
fn marks(r: &SensitivityReport, cam: &str) -> Vec<(usize, i32, &'static str)> {
    r.not_workable
        .iter()
        .filter(|n| n.cam == cam)
        .filter_map(|n| {
            let gi = Group::ALL.iter().position(|g| g.name() == n.group)?;
            let mark = if n.jump {
                " jump, then out of range "
            } else {
                " not workable "
            };
            Some((gi, n.change_pct, mark))
        })
        .collect()
}

/// A cam's bars of output `oi`: (group index, change, % change of the output, separated).
fn bars(r: &SensitivityReport, cam: &str, base: Option<&Case>, oi: usize) -> Vec<Bar4> {
    Group::ALL
        .iter()
        .enumerate()
        .flat_map(|(gi, g)| {
            r.cases
                .iter()
                .filter(move |c| c.cam == cam && c.group == g.name())
                .filter_map(move |c| {
                    let b = *base?.outputs.values().get(oi)?;
                    let v = *c.outputs.values().get(oi)?;
                    Some((gi, c.change_pct, pct(v, b)?, c.outputs.jump))
                })
        })
        .collect()
}

/// A bar: (group index, change, % change of the output, separated).
type Bar4 = (usize, i32, f64, bool);

/// One output's chart on one cam: a band a group (its name at the band's middle), a bar
/// a change within it (the largest decrease on top), the zero line.
fn panel(
    r: &SensitivityReport,
    cam: &str,
    base: Option<&Case>,
    oi: usize,
    changes: &[i32],
    units: Units,
) -> Panel {
    let bars = bars(r, cam, base, oi);
    let m = bars.iter().map(|b| b.2.abs()).fold(1.0f64, f64::max) * ROOM;
    let groups = Group::ALL.len();
    let names = Group::ALL.iter().map(|g| g.name().to_string()).collect();
    let y = Axis::plain("", "")
        .range(-0.5, groups as f64 - 0.5)
        .ticks(Ticks::Named(names));
    let mut x = Axis::plain(&x_title(base, oi, units), "").range(-m, m);
    x.signed = true;
    let mut p = Panel::new(x, y);
    p.caption = PLOT_TITLES.get(oi).map(|t| t.to_string());
    // Group gi's band is gi ± 0.5: separators between the bands, and the zero line.
    for g in 1..groups {
        p.markers.push(line(At::Y(g as f64 - 0.5), SEPARATOR));
    }
    p.markers.push(line(At::X(0.0), BLACK));
    let w = BARS_HEIGHT / changes.len().max(1) as f64;
    let top_of = |gi: usize, c: i32| {
        let k = changes.iter().position(|x| *x == c).unwrap_or(0) as f64;
        gi as f64 - 0.5 + 0.9 - k * w
    };
    let base_jumps = base.is_some_and(|b| b.outputs.jump);
    for &(gi, c, d, jump) in &bars {
        let top = top_of(gi, c);
        p.bars.push(Bar {
            x: (0.0, d),
            y: (top - 0.9 * w, top - 0.1 * w),
            colour: colour(c),
            edge: None,
        });
        // A case that separates where the baseline does not: marked at its bar.
        if jump && !base_jumps {
            let h = if d >= 0.0 {
                HAlign::Left
            } else {
                HAlign::Right
            };
            p.notes
                .push(Note::new((d, top - 0.5 * w), " jump ", h, VAlign::Middle));
        }
    }
    // A case that left the model's valid range: no bar (no value), a mark.
    for (gi, c, text) in marks(r, cam) {
        let mut n = Note::new(
            (0.0, top_of(gi, c) - 0.5 * w),
            text,
            HAlign::Left,
            VAlign::Middle,
        );
        n.colour = RED;
        p.notes.push(n);
    }
    p
}

/// The x axis's title: the change, %, of the baseline's value in its unit in `units` (as
/// the run plots' axes write it: mm/s², N·m).
fn x_title(base: Option<&Case>, oi: usize, units: Units) -> String {
    let unit = output_unit(oi).map_or_else(
        || OUTPUTS.get(oi).map_or("", |o| o.2).to_string(),
        |u| units.axis(u).1,
    );
    match base.and_then(|b| b.outputs.values().get(oi).copied()) {
        Some(v) => format!(
            "change, % of the baseline {} {unit}",
            fmt_value(oi, v, units)
        ),
        None => "change from the baseline, %".to_string(),
    }
}

/// A thin line across the panel at `at`.
fn line(at: At, colour: Colour) -> Marker {
    Marker {
        at,
        stroke: Some(Stroke::solid(colour, 1)),
        text: None,
        label: None,
    }
}
