//! A spring you can build for a rate: `camsim design spring`'s choice of wire, coil and
//! coils (docs/MODEL.md §5.6). Every standard wire diameter (camsim-core's
//! `STANDARD_WIRE_DIAMETERS_MM`) at every spring index C = D/d from 4 to 12 is wound with
//! the most quarter-turn active coils whose rate is at least the rate asked; a candidate
//! passes when its Wahl stress at full compression is within the wire's allowable and its
//! surge is at least `SURGE_HARMONIC_MARGIN` times the cam frequency (the verdict's
//! rules). Its free length is Shigley's L_0 = L_s + (1 + ξ) y_max, so it is not solid at
//! full compression. The candidates come lightest first: the contact check (a
//! simulation with the spring's own mass) takes the first that holds contact.

use camsim_core::{
    CoilEnds, CoilSpring, SpringWire, SPRING_CLASH_ALLOWANCE, SPRING_COIL_STEP, SPRING_INDEX_RANGE,
    STANDARD_WIRE_DIAMETERS_MM, SURGE_HARMONIC_MARGIN,
};
use serde::Serialize;

/// The fewest active coils a chosen spring may have: 2 (fewer and the end coils'
/// seating dominates its rate; Shigley recommends 3 to 15).
pub const MIN_ACTIVE_COILS: f64 = 2.0;

/// What the search holds fixed and what it asks.
#[derive(Clone, Copy, Debug)]
pub struct CoilQuery<'a> {
    /// The least rate, lb/in.
    pub rate: f64,
    /// Compression at full lift: assembly compression plus the largest lift, in.
    pub full_compression: f64,
    /// Cam frequency, Hz.
    pub cam_hz: f64,
    /// The wire.
    pub wire: &'a SpringWire,
    /// End type.
    pub ends: CoilEnds,
    /// Wire and mean coil diameter, in, when the scene's part gives them (only the coils
    /// are searched then).
    pub fixed: Option<(f64, f64)>,
}

/// A candidate spring and its checks.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CoilChoice {
    /// Wire diameter, in.
    pub wire_diameter_in: f64,
    /// Mean coil diameter, in.
    pub mean_diameter_in: f64,
    /// Spring index D/d.
    pub index: f64,
    /// Active coils.
    pub active_coils: f64,
    /// Total coils.
    pub total_coils: f64,
    /// Rate, lb/in.
    pub rate_lb_per_in: f64,
    /// Mass, lb (weight).
    pub mass_lb: f64,
    /// Surge, Hz.
    pub surge_hz: f64,
    /// Surge over the cam frequency.
    pub surge_harmonic: f64,
    /// Wahl stress at full compression, psi.
    pub shear_stress_psi: f64,
    /// The wire's allowable, psi.
    pub allowable_shear_psi: f64,
    /// Solid height, in.
    pub solid_height_in: f64,
    /// Free length L_s + (1 + ξ) y_max, in.
    pub free_length_in: f64,
    /// Length at full compression, in.
    pub full_compression_length_in: f64,
}

impl CoilChoice {
    /// The part as core's spring.
    pub fn coil(&self, q: &CoilQuery) -> CoilSpring<f64> {
        CoilSpring {
            wire_diameter: self.wire_diameter_in,
            mean_diameter: self.mean_diameter_in,
            active_coils: self.active_coils,
            ends: q.ends,
            material: q.wire.material(self.wire_diameter_in),
        }
    }

