//! The figures of `camsim tolerance-study --plot DIR`: the grid as two heat maps
//! (tolerance_grid.png: P(jump) with its interval, the acceleration RMS on a log colour
//! scale) and the responses against the tolerance (tolerance_response.png: P(jump) and
//! the quantiles of the smallest contact force and the largest contact stress, one
//! colour a waviness column, the theoretical cam dashed).

use camsim_scene_file::units::{Unit, STRESS};

use crate::figure::palette::{BLACK, BLUE, BROWN, GREEN, MID_GREY, ORANGE, PURPLE, RED, WHITE};
use crate::figure::{
    At, Axis, Band, Bar, Colour, Entry, Figure, HAlign, Mark, Marker, Note, Panel, Series, Shape,
    Strip, Stroke, Style, Swatch, Ticks, VAlign,
};
use crate::study::tolerance::{column_label, Cell, ToleranceReport};
use crate::units::{Units, FORCE};

/// The waviness columns' colours, in order.
const COLUMN_COLOURS: [Colour; 6] = [BLUE, RED, GREEN, ORANGE, PURPLE, BROWN];
/// The x offset between two columns' points at one tolerance (so the intervals do not
/// overlap), of the distance between two tolerances.
const COLUMN_OFFSET: f64 = 0.12;
/// A heat map cell's colour value above which its text is white.
const DARK_CELL: f64 = 0.6;
/// The response plot's size, pixels.
const RESPONSE_SIZE: (u32, u32) = (1800, 640);
/// The x axis of the response plot.
const TOLERANCE_AXIS: &str = "cam profile tolerance (the roller's at 1/5 of it)";

/// "1 actual cam" or "N actual cams".
fn cams(samples: u64) -> &'static str {
    if samples == 1 {
        "cam"
    } else {
        "cams"
    }
}

/// A heat map's colour: white (0) to dark red (1); white for none (NaN).
fn heat(t: f64) -> Colour {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    Colour(
        (255.0 - 75.0 * t) as u8,
        (255.0 - 235.0 * t) as u8,
        (255.0 - 225.0 * t) as u8,
    )
}

/// A grid cell's colour (0 to 1, NaN: none) and text: P(jump) (`jump`) or the
/// acceleration RMS sum (`t_acc` its colour, `fa` its unit's factor).
fn grid_cell(c: &Cell, jump: bool, t_acc: f64, fa: f64) -> (f64, String) {
    let p = &c.summary.jump;
    match (
        &c.not_workable,
        jump,
        c.acc_rms_sum_in_per_s2.map(|a| a.in_inch()),
    ) {
        (Some(_), _, _) => (f64::NAN, "not workable".into()),
        (None, true, _) => (p.p, format!("{:.2} [{:.2}, {:.2}]", p.p, p.lo95, p.hi95)),
        (None, false, None) => (f64::NAN, "no statistics".into()),
        (None, false, Some(a)) => (t_acc, format!("{:.0}", fa * a)),
    }
}

/// The heat maps: P(jump) (colour, with its interval written in the cell) and the
/// acceleration RMS (colour on a log scale, value written), tolerance by waviness, in
/// `units`.
pub fn grid(r: &ToleranceReport, units: Units) -> Figure {
    let (theoretical, cells, samples) = (&r.theoretical, &r.cells, r.samples_per_cell);
    let cols = r.columns.max(1);
    let rows = cells.len().div_ceil(cols);
    let (fa, ua) = units.axis(crate::units::ACCELERATION);
    let title = format!(
        "camsim tolerance-study: revolution 2, {samples} actual {} a cell (theoretical cam: sum of acceleration RMS {}, {})",
        cams(samples),
        theoretical
            .acc_rms_sum_in_per_s2
            .map_or("none (no statistics)".into(), |a| {
                format!("{:.0} {ua}", fa * a.in_inch())
            }),
        if theoretical.summary.jump.count > 0 { "jumps" } else { "no jump" }
    );
    let captions = [
        "P(jump) in revolution 2 [95 % Wilson interval]".to_string(),
        format!("sum over the periods of the acceleration RMS deviation, {ua} (colour: log scale)"),
    ];
    let acc: Vec<Option<f64>> = cells
        .iter()
        .map(|c| c.acc_rms_sum_in_per_s2.map(|a| a.in_inch()))
        .collect();
    let t_acc = acc_colours(&acc);
    let panels = captions
        .into_iter()
        .enumerate()
        .map(|(k, caption)| {
            let mut p = heat_panel(cells, cols, rows, units);
            p.caption = Some(caption);
            for (i, c) in cells.iter().enumerate() {
                let (col, row) = ((i % cols) as f64, (rows - 1 - i / cols) as f64);
                let t = t_acc.get(i).copied().unwrap_or(f64::NAN);
                let (t, label) = grid_cell(c, k == 0, t, fa);
                p.bars.push(Bar {
                    x: (col - 0.5, col + 0.5),
                    y: (row - 0.5, row + 0.5),
                    colour: heat(t),
                    edge: Some(BLACK),
                });
                let mut n = Note::new((col, row), label, HAlign::Centre, VAlign::Middle);
                n.colour = if t > DARK_CELL { WHITE } else { BLACK };
                n.large = true;
                p.notes.push(n);
            }
            p
        })
        .collect();
    let mut fig = Figure::new(title, (1600, 260 * rows as u32 + 160), panels);
    fig.columns = 2;
    fig
}

