//! `[design.spring]`: the return spring as a part (docs/MODEL.md §5.6). Its wire and
//! coil diameters, active coils, end type and material give the model's rate and spring
//! mass; the free length, if given, lets the verdict check that the spring is not solid
//! at full compression.
//!
//! The material is a named wire (`music-wire`, `oil-tempered`, `chrome-silicon`,
//! `stainless-302`: camsim-core's `SPRING_WIRES`) or explicit values; an explicit value
//! overrides the named wire's. Lengths and stresses read in either family
//! (`wire_diameter_in` or `_mm`, `shear_modulus_psi` or `_mpa`).

use camsim_core::{spring_key, CoilEnds, CoilSpring, SpringMaterial, SpringWire, SPRING_WIRES};
use serde::{Deserialize, Serialize};

use crate::Error;

/// `[design.spring]` as read (inch family: the reader converts SI keys).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringTable {
    /// Wire diameter d, in.
    pub wire_diameter_in: Option<f64>,
    /// Mean coil diameter D, in.
    pub mean_diameter_in: Option<f64>,
    /// Active coils N_a.
    pub active_coils: Option<f64>,
    /// End type (`plain`, `plain-ground`, `squared`, `squared-ground`; default
    /// `squared-ground`).
    pub ends: Option<CoilEnds>,
    /// A named wire (`music-wire`, `oil-tempered`, `chrome-silicon`, `stainless-302`).
    pub material: Option<String>,
    /// Shear modulus G, psi (instead of the named wire's).
    pub shear_modulus_psi: Option<f64>,
    /// Density, lb·s²/in⁴ (instead of the named wire's).
    pub density_lb_s2_per_in4: Option<f64>,
    /// Allowable shear stress, psi (instead of the named wire's).
    pub allowable_shear_stress_psi: Option<f64>,
    /// Free length L_0, in (optional: without it the verdict gives the least free length).
    pub free_length_in: Option<f64>,
}

/// The spring part of a scene: the coil, its named wire (if any) and its free length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringPart {
    /// The spring.
    pub coil: CoilSpring<f64>,
    /// The named wire it is made of (None: explicit material values).
    pub wire: Option<&'static SpringWire>,
    /// Free length L_0, in.
    pub free_length: Option<f64>,
}

/// The names of the named wires, for errors (`"music-wire", "oil-tempered", ...`).
fn wire_names() -> String {
    SPRING_WIRES
        .iter()
        .map(|w| format!("\"{}\"", w.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl SpringTable {
    /// The part: every dimension given, the material named or given in full; checked by
    /// camsim-core's `CoilSpring::checked`. Errors start with `design.spring.KEY` (inch
    /// family; the reader puts the user's key back).
    pub fn part(&self) -> Result<SpringPart, Error> {
        let need = |v: Option<f64>, key: &str| {
            v.ok_or_else(|| {
                Error::new(format!(
                    "design.{key}{}: missing: [design.spring] needs the wire diameter, the mean coil diameter and the active coils",
                    if key == spring_key::ACTIVE { "" } else { " (or _mm)" }
                ))
            })
        };
        let d = need(self.wire_diameter_in, spring_key::WIRE)?;
        let big_d = need(self.mean_diameter_in, spring_key::MEAN)?;
        let n = need(self.active_coils, spring_key::ACTIVE)?;
        let wire = match &self.material {
            Some(name) => Some(SpringWire::named(name).ok_or_else(|| {
                Error::new(format!(
                    "design.spring.material = \"{name}\": not a named wire: one of {}, or give shear_modulus, density and allowable_shear_stress",
                    wire_names()
                ))
            })?),
            None => None,
        };
        let named = wire.map(|w| w.material(d));
        let value = |given: Option<f64>, of: fn(&SpringMaterial<f64>) -> f64, key: &str| {
            given.or(named.as_ref().map(of)).ok_or_else(|| {
                let si = key
                    .split_once('.')
                    .and_then(|(t, k)| crate::units::si_name(&format!("design.{t}"), k))
                    .unwrap_or_default();
                Error::new(format!(
                    "design.{key} (or {si}): missing: give it, or name a wire with design.spring.material ({})",
                    wire_names()
                ))
            })
        };
        let material = SpringMaterial {
            shear_modulus: value(
                self.shear_modulus_psi,
                |m| m.shear_modulus,
                spring_key::SHEAR,
            )?,
            density: value(
                self.density_lb_s2_per_in4,
                |m| m.density,
                spring_key::DENSITY,
            )?,
            allowable_shear: value(
                self.allowable_shear_stress_psi,
                |m| m.allowable_shear,
                spring_key::ALLOWABLE,
            )?,
        };
        let coil = CoilSpring {
            wire_diameter: d,
            mean_diameter: big_d,
            active_coils: n,
            ends: self.ends.unwrap_or(CoilEnds::SquaredGround),
            material,
        }
        .checked()
        .map_err(|e| crate::refusal("design", e))?;
        if let Some(l) = self.free_length_in {
            if !(l.is_finite() && l > 0.0) {
                return Err(Error::new(format!(
                    "design.spring.free_length_in = {l}: must be positive and finite"
                )));
            }
        }
        Ok(SpringPart {
            coil,
            wire,
            free_length: self.free_length_in,
        })
    }
}
