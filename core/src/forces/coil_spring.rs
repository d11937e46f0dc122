//! The return spring as a part: a helical compression spring of round wire
//! (Shigley, *Mechanical Engineering Design*, ch. 10; Norton, *Machine Design*, ch. 14).
//!
//! From the wire diameter d, the mean coil diameter D, the active coils N_a, the end
//! type and the material: the rate k = G d⁴ / (8 D³ N_a), the total coils and the solid
//! height (Shigley's table of end types), the mass of the whole spring, the surge
//! frequency of the active coils between fixed ends f = ½ √(k / m_a), and the shear
//! stress at a force F with Wahl's curvature factor,
//! τ = K_W 8 F D / (π d³), K_W = (4C − 1)/(4C − 4) + 0.615/C, C = D/d.
//! Units: inch, pound-force, second (mass lb·s²/in, density lb·s²/in⁴, stress psi).

use crate::{positive, Error, Real, Result};

/// How the spring's ends are finished (Shigley, table "formulas for the dimensional
/// characteristics of compression springs").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum CoilEnds {
    /// Plain ends: no end coils, solid height d (N_t + 1).
    Plain,
    /// Plain and ground: one end coil, solid height d N_t.
    PlainGround,
    /// Squared (closed): two end coils, solid height d (N_t + 1).
    Squared,
    /// Squared and ground: two end coils, solid height d N_t.
    SquaredGround,
}

impl CoilEnds {
    /// Every end type, in the order of the table.
    pub const ALL: [CoilEnds; 4] = [
        CoilEnds::Plain,
        CoilEnds::PlainGround,
        CoilEnds::Squared,
        CoilEnds::SquaredGround,
    ];

    /// The name a scene writes (`squared-ground`).
    pub fn name(self) -> &'static str {
        match self {
            CoilEnds::Plain => "plain",
            CoilEnds::PlainGround => "plain-ground",
            CoilEnds::Squared => "squared",
            CoilEnds::SquaredGround => "squared-ground",
        }
    }

    /// End coils N_e: total coils N_t = N_a + N_e.
    pub fn end_coils<T: Real>(self) -> T {
        match self {
            CoilEnds::Plain => T::ZERO,
            CoilEnds::PlainGround => T::ONE,
            CoilEnds::Squared | CoilEnds::SquaredGround => T::TWO,
        }
    }

    /// Solid height of `total` coils of wire `d`: d (N_t + 1) unground, d N_t ground.
    pub fn solid_height<T: Real>(self, d: T, total: T) -> T {
        match self {
            CoilEnds::Plain | CoilEnds::Squared => d * (total + T::ONE),
            CoilEnds::PlainGround | CoilEnds::SquaredGround => d * total,
        }
    }
}

/// What a spring is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringMaterial<T> {
    /// Shear modulus G, psi.
    pub shear_modulus: T,
    /// Density, lb·s²/in⁴ (weight density over g).
    pub density: T,
    /// Allowable shear stress, psi (the stress the solid-side check compares with).
    pub allowable_shear: T,
}

/// A helical compression spring of round wire.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoilSpring<T> {
    /// Wire diameter d, in.
    pub wire_diameter: T,
    /// Mean coil diameter D, in.
    pub mean_diameter: T,
    /// Active coils N_a.
    pub active_coils: T,
    /// End type.
    pub ends: CoilEnds,
    /// Material.
    pub material: SpringMaterial<T>,
}

/// Scene keys of a spring's fields (relative to `[design.spring]`), for errors.
pub mod spring_key {
    /// Wire diameter.
    pub const WIRE: &str = "spring.wire_diameter_in";
    /// Mean coil diameter.
    pub const MEAN: &str = "spring.mean_diameter_in";
    /// Active coils.
    pub const ACTIVE: &str = "spring.active_coils";
    /// Shear modulus.
    pub const SHEAR: &str = "spring.shear_modulus_psi";
    /// Density.
    pub const DENSITY: &str = "spring.density_lb_s2_per_in4";
    /// Allowable shear stress.
    pub const ALLOWABLE: &str = "spring.allowable_shear_stress_psi";
}

