//! `design spring`'s text and JSON: the answer, its bracket, the spring to build with its
//! checks, and the `[design.spring]` lines that describe it as a scene.

use super::part::PartReport;
use super::{Searched, SpringReport};
use crate::report::Report;
use crate::units::{self, Kind, Length, Measure, Units};

impl Report for SpringReport {
    fn json(&self) -> serde_json::Result<String> {
        crate::report::sorted_pretty_json(self)
    }
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        spring_headline(self, &mut out, units);
        let _ = writeln!(out, "  criterion: {}", self.criterion);
        if let (Some(j), Some(b)) = (self.jump_onset_rpm, self.jump_onset_bracket_rpm) {
            let _ = writeln!(
                out,
                "  check: its jump onset is {j:.1} rpm (bracket {b:.1} rpm), {:+.1} % over {:.1} rpm",
                100.0 * (j / self.operating_rpm - 1.0),
                self.operating_rpm
            );
        }
        if let (Some(p), Some(n)) = (&self.p_jump, self.samples) {
            let _ = writeln!(
                out,
                "  P(jump) at the chosen rate: {} of {n}: {} (95 % Wilson)",
                p.count,
                p.text(4)
            );
        }
        if let Some(p) = &self.part {
            part_lines(&mut out, p, units);
            if self.searched == Searched::PreloadLength {
                let _ = writeln!(
                    out,
                    "    and in [design]: spring_preload_length_{} = {}",
                    units.key_suffix(units::LENGTH),
                    units.show(p.preload_length_in, 4)
                );
            }
        }
        let _ = writeln!(out, "  model: {}", self.model);
        let _ = match (&self.rates_tried_lb_per_in, &self.preload_lengths_tried_in) {
            (_, Some(t)) => writeln!(
                out,
                "  preload lengths tried ({}, + passes): {}",
                units.symbol(units::LENGTH),
                tried_text(t, 3, units)
            ),
            (t, None) => writeln!(
                out,
                "  rates tried ({}, + passes): {}",
                units.symbol(units::STIFFNESS),
                tried_text(t.as_deref().unwrap_or_default(), 1, units)
            ),
        };
        let _ = writeln!(
            out,
            "  {} model runs of 2 revolutions, {:.1} s",
            self.model_runs, self.wall_s
        );
        out
    }
}

/// The values a search tried with their sign: `+` passes, `-` fails.
fn tried_text<K: Kind>(tried: &[(Measure<K>, bool)], decimals: usize, units: Units) -> String {
    let signed: Vec<String> = tried
        .iter()
        .map(|(x, ok)| {
            format!(
                "{}{}",
                units.show(*x, decimals),
                if *ok { "+" } else { "-" }
            )
        })
        .collect();
    signed.join(" ")
}

/// The first lines of the spring search's text: the answer and its bracket. The rate it
/// gives is the built spring's own (its wire, coil and coils: the `[design.spring]` lines
/// below), beside the least rate the search found.
fn spring_headline(r: &SpringReport, out: &mut String, units: Units) {
    use std::fmt::Write;
    let ku = units.symbol(units::STIFFNESS);
    let rate = r
        .part
        .as_ref()
        .map_or(r.spring_rate_lb_per_in, |p| p.spring.rate_lb_per_in);
    if r.searched == Searched::PreloadLength {
        let _ = writeln!(
            out,
            "camsim design spring --preload: preload length {} {lu} at the rate held, {} {ku} {}",
            units.show(r.preload_length_in, 3),
            units.show(rate, 1),
            spring_summary(r, units),
            lu = units.symbol(units::LENGTH),
        );
        preload_bracket_line(r, out, units);
        return;
    }
    let found = match &r.part {
        Some(_) => format!(
            "; the least rate the search found: {} {ku}",
            units.show(r.spring_rate_lb_per_in, 1)
        ),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "camsim design spring: {} {ku} at preload length {} {} {}{found}",
        units.show(rate, 1),
        units.given(units::LENGTH, r.preload_length_in.in_inch()),
        units.symbol(units::LENGTH),
        spring_summary(r, units),
    );
    let _ = match r.failing_rate_lb_per_in {
        Some(b) => writeln!(
            out,
            "  bracket: fails at {} {ku}, passes at {} {ku} (width {} {ku})",
            units.show(b, 1),
            units.show(r.spring_rate_lb_per_in, 1),
            units.show(r.bracket_lb_per_in, 2),
        ),
        None => writeln!(
            out,
            "  the first rate tried passes: any rate up to it may do"
        ),
    };
}

