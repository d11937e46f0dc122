//! Whether the per-period statistics settled, said as a designer reads it: what changed
//! most between the last revolutions, and whether the change dies out.

use serde::Serialize;

use crate::sim::{PeriodRow, SteadyCheck};
use crate::units::Units;

/// Whether the statistics settled, in words.
#[derive(Clone, Debug, Serialize)]
pub struct SteadyVerdict {
    /// False only when the last revolutions' statistics really differ.
    pub settled: bool,
    /// What changed most, by how much, and what that means.
    pub summary: String,
}

/// What a run's steady-state comparison means to a designer. `rows` are the per-period
/// rows of every revolution; `checks` the comparison of each pair of consecutive
/// revolutions from the first, the last pair last.
///
/// The statistics have settled when the last revolution differs from the one before by at
/// most 1 % (of the statistic's largest magnitude over the periods), or when the change is
/// dying out fast enough that what remains after the last revolution is at most 1 %: with
/// the change before it `d1` and the last `d2`, a change that shrinks by `q = d2/d1` a
/// revolution leaves `d2 q / (1 - q)` to come. Separations in the last revolution make every
/// revolution different: not settled, and said so.
pub fn steady(rows: &[PeriodRow], checks: &[SteadyCheck], units: Units) -> Option<SteadyVerdict> {
    let last = checks.last()?;
    let rev = last.compared[1];
    let jumps_last = rows.iter().any(|r| r.revolution == rev && r.jump);
    let d2 = last.max_rel_change;
    let what = describe(rows, last, units);
    if jumps_last {
        return Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: the follower leaves the cam in revolution {rev}, so no two revolutions are alike; {what}"
            ),
        });
    }
    if d2 <= 0.01 {
        return Some(SteadyVerdict {
            settled: true,
            summary: format!("settled: {what}"),
        });
    }
    // The change before the last one, of the same statistic in the same period.
    let before = checks
        .len()
        .checked_sub(2)
        .and_then(|i| checks.get(i))
        .and_then(|c| change_of(rows, c.compared, &last.statistic));
    match before {
        Some(d1) if d1 > d2 => {
            let q = d2 / d1;
            let remaining = d2 * q / (1.0 - q);
            if remaining <= 0.01 {
                Some(SteadyVerdict {
                    settled: true,
                    summary: format!(
                        "settled: {what}; the change shrinks {:.1}-fold a revolution, so about {:.2} % more is to come",
                        1.0 / q,
                        100.0 * remaining
                    ),
                })
            } else {
                Some(SteadyVerdict {
                    settled: false,
                    summary: format!(
                        "NOT settled: {what}; it shrinks only {:.1}-fold a revolution, about {:.1} % more to come: run more revolutions (--revolutions)",
                        1.0 / q,
                        100.0 * remaining
                    ),
                })
            }
        }
        Some(_) => Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: {what}; the change does not shrink from one revolution to the next: run more revolutions (--revolutions), or the response is not periodic"
            ),
        }),
        None => Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: {what}; with only these revolutions it cannot be told whether it is dying out: run more revolutions (--revolutions)"
            ),
        }),
    }
}

/// The designer's name of a statistic and its unit.
fn label(stat: &str) -> (&'static str, Option<camsim_scene_file::units::Unit>) {
    use crate::units as u;
    match stat {
        "rms_displacement" => ("displacement deviation RMS", Some(u::LENGTH)),
        "rms_velocity" => ("velocity deviation RMS", Some(u::SPEED)),
        "rms_acceleration" => ("acceleration deviation RMS", Some(u::ACCELERATION)),
        "torque_avg" => ("average cam torque", Some(u::TORQUE)),
        "contact_force_avg" => ("average contact force", Some(u::FORCE)),
        _ => ("statistic", None),
    }
}

fn value_of(r: &PeriodRow, stat: &str) -> Option<f64> {
    Some(match stat {
        "rms_displacement" => r.rms_displacement.in_inch(),
        "rms_velocity" => r.rms_velocity.in_inch(),
        "rms_acceleration" => r.rms_acceleration.in_inch(),
        "torque_avg" => r.torque_avg.in_inch(),
        "contact_force_avg" => r.contact_force_avg.in_inch(),
        _ => return None,
    })
}

/// The relative change of `statistic` ("period.name") between the revolutions `pair`,
/// on the scale [`crate::sim::steady_check`] uses (its largest magnitude over the periods of
/// both, or its floor).
fn change_of(rows: &[PeriodRow], pair: [u32; 2], statistic: &str) -> Option<f64> {
    let (period, stat) = statistic.split_once('.')?;
    let floor = crate::sim::steady_floor(stat)?;
    let scale = rows
        .iter()
        .filter(|r| r.revolution == pair[0] || r.revolution == pair[1])
        .filter_map(|r| value_of(r, stat))
        .map(f64::abs)
        .fold(floor, f64::max);
    let a = rows
        .iter()
        .find(|r| r.revolution == pair[0] && r.period == period)?;
    let b = rows
        .iter()
        .find(|r| r.revolution == pair[1] && r.period == period)?;
    Some((value_of(a, stat)? - value_of(b, stat)?).abs() / scale)
}

/// "the low dwell's acceleration deviation RMS went from 202 to 218 in/s^2 between
/// revolutions 2 and 3 (3.3 % of its largest value in any period)".
fn describe(rows: &[PeriodRow], c: &SteadyCheck, units: Units) -> String {
    let Some((period, stat)) = c.statistic.split_once('.') else {
        return format!(
            "revolutions {} and {} agree (largest change {:.2} %)",
            c.compared[0],
            c.compared[1],
            100.0 * c.max_rel_change
        );
    };
    let (name, unit) = label(stat);
    let get = |rev: u32| {
        rows.iter()
            .find(|r| r.revolution == rev && r.period == period)
            .and_then(|r| value_of(r, stat))
            .map(|x| unit.map_or(x, |u| units.value(u, x)))
    };
    let unit = unit.map_or("", |u| units.symbol(u));
    match (get(c.compared[0]), get(c.compared[1])) {
        (Some(a), Some(b)) => format!(
            "the largest change from revolution {} to {} is the {} of the {} period, {} to {} {unit} ({:.2} % of its largest value in any period)",
            c.compared[0],
            c.compared[1],
            name,
            period,
            short(a),
            short(b),
            100.0 * c.max_rel_change
        ),
        _ => format!(
            "revolutions {} and {} differ by {:.2} % at most",
            c.compared[0],
            c.compared[1],
            100.0 * c.max_rel_change
        ),
    }
}

/// A number with 4 significant digits, plain where that reads well.
fn short(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-2..1e5).contains(&a) {
        let digits = if a >= 1000.0 {
            0
        } else if a >= 100.0 {
            1
        } else if a >= 10.0 {
            2
        } else {
            3
        };
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}