impl<T: Real> CoilSpring<T> {
    /// The spring checked: every dimension and material value positive and finite, and
    /// the coil wider than its wire (spring index C = D/d above 1, where Wahl's factor is
    /// defined). Errors name the `[design.spring]` key.
    pub fn checked(self) -> Result<Self> {
        positive(spring_key::WIRE, self.wire_diameter)?;
        positive(spring_key::MEAN, self.mean_diameter)?;
        positive(spring_key::ACTIVE, self.active_coils)?;
        positive(spring_key::SHEAR, self.material.shear_modulus)?;
        positive(spring_key::DENSITY, self.material.density)?;
        positive(spring_key::ALLOWABLE, self.material.allowable_shear)?;
        if self.mean_diameter <= self.wire_diameter {
            return Err(Error::InvalidParameter {
                field: spring_key::MEAN,
                rule: "must exceed the wire diameter (spring.wire_diameter): the coil is wound around its axis",
                value: self.mean_diameter.to_f64(),
            });
        }
        Ok(self)
    }

    /// Spring index C = D / d.
    pub fn index(&self) -> T {
        self.mean_diameter / self.wire_diameter
    }

    /// Rate k = G d⁴ / (8 D³ N_a), lb/in.
    pub fn rate(&self) -> T {
        let d = self.wire_diameter;
        let big_d = self.mean_diameter;
        self.material.shear_modulus * d * d * d * d
            / (T::from_f64(8.0) * big_d * big_d * big_d * self.active_coils)
    }

    /// Total coils N_t = N_a + N_e.
    pub fn total_coils(&self) -> T {
        self.active_coils + self.ends.end_coils::<T>()
    }

    /// Solid height L_s, in.
    pub fn solid_height(&self) -> T {
        self.ends
            .solid_height(self.wire_diameter, self.total_coils())
    }

    /// Mass of one coil of wire: ρ (π d²/4) (π D), lb·s²/in.
    fn coil_mass(&self) -> T {
        let d = self.wire_diameter;
        self.material.density * (T::PI * d * d / T::from_f64(4.0)) * (T::PI * self.mean_diameter)
    }

    /// Mass of the whole spring (total coils), lb·s²/in.
    pub fn mass(&self) -> T {
        self.coil_mass() * self.total_coils()
    }

    /// Surge frequency, Hz: the first axial mode of the active coils between fixed
    /// ends, f = ½ √(k / m_a).
    pub fn surge_hz(&self) -> T {
        (self.rate() / (self.coil_mass() * self.active_coils)).sqrt() / T::TWO
    }

    /// Wahl's factor K_W = (4C − 1)/(4C − 4) + 0.615/C (C above 1: [`Self::checked`]).
    pub fn wahl_factor(&self) -> T {
        let c = self.index();
        let four_c = T::from_f64(4.0) * c;
        (four_c - T::ONE) / (four_c - T::from_f64(4.0)) + T::from_f64(0.615) / c
    }

