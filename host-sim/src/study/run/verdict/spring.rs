//! The return spring: rate, mass, coils and surge against the cam's harmonics; the part's
//! shear stress at full compression and its solid height (judged only for a part the
//! scene gives).

use anyhow::Result;
use camsim_core::{Design, HelicalSpring};
use camsim_scene_file::spring::SpringPart;
use serde::Serialize;

use crate::units::{Force, Length, Stiffness, Stress, Units, Weight};

/// The return spring: the part `[design.spring]` gives, or the wire-and-coil model's
/// spring of the rate (assumed: docs/MODEL.md §5.6).
#[derive(Clone, Debug, Serialize)]
pub struct SpringVerdict {
    /// Rate, lb/in.
    pub rate_lb_per_in: Stiffness,
    /// Mass the model uses, lb (weight).
    pub mass_lb: Weight,
    /// Whether the part is the scene's (`[design.spring]`) or assumed from the rate.
    pub given: bool,
    /// The wire: a named wire's title, or `explicit material values`.
    pub material: String,
    /// End type.
    pub ends: &'static str,
    /// Wire diameter d, in.
    pub wire_diameter_in: Length,
    /// Mean coil diameter D, in.
    pub mean_diameter_in: Length,
    /// Active coils.
    pub active_coils: f64,
    /// Total coils.
    pub total_coils: f64,
    /// Surge frequency, Hz.
    pub surge_hz: f64,
    /// Cam rotation frequency, Hz.
    pub cam_hz: f64,
    /// Surge over the cam frequency: the harmonic of the cam motion at the surge.
    pub surge_harmonic: f64,
    /// The least harmonic ratio accepted without a warning.
    pub least_harmonic: f64,
    /// Spring force at full compression (assembly compression plus the largest lift), lb.
    pub full_compression_force_lb: Force,
    /// Wahl-corrected shear stress at that force, psi.
    pub shear_stress_psi: Stress,
    /// The allowable shear stress, psi.
    pub allowable_shear_psi: Stress,
    /// Solid height, in.
    pub solid_height_in: Length,
    /// Compression at full lift (assembly compression plus the largest lift), in.
    pub full_compression_in: Length,
    /// Free length, in (absent: not given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_length_in: Option<Length>,
    /// The least free length that is not solid at full compression: solid height plus
    /// the full compression, in.
    pub least_free_length_in: Length,
}

impl SpringVerdict {
    /// Whether the spring is solid (or beyond) at full compression: only with a free length.
    pub fn solid(&self) -> Option<bool> {
        self.free_length_in.map(|l| {
            l.in_inch() - self.full_compression_in.in_inch() <= self.solid_height_in.in_inch()
        })
    }
}

/// The spring verdict of `design` at its speed: `part` (the scene's `[design.spring]`),
/// or the wire-and-coil model's spring of the design's rate.
pub fn spring(design: &Design<f64>, part: Option<&SpringPart>) -> Result<SpringVerdict> {
    let (coil, given, material, free_length) = match part {
        Some(p) => (
            p.coil,
            true,
            p.wire.map_or("explicit material values", |w| w.title),
            p.free_length,
        ),
        None => (
            HelicalSpring::of_rate(design.k_rs)?.part(),
            false,
            "VI.1's steel, music wire's allowable",
            None,
        ),
    };
    let cam_hz = camsim_core::rad_per_s_to_rpm(design.omega0) / 60.0;
    let compression = design.delta_rs + design.program.max_lift();
    let force = design.k_rs * compression;
    // The wire model's surge is the rate asked's (its quarter-turn coils differ a little).
    let surge_hz = match part {
        Some(_) => coil.surge_hz(),
        None => HelicalSpring::of_rate(design.k_rs)?.surge_hz,
    };
    Ok(SpringVerdict {
        rate_lb_per_in: Stiffness::inch(design.k_rs),
        mass_lb: Weight::inch(design.m_spring * camsim_core::GRAVITY_IN_PER_S2),
        given,
        material: material.to_string(),
        ends: coil.ends.name(),
        wire_diameter_in: Length::inch(coil.wire_diameter),
        mean_diameter_in: Length::inch(coil.mean_diameter),
        active_coils: coil.active_coils,
        total_coils: coil.total_coils(),
        surge_hz,
        cam_hz,
        surge_harmonic: surge_hz / cam_hz,
        least_harmonic: camsim_core::SURGE_HARMONIC_MARGIN,
        full_compression_force_lb: Force::inch(force),
        shear_stress_psi: Stress::inch(coil.shear_stress(force)),
        allowable_shear_psi: Stress::inch(coil.material.allowable_shear),
        solid_height_in: Length::inch(coil.solid_height()),
        full_compression_in: Length::inch(compression),
        free_length_in: free_length.map(Length::inch),
        least_free_length_in: Length::inch(coil.solid_height() + compression),
    })
}

