//! The plots of a Monte Carlo study (`camsim montecarlo --plot DIR`), drawn from the
//! streamed statistics' histograms: the cams that kept contact and those that jumped
//! stacked in two colours, and P(jump) with its 95 % Wilson interval.

use super::charts::{histograms, probabilities, HistPanel, ProbBar, ALL, HELD, JUMPED};
use crate::figure::Figure;
use crate::stats::stream::Stream;
use crate::stats::Probability;
use crate::study::montecarlo::{StudyStats, COLUMNS, REVOLUTION_COLUMNS};
use crate::units::{Units, ACCELERATION, FORCE};
use camsim_scene_file::units::Unit;

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 3] = ["histograms.png", "period_histograms.png", "p_jump.png"];

/// A column's panel caption, its quantity on the x axis and its unit (`None`:
/// dimensionless).
fn quantity(col: &str) -> (&'static str, &'static str, Option<Unit>) {
    use camsim_scene_file::units::{LENGTH, STRESS, TORQUE};
    match col {
        "acc_rms_sum" => (
            "Σ acceleration RMS",
            "acceleration RMS summed over the periods",
            Some(ACCELERATION),
        ),
        "rms_acceleration" => ("acceleration RMS", "acceleration RMS", Some(ACCELERATION)),
        "contact_force_min" => ("smallest Fc", "smallest contact force Fc", Some(FORCE)),
        "contact_force_max" => ("largest Fc", "largest contact force Fc", Some(FORCE)),
        "torque_max" => ("largest torque", "largest drive torque", Some(TORQUE)),
        "torque_min" => ("smallest torque", "smallest drive torque", Some(TORQUE)),
        "contact_stress_max" => ("largest stress", "largest contact stress", Some(STRESS)),
        "fpr" => ("waviness FPR", "waviness FPR", None),
        "rms_deviation_in" => (
            "RMS lift deviation",
            "RMS lift deviation from the design",
            Some(LENGTH),
        ),
        _ => ("", "", None),
    }
}

/// A column's factor on its inch-family values and its unit (for a panel's note), in
/// `units`.
fn axis_unit(col: &str, units: Units) -> (f64, String) {
    quantity(col)
        .2
        .map_or((1.0, String::new()), |u| units.axis(u))
}

/// A histogram's data: every sample (`all`) and the samples that jumped (`jumped`,
/// none: no split), over `bins` bins; `n` samples.
struct Histogram<'a> {
    all: &'a Stream,
    jumped: Option<&'a Stream>,
    bins: usize,
    n: u64,
}

/// A panel of `h.all` (every sample) with `h.jumped` (the samples that jumped) stacked
/// on the held ones, over `h.bins` bins of `all`'s range; its note in `units`.
fn panel(caption: String, col: &str, h: Histogram, units: Units) -> HistPanel {
    let Histogram {
        all,
        jumped,
        bins,
        n,
    } = h;
    let split = jumped.is_some();
    let (lo, hi, counts) = all.display_bins(bins);
    let jumped = jumped.map_or_else(|| vec![0; counts.len()], |j| j.counts_over(lo, hi, bins));
    let held = counts
        .iter()
        .zip(&jumped)
        .map(|(a, j)| a.saturating_sub(*j))
        .collect();
    let (_, q, quantity_unit) = quantity(col);
    let (factor, unit) = axis_unit(col, units);
    let note = all.range().filter(|(a, b)| a == b).map(|(v, _)| {
        let v = v * factor;
        let lost = if col.starts_with("contact_force_min") && v <= 0.0 {
            ": contact lost"
        } else {
            ""
        };
        format!(
            "all {n} cams at {} {unit}{lost}",
            crate::plot::fmt_tick(v, v.abs())
        )
    });
    HistPanel {
        caption,
        quantity: q.to_string(),
        unit: quantity_unit,
        lo,
        hi,
        held,
        colour: if split { HELD } else { ALL },
        jumped,
        note,
    }
}

/// The bars of the P(jump) chart: every period's, then the whole revolution's (the
/// numbers the report prints).
pub fn jump_bars(stats: &StudyStats) -> Vec<ProbBar> {
    let n = stats.samples;
    stats
        .periods
        .iter()
        .map(|p| ProbBar {
            name: p.period.clone(),
            p: Probability::of(p.jumps, n),
        })
        .chain([ProbBar {
            name: "whole revolution".into(),
            p: Probability::of(stats.jumps, n),
        }])
        .collect()
}

