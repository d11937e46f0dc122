//! The run's figures drawn to pixels: jump shading, curves and their clipping.

use anyhow::{anyhow, Result};
use camsim_core::JumpInterval;

use super::tests::synthetic;
use super::*;
use crate::plot::axis::AngleAxis;

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
    let col = |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
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
    let col = |deg: f64| xr.start + ((deg / 720.0) * f64::from(xr.end - xr.start)).round() as i32;
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