/// The answer's spring in brackets: its preload, coils, mass and surge.
fn spring_summary(r: &SpringReport, units: Units) -> String {
    format!(
        "(preload {} {}; {:.2} active coils, {} {}, surge {:.0} Hz)",
        units.show(r.preload_lb, 2),
        units.symbol(units::FORCE),
        r.active_coils,
        units.show(r.spring_mass_lb, 4),
        units.symbol(units::WEIGHT),
        r.surge_hz,
    )
}

/// The preload search's bracket line.
fn preload_bracket_line(r: &SpringReport, out: &mut String, units: Units) {
    use std::fmt::Write;
    let lu = units.symbol(units::LENGTH);
    let _ = match (r.failing_preload_length_in, r.preload_bracket_in) {
        (Some(b), Some(w)) => writeln!(
            out,
            "  searched: the preload length; bracket: fails at {} {lu}, passes at {} {lu} (width {} {lu})",
            units.show(b, 3),
            units.show(Length::inch(b.in_inch() + w.in_inch()), 3),
            units.show(w, 3),
        ),
        _ => writeln!(
            out,
            "  searched: the preload length; the first length tried passes: any length up to it may do"
        ),
    };
}

/// The binding rule as the part's text gives it: `binding` at `percent` of its limit; or,
/// when contact bound (`binding` is not `limit_rule`: the rate was raised until a buildable
/// spring held contact with its own mass, and `binding` says by how much), the part's
/// own stress and surge use of their limits, percent.
fn binding_text(p: &PartReport) -> String {
    if p.binding == p.limit_rule {
        return format!("{} ({:.0} % of its limit)", p.binding, p.binding_percent);
    }
    let c = &p.spring;
    format!(
        "{}; the part's stress at {:.0} % and surge at {:.0} % of their limits",
        p.binding,
        100.0 * c.shear_stress_psi.in_inch() / c.allowable_shear_psi.in_inch(),
        100.0 * camsim_core::SURGE_HARMONIC_MARGIN / c.surge_harmonic
    )
}

