//! A study's named statistics ([`Columns`]: the per-period columns of `camsim run`'s
//! table, the whole revolution's and the profiles') and the quantity of each
//! ([`column_dimension`]): in a report's JSON each column's numbers are one `Measures` of its
//! quantity, so its key is named by its unit (`contact_force_min_lb`, `_n`) and SI
//! converts them.

use serde::{ser::SerializeMap, Serialize, Serializer};

use crate::stats::stream::Moments;
use crate::units::measure::{kind, Kind, Measures};
use camsim_scene_file::units::Unit;

/// Named statistics in a fixed order (a JSON object in that order).
#[derive(Clone, Debug, PartialEq)]
pub struct Columns(pub Vec<(String, Moments)>);

impl Serialize for Columns {
    /// Each column's moments, as measures of its quantity where it has one.
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            entry(&mut m, k, v, column_dimension(k))?;
        }
        m.end()
    }
}

/// The map entry `key: v`, `v`'s numbers (inch-family values) one `Measures` of
/// `dimension` where it has one: its key named by the unit, SI converting them.
pub fn entry<M: SerializeMap, T: Serialize + Copy>(
    m: &mut M,
    key: &str,
    v: &T,
    dimension: Option<Dimension>,
) -> std::result::Result<(), M::Error> {
    use Dimension as D;
    match dimension {
        Some(D::Length) => m.serialize_entry(key, &measures::<kind::Length, T>(v)),
        Some(D::Speed) => m.serialize_entry(key, &measures::<kind::Speed, T>(v)),
        Some(D::Acceleration) => m.serialize_entry(key, &measures::<kind::Acceleration, T>(v)),
        Some(D::Torque) => m.serialize_entry(key, &measures::<kind::Torque, T>(v)),
        Some(D::Force) => m.serialize_entry(key, &measures::<kind::Force, T>(v)),
        Some(D::Stress) => m.serialize_entry(key, &measures::<kind::Stress, T>(v)),
        None => m.serialize_entry(key, v),
    }
}

/// `v` (inch-family values) as measures of quantity `K`.
fn measures<K: Kind, T: Copy>(v: &T) -> Measures<K, T> {
    Measures::inch(*v)
}

impl Columns {
    /// The statistics of `name`, if present.
    pub fn get(&self, name: &str) -> Option<&Moments> {
        self.0.iter().find(|(k, _)| k == name).map(|(_, m)| m)
    }
}

/// The quantity of a column with a unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// in, mm.
    Length,
    /// in/s, mm/s.
    Speed,
    /// in/s², mm/s².
    Acceleration,
    /// lb in, N m.
    Torque,
    /// lb, N.
    Force,
    /// psi, MPa.
    Stress,
}

impl Dimension {
    /// Its unit in both families.
    pub fn unit(self) -> Unit {
        use crate::units::{ACCELERATION, FORCE, LENGTH, SPEED, STRESS, TORQUE};
        match self {
            Dimension::Length => LENGTH,
            Dimension::Speed => SPEED,
            Dimension::Acceleration => ACCELERATION,
            Dimension::Torque => TORQUE,
            Dimension::Force => FORCE,
            Dimension::Stress => STRESS,
        }
    }
}

/// The quantity of column `col` (of `crate::study::montecarlo::COLUMNS`,
/// `crate::stats::study::REVOLUTION_COLUMNS` or the profiles'); `None` for a
/// dimensionless one (`aord_*`, `fpr`) or a count (`steps`).
pub fn column_dimension(col: &str) -> Option<Dimension> {
    match col {
        "rms_displacement" | "rms_deviation_in" => Some(Dimension::Length),
        "rms_velocity" => Some(Dimension::Speed),
        "rms_acceleration" | "acc_rms_sum" => Some(Dimension::Acceleration),
        "torque_avg" | "torque_max" | "torque_min" => Some(Dimension::Torque),
        "contact_force_min" | "contact_force_max" | "contact_force_avg" => Some(Dimension::Force),
        "contact_stress_max" => Some(Dimension::Stress),
        _ => None,
    }
}