/// Each cell's acceleration RMS (`acc`, none: no statistics) on a log colour scale from
/// the grid's least (0) to its largest (1); 0.5 when they are one value, NaN for none.
fn acc_colours(acc: &[Option<f64>]) -> Vec<f64> {
    let acc: Vec<f64> = acc
        .iter()
        .map(|a| a.map_or(f64::NAN, |a| a.max(1e-9).log10()))
        .collect();
    let (amin, amax) = acc
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    acc.iter()
        .map(|a| {
            if amax > amin {
                (a - amin) / (amax - amin)
            } else {
                0.5
            }
        })
        .collect()
}

/// A heat map's empty panel: a column a waviness, a row a tolerance (the first on top).
fn heat_panel(cells: &[Cell], cols: usize, rows: usize, units: Units) -> Panel {
    let xlabels = (0..cols.min(cells.len()))
        .map(|j| column_label(cells, cols, j))
        .collect();
    let ylabels = cells
        .chunks(cols)
        .rev()
        .map(|r| {
            r.first()
                .map_or(String::new(), |c| tolerance_label(c, units))
        })
        .collect();
    let x = Axis::plain("waviness asked: FPR (achieved: mean of the cams)", "")
        .range(-0.5, cols as f64 - 0.5)
        .ticks(Ticks::Named(xlabels));
    let y = Axis::plain("cam / roller tolerance", "")
        .range(-0.5, rows as f64 - 0.5)
        .ticks(Ticks::Named(ylabels));
    Panel::new(x, y)
}

/// A length in `units`, to four significant digits.
fn length_text(inch: f64, units: Units) -> String {
    let (f, unit) = units.axis(camsim_scene_file::units::LENGTH);
    let v = inch * f;
    let digits = (3 - v.abs().max(1e-300).log10().floor() as i32).clamp(0, 9) as usize;
    let t = format!("{v:.digits$}");
    let t = if t.contains('.') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    };
    format!("{t} {unit}")
}

/// A grid row's tolerances: "±cam / ±roller" in the length unit of `units`.
fn tolerance_label(c: &Cell, units: Units) -> String {
    let cam = length_text(c.cam_tolerance_in.in_inch(), units);
    let roller = length_text(c.roller_tolerance_in.in_inch(), units);
    format!("±{} / ±{roller}", cam.split(' ').next().unwrap_or(&cam))
}

/// A point with its interval: (low, middle, high).
type Whisker = (f64, f64, f64);

/// No point.
const NONE: Whisker = (f64::NAN, f64::NAN, f64::NAN);

/// A cell's P(jump) with its interval (none for a cell that is not workable).
fn jump_whisker(c: &Cell) -> Whisker {
    let p = &c.summary.jump;
    match c.not_workable {
        Some(_) => NONE,
        None => (p.lo95, p.p, p.hi95),
    }
}

/// A response panel: its caption, its y axis, each cell's value and the theoretical
/// cam's (in the inch family).
struct Response {
    caption: String,
    y: Axis,
    value: fn(&Cell) -> Whisker,
}

/// The 5th, 50th and 95th percentiles of a whole-revolution column of a cell.
fn quantiles(c: &Cell, col: &str) -> Whisker {
    c.summary
        .whole_revolution
        .get(col)
        .map_or(NONE, |m| (m.p5, m.p50, m.p95))
}

/// The response panels: P(jump), then the quantiles of each column.
fn responses(samples: u64) -> [Response; 3] {
    let q = |title: &str, unit: Unit, value| {
        let mut y = Axis::of(title, unit);
        y.thousands = true;
        Response {
            caption: format!("{title}: p5, p50, p95"),
            y,
            value,
        }
    };
    [
        Response {
            caption: if samples < 2 {
                "P(jump), revolution 2 (1 cam a cell: use --samples)".into()
            } else {
                "P(jump) in revolution 2".into()
            },
            y: Axis::plain("P(jump)", "")
                .range(0.0, 1.05)
                .ticks(Ticks::Auto(6)),
            value: jump_whisker,
        },
        q("smallest contact force Fc", FORCE, |c| {
            quantiles(c, "contact_force_min")
        }),
        q("largest contact stress", STRESS, |c| {
            quantiles(c, "contact_stress_max")
        }),
    ]
}