/// The spring's stress and solid-height warnings: the part's shear stress at full
/// compression over its allowable, the free length too short for full compression. An
/// assumed spring (a rate without `[design.spring]`) is not judged on them: its wire is
/// the model's assumption, not the designer's part.
pub fn spring_part_warnings(spring: &SpringVerdict, units: Units) -> Vec<String> {
    use crate::units as u;
    let mut w = Vec::new();
    if !spring.given {
        return w;
    }
    let su = units.symbol(u::STRESS);
    if spring.shear_stress_psi.in_inch() > spring.allowable_shear_psi.in_inch() {
        w.push(format!(
            "spring shear stress {} {su} at full compression ({} {fu}) exceeds the allowable {} {su} (design.spring): a thicker wire, a smaller coil or a softer spring",
            units.show(spring.shear_stress_psi, 0),
            units.show(spring.full_compression_force_lb, 1),
            units.show(spring.allowable_shear_psi, 0),
            fu = units.symbol(u::FORCE)
        ));
    }
    if spring.solid() == Some(true) {
        w.push(format!(
            "the spring is solid at full compression: free length {} {lu} less the compression {} {lu} is not above the solid height {} {lu} ({}: at least {} {lu})",
            units.q(u::LENGTH, spring.free_length_in.map_or(f64::NAN, Length::in_inch), 3),
            units.show(spring.full_compression_in, 3),
            units.show(spring.solid_height_in, 3),
            key_hint("design.spring.free_length", u::LENGTH, units),
            units.show(spring.least_free_length_in, 3),
            lu = units.symbol(u::LENGTH)
        ));
    }
    w
}

/// A scene key a hint names, in the output's unit family first and the other family's
/// suffix after it: `design.spring.free_length_mm or _in` under `--units si`.
pub fn key_hint(stem: &str, unit: camsim_scene_file::units::Unit, units: Units) -> String {
    let (first, other) = match units {
        crate::units::Units::Inch => (unit.inch, unit.si),
        crate::units::Units::Si => (unit.si, unit.inch),
    };
    format!("{stem}_{first} or _{other}")
}

/// The verdict's spring lines: rate, mass, coils and surge; the part (given, or assumed
/// from the rate); stress at full compression and the solid-height check.
pub fn spring_lines(out: &mut String, s: &SpringVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let (lu, su) = (units.symbol(u::LENGTH), units.symbol(u::STRESS));
    let _ = writeln!(
        out,
        "  spring:    {} {}, {:.2} active coils, {} {}; surge {:.0} Hz = {:.1} x the cam's {:.2} Hz",
        units.show(s.rate_lb_per_in, 1),
        units.symbol(u::STIFFNESS),
        s.active_coils,
        units.show(s.mass_lb, 4),
        units.symbol(u::WEIGHT),
        s.surge_hz,
        s.surge_harmonic,
        s.cam_hz
    );
    let part = format!(
        "wire {} {lu}, mean coil {} {lu}, {:.2} total coils, {} ends, {}",
        units.show(s.wire_diameter_in, 3),
        units.show(s.mean_diameter_in, 3),
        s.total_coils,
        s.ends,
        s.material
    );
    if s.given {
        let _ = writeln!(out, "             [design.spring]: {part}");
    } else {
        let _ = writeln!(
            out,
            "             assumed from the rate (no [design.spring]): {part}"
        );
    }
    // An assumed wire's stress and solid height are shown, not judged: say so on their
    // lines, beside the numbers a reader would otherwise take as a verdict.
    let assumed = if s.given {
        ""
    } else {
        " (the assumed wire's: not judged; give [design.spring], or camsim design spring for one)"
    };
    let _ = writeln!(
        out,
        "             at full compression {} {lu} ({} {}): shear stress {} {su} (Wahl), {:.0} % of the allowable {} {su}{assumed}",
        units.show(s.full_compression_in, 3),
        units.show(s.full_compression_force_lb, 1),
        units.symbol(u::FORCE),
        units.show(s.shear_stress_psi, 0),
        100.0 * s.shear_stress_psi.in_inch() / s.allowable_shear_psi.in_inch(),
        units.show(s.allowable_shear_psi, 0)
    );
    let solid = match s.free_length_in {
        Some(l) => format!(
            "free length {} {lu}: {} {lu} at full compression, {}",
            units.show(l, 3),
            units.q(u::LENGTH, l.in_inch() - s.full_compression_in.in_inch(), 3),
            if s.solid() == Some(true) {
                "SOLID"
            } else {
                "not solid"
            }
        ),
        None => format!(
            "free length not given ({}): at least {} {lu}",
            key_hint("design.spring.free_length", u::LENGTH, units),
            units.show(s.least_free_length_in, 3)
        ),
    };
    let _ = writeln!(
        out,
        "             solid height {} {lu}{}; {solid}",
        units.show(s.solid_height_in, 3),
        if s.given { "" } else { " (the assumed wire's)" }
    );
}