    /// Shear stress at axial force `force` lb, psi: τ = K_W 8 F D / (π d³).
    pub fn shear_stress(&self, force: T) -> T {
        let d = self.wire_diameter;
        self.wahl_factor() * T::from_f64(8.0) * force * self.mean_diameter / (T::PI * d * d * d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shigley, *Mechanical Engineering Design* (9th ed.), Example 10-1: no. 16 music wire
    /// (d = 0.037 in, G = 11.85 Mpsi), outside diameter 7/16 in, squared ends, 12.5 total
    /// coils. The book: D = 0.4005 in, C = 10.82, N_a = N_t - 2 = 10.5, solid length
    /// L_s = (N_t + 1) d = 0.500 in, S_ut = 324 kpsi, S_sy = 0.45 S_ut = 146 kpsi. The
    /// rate, mass, surge and Wahl stress below are worked by hand from the closed forms.
    fn example_10_1() -> CoilSpring<f64> {
        CoilSpring {
            wire_diameter: 0.037,
            mean_diameter: 0.4375 - 0.037,
            active_coils: 10.5,
            ends: CoilEnds::Squared,
            material: SpringMaterial {
                shear_modulus: 11.85e6,
                density: 0.284 / 386.09,
                allowable_shear: 146e3,
            },
        }
        .checked()
        .unwrap()
    }

    #[test]
    fn shigley_example_10_1_rate_index_and_solid_length() {
        let s = example_10_1();
        assert!((s.index() - 10.82).abs() < 0.005, "{}", s.index());
        assert!((s.total_coils() - 12.5).abs() < 1e-12);
        // k = G d^4 / (8 D^3 N_a) = 11.85e6 * 1.8742e-6 / (8 * 0.064240 * 10.5) = 4.1156.
        assert!((s.rate() - 4.1156).abs() < 1e-4, "{}", s.rate());
        assert!(
            (s.solid_height() - 0.4995).abs() < 1e-9,
            "{}",
            s.solid_height()
        );
        // Ground ends take d off: d N_t.
        let ground = CoilSpring {
            ends: CoilEnds::SquaredGround,
            ..s
        };
        assert!((ground.solid_height() - 12.5 * 0.037).abs() < 1e-12);
    }

    #[test]
    fn wahl_stress_mass_and_surge_by_hand() {
        let s = example_10_1();
        // K_W at C = 10.8243: (42.297 / 39.297) + 0.615 / 10.8243 = 1.07634 + 0.05682.
        let c = 0.4005 / 0.037;
        let kw = (4.0 * c - 1.0) / (4.0 * c - 4.0) + 0.615 / c;
        assert!((kw - 1.13316).abs() < 1e-4, "{kw}");
        assert!((s.wahl_factor() - kw).abs() < 1e-12);
        // The book's yield load 6.46 lbf (with Bergstrasser's 1.124) at 146 kpsi: with
        // Wahl's factor the same load gives 146 * 1.13316 / 1.124 = 147.2 kpsi.
        let tau = s.shear_stress(6.46);
        let by_hand = 1.13316 * 8.0 * 6.46 * 0.4005 / (std::f64::consts::PI * 0.037f64.powi(3));
        assert!((tau / by_hand - 1.0).abs() < 1e-4, "{tau} {by_hand}");
        assert!((tau / 147.2e3 - 1.0).abs() < 0.005, "{tau}");
        // Mass: 12.5 coils of 0.037 in wire on 0.4005 in: 0.016910 in³ of wire.
        let volume =
            12.5 * (std::f64::consts::PI * 0.037 * 0.037 / 4.0) * (std::f64::consts::PI * 0.4005);
        assert!((volume - 0.0169).abs() < 1e-4, "{volume}");
        assert!((s.mass() * 386.09 / (volume * 0.284) - 1.0).abs() < 1e-12);
        // Surge with both ends fixed: f = (1/2) sqrt(k g / W_a), W_a the active coils'
        // weight (Shigley eq. 10-25): 10.5 of 12.5 coils.
        let w_a = volume * 0.284 * 10.5 / 12.5;
        let f = 0.5 * (s.rate() * 386.09 / w_a).sqrt();
        assert!((s.surge_hz() / f - 1.0).abs() < 1e-12);
        // 0.5 * sqrt(4.1156 * 386.09 / 0.0040340 lb) = 313.8 Hz.
        assert!((s.surge_hz() - 313.8).abs() < 0.05, "{}", s.surge_hz());
    }

    #[test]
    fn a_coil_no_wider_than_its_wire_is_refused() {
        let mut s = example_10_1();
        s.mean_diameter = s.wire_diameter;
        let e = s.checked().unwrap_err();
        assert!(format!("{e}").starts_with("spring.mean_diameter_in = 0.037: must exceed"));
        let mut s = example_10_1();
        s.active_coils = f64::NAN;
        assert!(s.checked().is_err());
    }
}