/// P(jump) with its 95 % Wilson interval, and the 5th, 50th and 95th percentiles of the
/// smallest contact force and of the largest contact stress in revolution 2, against the
/// cam / roller tolerance (the grid's rows, smallest first), one colour per waviness
/// column; the theoretical cam as a grey dashed line; in `units`.
pub fn response(r: &ToleranceReport, units: Units) -> Figure {
    let (theoretical, cells, samples) = (&r.theoretical, &r.cells, r.samples_per_cell);
    let cols = r.columns.max(1);
    // Rows of the grid, smallest tolerance first (the grid lists the largest first).
    let rows: Vec<&[Cell]> = cells.chunks(cols).rev().collect();
    let names: Vec<String> = rows
        .iter()
        .map(|r| {
            r.first().map_or(String::new(), |c| {
                format!("±{}", length_text(c.cam_tolerance_in.in_inch(), units))
            })
        })
        .collect();
    let panels = responses(samples)
        .into_iter()
        .map(|r| response_panel(r, theoretical, &rows, cols, &names))
        .collect();
    let title = format!(
        "Against the tolerance: revolution 2, {samples} actual {} a cell; dot = P(jump) or median, bar = 95 % Wilson interval or p5-p95",
        cams(samples)
    );
    let mut fig = Figure::new(title, RESPONSE_SIZE, panels);
    fig.columns = 3;
    let mut entries: Vec<Entry> = (0..cols.min(cells.len()))
        .map(|j| Entry {
            swatch: Swatch::Line(Stroke::solid(column_colour(j), 2), Some(Mark::Dot)),
            text: column_label(cells, cols, j),
        })
        .collect();
    entries.push(Entry {
        swatch: Swatch::Line(Stroke::dashed(MID_GREY, 2), None),
        text: "theoretical cam (dashed)".into(),
    });
    fig.strip = Strip::row(entries);
    fig
}

/// Waviness column `j`'s colour.
fn column_colour(j: usize) -> Colour {
    COLUMN_COLOURS
        .get(j % COLUMN_COLOURS.len())
        .copied()
        .unwrap_or(BLUE)
}

/// One response panel: each column's points joined, with their whiskers; the
/// theoretical cam's middle value dashed across.
fn response_panel(
    r: Response,
    theoretical: &Cell,
    rows: &[&[Cell]],
    cols: usize,
    names: &[String],
) -> Panel {
    let n = rows.len();
    let x = Axis::plain(TOLERANCE_AXIS, "")
        .range(-0.5, n as f64 - 0.5)
        .ticks(Ticks::Named(names.to_vec()));
    let Response { caption, y, value } = r;
    let mut p = Panel::new(x, y);
    p.caption = Some(caption);
    let theo = value(theoretical).1;
    if theo.is_finite() {
        p.markers.push(Marker {
            at: At::Y(theo),
            stroke: Some(Stroke::dashed(MID_GREY, 2)),
            text: None,
            label: None,
        });
    }
    for j in 0..cols {
        let offset = (j as f64 - (cols as f64 - 1.0) / 2.0) * COLUMN_OFFSET;
        let col: Vec<(f64, Whisker)> = rows
            .iter()
            .enumerate()
            .filter_map(|(i, row)| row.get(j).map(|c| (i as f64 + offset, value(c))))
            .filter(|(_, w)| w.1.is_finite())
            .collect();
        let c = column_colour(j);
        p.bands.push(Band {
            label: None,
            colour: c,
            alpha: 2.0,
            shape: Shape::Whiskers(col.iter().map(|(x, w)| (*x, w.0, w.2)).collect()),
        });
        p.series.push(Series {
            label: None,
            points: col.iter().map(|(x, w)| (*x, w.1)).collect(),
            style: Style::Line(Stroke::solid(c, 1), Some(Mark::Dot)),
        });
    }
    if p.y.range.is_none() && !has_finite_y(&p) {
        // No cell has statistics: an empty chart on 0 to 1 rather than none.
        p.y = p.y.range(0.0, 1.0);
    }
    p
}

/// Whether any series, whisker or marker of `p` has a finite y.
fn has_finite_y(p: &Panel) -> bool {
    p.series
        .iter()
        .flat_map(|s| s.points.iter().map(|q| q.1))
        .chain(p.markers.iter().filter_map(|m| match m.at {
            At::Y(y) => Some(y),
            At::X(_) => None,
        }))
        .any(f64::is_finite)
}

#[cfg(test)]
mod tests {
    use super::acc_colours;

    /// The colour scale is logarithmic: 10, 100 and 1000 sit at 0, 1/2 and 1; a cell
    /// without statistics has no colour; one value alone sits in the middle.
    #[test]
    fn the_acceleration_colours_are_on_a_log_scale() {
        let t = acc_colours(&[Some(100.0), Some(10.0), None, Some(1000.0)]);
        assert!(
            (t[0] - 0.5).abs() < 1e-12 && t[1] == 0.0 && t[3] == 1.0,
            "{t:?}"
        );
        assert!(t[2].is_nan());
        assert_eq!(acc_colours(&[Some(5.0), Some(5.0)]), vec![0.5, 0.5]);
    }
}
