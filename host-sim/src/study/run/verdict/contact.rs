//! Does contact hold: the separations in the judged revolutions (bursts of bounces
//! merged per period), the start transient's, and the smallest contact force.

use anyhow::Result;
use camsim_core::Design;
use serde::Serialize;

use super::{at_text, At, Watch};
use crate::units::{Force, Units};

/// One separation in the steady revolutions.
#[derive(Clone, Debug, Serialize)]
pub struct Separation {
    /// Revolution of the lift-off.
    pub revolution: u32,
    /// The period it starts in.
    pub period: String,
    /// Cam angle of the lift-off, degrees.
    pub from_deg: f64,
    /// Cam angle of the landing, degrees.
    pub to_deg: f64,
    /// Time off the cam, ms.
    pub duration_ms: f64,
}

/// Does contact hold.
#[derive(Clone, Debug, Serialize)]
pub struct ContactVerdict {
    /// True when the follower never leaves the cam in the judged revolutions.
    pub holds: bool,
    /// The revolutions judged (first, last).
    pub revolutions: [u32; 2],
    /// The separations in them (bursts of bounces merged per period).
    pub separations: Vec<Separation>,
    /// Cam angle off the cam in all of them, degrees.
    pub off_cam_deg: f64,
    /// Separations in revolution 1 before the judged ones (the start transient).
    pub start_transient_separations: usize,
    /// Smallest contact force while in contact, lb.
    pub min_contact_force_lb: Force,
    /// Where.
    pub min_contact_force_at: At,
    /// The period of the smallest contact force.
    pub min_contact_force_period: String,
}

/// The contact verdict from the run's jumps and watch.
pub fn contact(
    design: &Design<f64>,
    jumps: &[JumpRow],
    periods: &[&'static str],
    watch: &Watch,
    revolutions: u32,
) -> Result<ContactVerdict> {
    let rpm = camsim_core::rad_per_s_to_rpm(design.omega0);
    let from = watch.from_revolution;
    let mut separations: Vec<Separation> = Vec::new();
    let mut off = 0.0;
    let mut transient = 0;
    let ms_per_deg = 60_000.0 / (360.0 * rpm);
    let mut last_key: Option<(u32, usize)> = None;
    for j in jumps {
        if j.revolution < from {
            transient += 1;
            continue;
        }
        off += j.end_deg - j.start_deg;
        let period = periods.get(j.period).copied().unwrap_or("?").to_string();
        match separations.last_mut() {
            Some(s) if last_key == Some((j.revolution, j.period)) => {
                s.to_deg = j.end_deg;
                s.duration_ms += (j.end_deg - j.start_deg) * ms_per_deg;
            }
            _ => separations.push(Separation {
                revolution: j.revolution,
                period,
                from_deg: j.start_deg,
                to_deg: j.end_deg,
                duration_ms: (j.end_deg - j.start_deg) * ms_per_deg,
            }),
        }
        last_key = Some((j.revolution, j.period));
    }
    let (f, at) = watch.min_force.ok_or_else(|| {
        anyhow::anyhow!("the follower was never on the cam in the judged revolutions")
    })?;
    let seg = design.program.segment_at(at.cam_angle_deg.to_radians());
    Ok(ContactVerdict {
        holds: separations.is_empty(),
        revolutions: [from, revolutions],
        separations,
        off_cam_deg: off,
        start_transient_separations: transient,
        min_contact_force_lb: Force::inch(f),
        min_contact_force_at: at,
        min_contact_force_period: periods.get(seg).copied().unwrap_or("?").to_string(),
    })
}

/// The verdict's heading and contact lines: whether contact holds and its smallest force,
/// or where the follower leaves the cam; the start transient's separations, not judged.
pub(super) fn contact_lines(out: &mut String, c: &ContactVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "VERDICT (revolutions {}-{})",
        c.revolutions[0], c.revolutions[1]
    );
    if c.holds {
        let _ = writeln!(
            out,
            "  contact:   HOLDS; smallest contact force {} {} at {} ({})",
            units.show(c.min_contact_force_lb, 2),
            units.symbol(u::FORCE),
            at_text(&c.min_contact_force_at),
            c.min_contact_force_period
        );
    } else {
        let _ = writeln!(
            out,
            "  contact:   the follower LEAVES the cam ({:.2} deg of cam angle off it); smallest force in contact {} {} at {}",
            c.off_cam_deg,
            units.show(c.min_contact_force_lb, 2),
            units.symbol(u::FORCE),
            at_text(&c.min_contact_force_at)
        );
        for s in &c.separations {
            let _ = writeln!(
                out,
                "             revolution {}, {}: off from {:.2} to {:.2} deg, {:.3} ms",
                s.revolution, s.period, s.from_deg, s.to_deg, s.duration_ms
            );
        }
    }
    if c.start_transient_separations > 0 && c.revolutions[0] > 1 {
        let _ = writeln!(
            out,
            "             (revolution 1, the start transient, separated {} time(s): not judged)",
            c.start_transient_separations
        );
    }
}

/// One separation interval (the JSON `jumps` entries).
#[derive(Clone, Debug, Serialize)]
pub struct JumpRow {
    /// Revolution of the onset, from 1.
    pub revolution: u32,
    /// Cam angle of the onset within that revolution, degrees.
    pub start_deg: f64,
    /// Cam angle of the landing, degrees (on the onset revolution's scale).
    pub end_deg: f64,
    /// Index of the period of the onset (text only).
    #[serde(skip)]
    pub period: usize,
}