    /// Each rule's use of its limit: the rate asked over the rate, the stress over the
    /// allowable, the least surge over the surge.
    pub fn utilisation(&self, q: &CoilQuery) -> [(&'static str, f64); 3] {
        [
            ("contact (the rate asked)", q.rate / self.rate_lb_per_in),
            ("stress", self.shear_stress_psi / self.allowable_shear_psi),
            ("surge", SURGE_HARMONIC_MARGIN / self.surge_harmonic),
        ]
    }

    /// The rule closest to its limit, with its use in percent.
    pub fn binding(&self, q: &CoilQuery) -> (&'static str, f64) {
        self.utilisation(q).into_iter().fold(
            ("", f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        )
    }
}

/// How many candidates each rule turned away.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Rejections {
    /// Too few coils for the rate (below [`MIN_ACTIVE_COILS`]).
    pub too_stiff: u32,
    /// Stress above the allowable.
    pub stress: u32,
    /// Surge below the least harmonic.
    pub surge: u32,
}

/// The candidate of wire `d` and coil `big_d` in, if it can make the rate.
fn candidate(q: &CoilQuery, d: f64, big_d: f64, rejected: &mut Rejections) -> Option<CoilChoice> {
    let material = q.wire.material(d);
    // Coils for the rate exactly; the most quarter turns at or below it (rate at least q.rate).
    let exact = material.shear_modulus * d.powi(4) / (8.0 * big_d.powi(3) * q.rate);
    let active = (exact / SPRING_COIL_STEP).floor() * SPRING_COIL_STEP;
    if active.is_nan() || active < MIN_ACTIVE_COILS {
        rejected.too_stiff += 1;
        return None;
    }
    let coil = CoilSpring {
        wire_diameter: d,
        mean_diameter: big_d,
        active_coils: active,
        ends: q.ends,
        material,
    }
    .checked()
    .ok()?;
    let rate = coil.rate();
    let stress = coil.shear_stress(rate * q.full_compression);
    let surge = coil.surge_hz();
    let ok_stress = stress <= material.allowable_shear;
    let ok_surge = surge >= SURGE_HARMONIC_MARGIN * q.cam_hz;
    rejected.stress += u32::from(!ok_stress);
    rejected.surge += u32::from(!ok_surge);
    if !(ok_stress && ok_surge) {
        return None;
    }
    let solid = coil.solid_height();
    let free = solid + (1.0 + SPRING_CLASH_ALLOWANCE) * q.full_compression;
    Some(CoilChoice {
        wire_diameter_in: d,
        mean_diameter_in: big_d,
        index: big_d / d,
        active_coils: active,
        total_coils: coil.total_coils(),
        rate_lb_per_in: rate,
        mass_lb: coil.mass() * camsim_core::GRAVITY_IN_PER_S2,
        surge_hz: surge,
        surge_harmonic: surge / q.cam_hz,
        shear_stress_psi: stress,
        allowable_shear_psi: material.allowable_shear,
        solid_height_in: solid,
        free_length_in: free,
        full_compression_length_in: free - q.full_compression,
    })
}

/// Every passing candidate, lightest first, and the rejections.
pub fn candidates(q: &CoilQuery) -> (Vec<CoilChoice>, Rejections) {
    let mut rejected = Rejections::default();
    let mut out = Vec::new();
    let sizes: Vec<(f64, f64)> = match q.fixed {
        Some(dd) => vec![dd],
        None => {
            let (lo, hi, step) = SPRING_INDEX_RANGE;
            let steps = ((hi - lo) / step).round() as usize;
            STANDARD_WIRE_DIAMETERS_MM
                .iter()
                .map(|mm| mm / 25.4)
                .flat_map(|d| (0..=steps).map(move |i| (d, d * (lo + step * i as f64))))
                .collect()
        }
    };
    for (d, big_d) in sizes {
        if let Some(c) = candidate(q, d, big_d, &mut rejected) {
            out.push(c);
        }
    }
    out.sort_by(|a, b| a.mass_lb.total_cmp(&b.mass_lb));
    (out, rejected)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_candidate_passes_the_verdicts_rules_and_the_lightest_comes_first() {
        let q = CoilQuery {
            rate: 60.0,
            full_compression: 2.0,
            cam_hz: 800.0 / 60.0,
            wire: &camsim_core::SPRING_WIRES[2],
            ends: CoilEnds::SquaredGround,
            fixed: None,
        };
        let (c, r) = candidates(&q);
        assert!(!c.is_empty(), "{r:?}");
        assert!(r.stress > 0 && r.too_stiff > 0, "{r:?}");
        for w in c.windows(2) {
            assert!(w[0].mass_lb <= w[1].mass_lb);
        }
        for x in &c {
            let coil = x.coil(&q);
            // Rate at least the one asked, and the next quarter turn would fall below it.
            assert!(coil.rate() >= 60.0);
            let more = CoilSpring {
                active_coils: x.active_coils + 0.25,
                ..coil
            };
            assert!(more.rate() < 60.0);
            assert!(coil.shear_stress(coil.rate() * 2.0) <= coil.material.allowable_shear);
            assert!(coil.surge_hz() >= 13.0 * 800.0 / 60.0);
            // Free length: solid height plus 1.15 times the working compression.
            assert!((x.free_length_in - coil.solid_height() - 2.3).abs() < 1e-12);
            assert!(x.full_compression_length_in > coil.solid_height());
            assert!((4.0..=12.0).contains(&x.index));
        }
    }
}