/// The by-period histograms: each period's acceleration RMS, smallest contact force,
/// largest torque and largest stress, over `bins` bins, in `units`.
fn period_panels(stats: &StudyStats, bins: usize, units: Units) -> Vec<HistPanel> {
    let mut panels = Vec::new();
    for col in [
        "rms_acceleration",
        "contact_force_min",
        "torque_max",
        "contact_stress_max",
    ] {
        let c = COLUMNS.iter().position(|x| *x == col);
        for p in &stats.periods {
            if let Some(s) = c.and_then(|c| p.columns.get(c)) {
                let (q, _, _) = quantity(col);
                let h = Histogram {
                    all: s,
                    jumped: c.and_then(|c| p.jumped_columns.get(c)),
                    bins,
                    n: stats.samples,
                };
                let caption = format!("{}: {q}", p.period);
                panels.push(panel(caption, col, h, units));
            }
        }
    }
    panels
}

/// The figures of a study's statistics, in `units`, each with its file name
/// ([`PLOT_FILES`]).
pub fn figures(stats: &StudyStats, revolution: u32, units: Units) -> [(&'static str, Figure); 3] {
    let n = stats.samples;
    let bins = ((n as f64).sqrt().ceil() as usize).clamp(5, 50);
    let legend = [
        (
            HELD,
            format!("kept contact: {} cams", n - stats.jumps.min(n)),
        ),
        (
            JUMPED,
            format!("jumped in revolution {revolution}: {} cams", stats.jumps),
        ),
    ];
    let mut legend_profiles = legend.to_vec();
    legend_profiles.push((ALL, "profiles: every cam".to_string()));
    let mut panels: Vec<HistPanel> = REVOLUTION_COLUMNS
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let all = stats.whole_revolution.get(i)?;
            let (q, _, _) = quantity(c);
            let h = Histogram {
                all,
                jumped: stats.jumped_revolution.get(i),
                bins,
                n,
            };
            Some(panel(format!("revolution {revolution}: {q}"), c, h, units))
        })
        .collect();
    // The profiles are drawn before the run: no jumped/held split.
    for (caption, col, all) in [
        ("profile: waviness FPR", "fpr", &stats.fpr),
        (
            "profile: RMS lift deviation",
            "rms_deviation_in",
            &stats.rms_deviation_in,
        ),
    ] {
        let h = Histogram {
            all,
            jumped: None,
            bins,
            n,
        };
        panels.push(panel(caption.into(), col, h, units));
    }
    let title = format!("{n} actual cams, revolution {revolution}: histograms");
    let whole = histograms(&title, &legend_profiles, "cams", &panels, 4);
    let panels = period_panels(stats, bins, units);
    let title = format!("{n} actual cams, revolution {revolution}, by period: histograms");
    let periods = histograms(&title, &legend, "cams", &panels, stats.periods.len().max(1));
    let title = format!(
        "Probability of a jump in revolution {revolution} over {n} actual cams, by period and over the revolution"
    );
    let jumps = probabilities(&title, "P(jump)", n, &jump_bars(stats));
    let [a, b, c] = PLOT_FILES;
    [(a, whole), (b, periods), (c, jumps)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::study::PeriodStats;

    /// The chart's bars are the report's numbers: each period's jumps of n, then the
    /// revolution's, with the Wilson interval (3 of 10: 0.1078 to 0.6032, the textbook
    /// value; 0 of 10: 0 to 0.2775).
    #[test]
    fn jump_bars_are_the_counts_with_their_wilson_intervals() {
        let stats = StudyStats {
            samples: 10,
            jumps: 3,
            periods: vec![
                PeriodStats {
                    period: "rise".into(),
                    jumps: 0,
                    ..Default::default()
                },
                PeriodStats {
                    period: "return".into(),
                    jumps: 3,
                    ..Default::default()
                },
            ],
            ..Default::default()
        };
        let bars = jump_bars(&stats);
        let names: Vec<&str> = bars.iter().map(|b| b.name.as_str()).collect();
        assert_eq!(names, ["rise", "return", "whole revolution"]);
        let close = |a: f64, b: f64| (a - b).abs() < 5e-5;
        assert_eq!(bars[0].p.count, 0);
        assert!(close(bars[0].p.lo95, 0.0) && close(bars[0].p.hi95, 0.2775));
        for b in &bars[1..] {
            assert_eq!(b.p.count, 3);
            assert!(close(b.p.p, 0.3), "{}", b.p.p);
            assert!(
                close(b.p.lo95, 0.1078) && close(b.p.hi95, 0.6032),
                "{:?}",
                b.p
            );
        }
    }
}