/// The spring to build: the part, its checks, the rule that binds, and the
/// `[design.spring]` lines that describe it in the output's family.
fn part_lines(out: &mut String, p: &PartReport, units: Units) {
    use std::fmt::Write;
    let c = &p.spring;
    let (lu, su) = (units.symbol(units::LENGTH), units.symbol(units::STRESS));
    let _ = writeln!(
        out,
        "  spring to build: {}, wire {} {lu}, mean coil {} {lu} (index {:.1}), {:.2} active / {:.2} total coils, {} ends; rate {} {}, {} {}",
        p.wire,
        units.show(c.wire_diameter_in, 3),
        units.show(c.mean_diameter_in, 3),
        c.index,
        c.active_coils,
        c.total_coils,
        p.ends,
        units.show(c.rate_lb_per_in, 1),
        units.symbol(units::STIFFNESS),
        units.show(c.mass_lb, 4),
        units.symbol(units::WEIGHT)
    );
    let _ = writeln!(
        out,
        "    checks: stress {} {su} at full compression, {:.0} % of the allowable {} {su}; surge {:.0} Hz = {:.1} x the cam (least {:.0}); free length {} {lu}, {} {lu} at full compression above the solid {} {lu}; contact {}",
        units.show(c.shear_stress_psi, 0),
        100.0 * c.shear_stress_psi.in_inch() / c.allowable_shear_psi.in_inch(),
        units.show(c.allowable_shear_psi, 0),
        c.surge_hz,
        c.surge_harmonic,
        camsim_core::SURGE_HARMONIC_MARGIN,
        units.show(c.free_length_in, 3),
        units.show(c.full_compression_length_in, 3),
        units.show(c.solid_height_in, 3),
        if p.contact_checked {
            "checked with its own rate and mass"
        } else {
            "judged at the rate found, with the wire model's mass"
        }
    );
    let _ = writeln!(
        out,
        "    binding: {}; turned away: {} too stiff for {} coils, {} over the stress, {} low surge",
        binding_text(p),
        p.rejected.too_stiff,
        crate::study::coil_spring::MIN_ACTIVE_COILS,
        p.rejected.stress,
        p.rejected.surge
    );
    let k = units.key_suffix(units::LENGTH);
    let _ = writeln!(
        out,
        "    as a scene (these lines in place of the spring rate):\n      [design.spring]\n      wire_diameter_{k} = {}\n      mean_diameter_{k} = {}\n      active_coils = {}\n      ends = \"{}\"\n      material = \"{}\"\n      free_length_{k} = {}",
        scene_length(c.wire_diameter_in.in_inch(), units),
        scene_length(c.mean_diameter_in.in_inch(), units),
        c.active_coils,
        p.ends,
        p.material,
        units.show(c.free_length_in, 4)
    );
}

/// A wire or coil diameter for the scene lines, to 6 significant digits in the output's
/// family: the standard wires are millimetre sizes, so an inch scene needs more than 4
/// decimals for the part it reads back to be the part printed (5.6 mm is 0.220472 in;
/// 0.2205 in would read back as a 0.221 in wire).
fn scene_length(inch: f64, units: Units) -> f64 {
    let v = units.value(units::LENGTH, inch);
    format!("{v:.5e}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::coil_spring::Rejections;
    use crate::study::design::spring::CoilReport;

    /// The binding text (issue 30): a part bound by contact after a raised rate gives its
    /// own stress and surge use (here 500/1000 psi and a surge harmonic of twice the
    /// least), not the stale use of the rule before the raise; an unraised part gives its
    /// rule's.
    #[test]
    fn a_raised_rates_binding_text_gives_the_parts_own_figures() {
        let c: CoilReport = crate::study::coil_spring::CoilChoice {
            wire_diameter_in: 0.1,
            mean_diameter_in: 1.0,
            index: 10.0,
            active_coils: 8.0,
            total_coils: 10.0,
            rate_lb_per_in: 20.0,
            mass_lb: 0.1,
            surge_hz: 100.0,
            surge_harmonic: 2.0 * camsim_core::SURGE_HARMONIC_MARGIN,
            shear_stress_psi: 500.0,
            allowable_shear_psi: 1000.0,
            solid_height_in: 1.0,
            free_length_in: 3.0,
            full_compression_length_in: 2.0,
        }
        .into();
        let mut p = PartReport {
            spring: c,
            wire: "music wire".into(),
            material: "music-wire",
            ends: "squared-ground",
            binding: "contact with the spring's own mass (the rate raised 10 % above the one found, in 2 step(s) of 5 %)".into(),
            limit_rule: "contact (the rate asked)".into(),
            binding_percent: 99.0,
            rejected: Rejections::default(),
            contact_checked: true,
            preload_length_in: Length::inch(0.5),
        };
        let t = binding_text(&p);
        assert!(
            t.ends_with("; the part's stress at 50 % and surge at 50 % of their limits"),
            "{t}"
        );
        assert!(!t.contains("99"), "{t}");
        p.binding = "stress".into();
        p.limit_rule = "stress".into();
        p.binding_percent = 87.0;
        assert_eq!(binding_text(&p), "stress (87 % of its limit)");
    }
}
