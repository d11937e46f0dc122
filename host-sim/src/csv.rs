//! `--csv FILE`: one row per sample of everything the observer sees, plus the
//! theoretical values, written with the `csv` crate from [`CsvRow`] records into an
//! atomic output ([`crate::output`]): the file appears, complete, only when the run
//! succeeds.

use std::ops::ControlFlow;

use anyhow::{anyhow, Result};
use camsim_core::{Sample, TransDof};
use serde::{Serialize, Serializer};

use crate::output::{AtomicFile, FileTarget};
use crate::sim::RunSpec;
use crate::units::Units;

/// The CSV header: [`CsvRow`]'s field names, units in the names.
pub const HEADER: &str =
    "t_s,revolution,cam_angle_deg,period,theta_c_rad,theta_cp_rad,theta_m_rad,\
omega_c_rad_s,omega_cp_rad_s,omega_m_rad_s,\
y1_in,x1_in,y2_in,x2_in,y3_in,x3_in,y4_in,y5_in,\
v_y1_in_s,v_x1_in_s,v_y2_in_s,v_x2_in_s,v_y3_in_s,v_x3_in_s,v_y4_in_s,v_y5_in_s,\
a_y1_in_s2,a_x1_in_s2,a_y2_in_s2,a_x2_in_s2,a_y3_in_s2,a_x3_in_s2,a_y4_in_s2,a_y5_in_s2,\
lift_in,pressure_angle_deg,k_h_lb_in,surface_radius_in,contact_force_lb,in_contact,\
torque_out_lb_in,torque_drive_lb_in,contact_stress_psi,theory_y_in,theory_v_in_s,theory_a_in_s2";

/// The header in the output's family `units`: [`HEADER`] in inch;
/// in SI every dimensional column with its SI unit, named as the JSON's keys are
/// (`y1_mm`, `v_y1_mm_per_s`, `a_y1_mm_per_s2`, `k_h_n_per_mm`, `torque_out_n_m`,
/// `contact_force_n`, `contact_stress_mpa`).
pub fn header(units: Units) -> String {
    if units == Units::Inch {
        return HEADER.to_string();
    }
    HEADER
        .split(',')
        .map(|c| match column_unit(c) {
            Some((stem, u)) => format!("{stem}_{}", u.si),
            None => c.to_string(),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// A column's stem and unit (`k_h_lb_in` is a stiffness, lb/in; `torque_out_lb_in` a
/// torque, lb in).
fn column_unit(c: &str) -> Option<(&str, camsim_scene_file::units::Unit)> {
    use crate::units as u;
    if let Some(stem) = c.strip_suffix("_lb_in") {
        return Some((
            stem,
            if stem == "k_h" {
                u::STIFFNESS
            } else {
                u::TORQUE
            },
        ));
    }
    [
        ("_in_s2", u::ACCELERATION),
        ("_in_s", u::SPEED),
        ("_in", u::LENGTH),
        ("_lb", u::FORCE),
        ("_psi", u::STRESS),
    ]
    .into_iter()
    .find_map(|(suffix, unit)| c.strip_suffix(suffix).map(|stem| (stem, unit)))
}

/// A number written as Rust's `{:e}`: the shortest digits that read back to the same
/// `f64`, in scientific notation (`8.377580409572782e1`, `0e0`, `-1.5e-7`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sci(pub f64);

impl Serialize for Sci {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(&format_args!("{:e}", self.0))
    }
}

/// A number written with six decimals (`{:.6}`: the cam angle in degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fixed6(pub f64);

impl Serialize for Fixed6 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(&format_args!("{:.6}", self.0))
    }
}

/// One row of `--csv`: the field names are the column names ([`HEADER`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CsvRow {
    /// Time, s.
    pub t_s: Sci,
    /// Revolution, from 1.
    pub revolution: u32,
    /// Cam angle within the revolution, degrees.
    pub cam_angle_deg: Fixed6,
    /// Index of the program segment (period).
    pub period: usize,
    /// Cam angle θ_c (unwrapped), rad.
    pub theta_c_rad: Sci,
    /// Coupling angle θ_cp, rad.
    pub theta_cp_rad: Sci,
    /// Motor angle θ_m, rad.
    pub theta_m_rad: Sci,
    /// Cam speed, rad/s.
    pub omega_c_rad_s: Sci,
    /// Coupling speed, rad/s.
    pub omega_cp_rad_s: Sci,
    /// Motor speed, rad/s.
    pub omega_m_rad_s: Sci,
    /// y1, cam vertical, in.
    pub y1_in: Sci,
    /// x1, cam horizontal, in.
    pub x1_in: Sci,
    /// y2, roller vertical, in.
    pub y2_in: Sci,
    /// x2, roller horizontal, in.
    pub x2_in: Sci,
    /// y3, cantilever vertical, in.
    pub y3_in: Sci,
    /// x3, cantilever horizontal, in.
    pub x3_in: Sci,
    /// y4, follower, in.
    pub y4_in: Sci,
    /// y5, load, in.
    pub y5_in: Sci,
    /// Velocity of y1, in/s.
    pub v_y1_in_s: Sci,
    /// Velocity of x1, in/s.
    pub v_x1_in_s: Sci,
    /// Velocity of y2, in/s.
    pub v_y2_in_s: Sci,
    /// Velocity of x2, in/s.
    pub v_x2_in_s: Sci,
    /// Velocity of y3, in/s.
    pub v_y3_in_s: Sci,
    /// Velocity of x3, in/s.
    pub v_x3_in_s: Sci,
    /// Velocity of y4, in/s.
    pub v_y4_in_s: Sci,
    /// Velocity of y5, in/s.
    pub v_y5_in_s: Sci,
    /// Acceleration of y1, in/s².
    pub a_y1_in_s2: Sci,
    /// Acceleration of x1, in/s².
    pub a_x1_in_s2: Sci,
    /// Acceleration of y2, in/s².
    pub a_y2_in_s2: Sci,
    /// Acceleration of x2, in/s².
    pub a_x2_in_s2: Sci,
    /// Acceleration of y3, in/s².
    pub a_y3_in_s2: Sci,
    /// Acceleration of x3, in/s².
    pub a_x3_in_s2: Sci,
    /// Acceleration of y4, in/s².
    pub a_y4_in_s2: Sci,
    /// Acceleration of y5, in/s².
    pub a_y5_in_s2: Sci,
    /// The cam's commanded lift, in.
    pub lift_in: Sci,
    /// Pressure angle, degrees.
    pub pressure_angle_deg: Sci,
    /// Hertz contact stiffness, lb/in.
    pub k_h_lb_in: Sci,
    /// Cam surface radius of curvature at the contact, in.
    pub surface_radius_in: Sci,
    /// Contact force, lb.
    pub contact_force_lb: Sci,
    /// 1 on the cam, 0 off it.
    pub in_contact: u8,
    /// Output torque on the cam, lb·in.
    pub torque_out_lb_in: Sci,
    /// Torque of the drive, lb·in.
    pub torque_drive_lb_in: Sci,
    /// Maximum Hertz contact stress, psi.
    pub contact_stress_psi: Sci,
    /// Theoretical load displacement, in.
    pub theory_y_in: Sci,
    /// Theoretical load velocity, in/s.
    pub theory_v_in_s: Sci,
    /// Theoretical load acceleration, in/s².
    pub theory_a_in_s2: Sci,
}

impl CsvRow {
    /// The row of sample `s`, its values in `units`.
    pub fn of(s: &Sample<f64>, units: Units) -> Self {
        use TransDof::*;
        let p = &s.point;
        // In the output's family (the inch value itself in inch).
        use crate::units as u;
        let value = |unit, x| units.value(unit, x);
        let pos = |d| Sci(value(u::LENGTH, p.position(d)));
        let vel = |d| Sci(value(u::SPEED, p.velocity(d)));
        let acc = |d| Sci(value(u::ACCELERATION, p.acceleration(d)));
        let (len, force, torque) = (
            |x| Sci(value(u::LENGTH, x)),
            |x| Sci(value(u::FORCE, x)),
            |x| Sci(value(u::TORQUE, x)),
        );
        CsvRow {
            t_s: Sci(p.t),
            revolution: s.revolution,
            cam_angle_deg: Fixed6(s.angle_deg),
            period: s.segment,
            theta_c_rad: Sci(p.theta_c),
            theta_cp_rad: Sci(p.theta_cp),
            theta_m_rad: Sci(p.theta_m),
            omega_c_rad_s: Sci(p.omega_c),
            omega_cp_rad_s: Sci(p.omega_cp),
            omega_m_rad_s: Sci(p.omega_m),
            y1_in: pos(CamY),
            x1_in: pos(CamX),
            y2_in: pos(RollerY),
            x2_in: pos(RollerX),
            y3_in: pos(CantileverY),
            x3_in: pos(CantileverX),
            y4_in: pos(Follower),
            y5_in: pos(Load),
            v_y1_in_s: vel(CamY),
            v_x1_in_s: vel(CamX),
            v_y2_in_s: vel(RollerY),
            v_x2_in_s: vel(RollerX),
            v_y3_in_s: vel(CantileverY),
            v_x3_in_s: vel(CantileverX),
            v_y4_in_s: vel(Follower),
            v_y5_in_s: vel(Load),
            a_y1_in_s2: acc(CamY),
            a_x1_in_s2: acc(CamX),
            a_y2_in_s2: acc(RollerY),
            a_x2_in_s2: acc(RollerX),
            a_y3_in_s2: acc(CantileverY),
            a_x3_in_s2: acc(CantileverX),
            a_y4_in_s2: acc(Follower),
            a_y5_in_s2: acc(Load),
            lift_in: len(p.lift.y),
            pressure_angle_deg: Sci(p.pressure_angle.to_degrees()),
            k_h_lb_in: Sci(value(u::STIFFNESS, p.k_h)),
            surface_radius_in: len(p.surface_radius),
            contact_force_lb: force(p.contact_force),
            in_contact: u8::from(p.in_contact),
            torque_out_lb_in: torque(p.torque_out),
            torque_drive_lb_in: torque(p.torque_drive),
            contact_stress_psi: Sci(value(u::STRESS, s.contact_stress)),
            theory_y_in: len(s.theory.y),
            theory_v_in_s: Sci(value(u::SPEED, s.theory.v)),
            theory_a_in_s2: Sci(value(u::ACCELERATION, s.theory.a)),
        }
    }
}

/// Typical bytes of one row: the reference run's mean (`camsim run --csv`: 281 451 362
/// bytes in 337 062 rows, 835 B), rounded up.
pub const ROW_BYTES: u64 = 850;

/// Accepted double steps per revolution assumed at rtol 1e-6: an upper bound set by the
/// most demanding shipped scene, the printed undamped model from the thesis start
/// (`scenes/undamped-printed.toml`, whose ringing and impacts need short steps; its step
/// count is in docs/FIGURES.md#run), rounded up. The damped reference needs far fewer.
pub const STEPS_PER_REV: f64 = 60_000.0;

/// The rows `--csv` is expected to get for `spec`, before it runs: two samples per
/// accepted England double step (Merson's pair, the default, takes about 1.6 times as many
/// single steps with one sample each: fewer rows), [`STEPS_PER_REV`] steps per revolution at rtol 1e-6, scaled
/// by (1e-6 / rtol)^(1/4) for tighter tolerances (England's method is of fourth order;
/// looser ones do not take fewer steps, the dynamics bound them), at least the
/// 1 / `max_step_fraction_rev` steps the step cap forces and at most the step budget.
///
/// A rough estimate: the steps a run takes depend on its dynamics (a low speed from the
/// thesis start takes up to 7 times more). The bytes written are held to the limit too.
pub fn estimated_rows(spec: &RunSpec) -> u64 {
    let s = &spec.solver;
    let tol = (1e-6 / s.rtol).powf(0.25).max(1.0);
    let steps = (STEPS_PER_REV * tol)
        .max(1.0 / s.max_step_fraction)
        .min(f64::from(s.max_steps_per_rev));
    let rows = 2.0 * steps * f64::from(spec.revolutions);
    if rows.is_finite() && rows > 0.0 {
        rows.ceil() as u64
    } else {
        u64::MAX
    }
}

/// The bytes `--csv` is expected to write for `spec` ([`estimated_rows`] rows of
/// [`ROW_BYTES`] and the header).
pub fn estimated_bytes(spec: &RunSpec) -> u64 {
    rows_bytes(estimated_rows(spec))
}

/// The most rows `--csv` gets on the cam-angle grid `grid` for `spec`: every grid point
/// and every segment start (those on the grid count once) of every revolution.
pub fn grid_rows(spec: &RunSpec, grid: &camsim_core::AngleGrid<f64>) -> u64 {
    let segments = spec.design.program.segments().len() as u64;
    grid.points_per_revolution()
        .saturating_add(segments)
        .saturating_mul(u64::from(spec.revolutions))
}

/// The bytes of `rows` rows of [`ROW_BYTES`] and the header.
pub fn rows_bytes(rows: u64) -> u64 {
    rows.saturating_mul(ROW_BYTES)
        .saturating_add(HEADER.len() as u64 + 1)
}

/// Streams samples as [`CsvRow`]s into an atomic output.
pub struct CsvOut {
    out: csv::Writer<AtomicFile>,
    err: Option<csv::Error>,
    header: bool,
    units: Units,
}

impl CsvOut {
    /// Starts the CSV in `file`, its values in `units` (the header is written with the
    /// first row).
    pub fn new(file: AtomicFile, units: Units) -> Self {
        Self {
            out: csv::WriterBuilder::new()
                .has_headers(false)
                .from_writer(file),
            err: None,
            header: false,
            units,
        }
    }

    /// Writes one sample; after the first write error (a full disk, the size limit)
    /// asks the simulation to stop, and [`CsvOut::into_file`] reports the error.
    pub fn row(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        if self.err.is_some() {
            return ControlFlow::Break(());
        }
        if !self.header {
            // The header in the output's family (the rows' values are converted alike).
            self.header = true;
            if let Err(e) = self.out.write_record(header(self.units).split(',')) {
                self.err = Some(e);
                return ControlFlow::Break(());
            }
        }
        match self.out.serialize(CsvRow::of(s, self.units)) {
            Ok(()) => ControlFlow::Continue(()),
            Err(e) => {
                self.err = Some(e);
                ControlFlow::Break(())
            }
        }
    }

    /// The written file, flushed and ready for its [`AtomicFile::commit`] (which
    /// replaces the target), or the first write error (dropped, the temporary is removed
    /// and the target untouched).
    pub fn into_file(mut self) -> Result<AtomicFile> {
        // Write errors stay I/O errors (their kind tells a closed pipe, which ends the
        // command quietly, from a full disk).
        if let Some(e) = self.err.take() {
            if !e.is_io_error() {
                return Err(anyhow!("{e}"));
            }
            return Err(match e.into_kind() {
                csv::ErrorKind::Io(io) => io.into(),
                _ => anyhow!("CSV write failed"),
            });
        }
        self.out.flush()?;
        self.out
            .into_inner()
            .map_err(|e| anyhow!(std::io::Error::new(e.error().kind(), e.error().to_string())))
    }
}

/// `--csv`'s rows: on the solver's samples (`--csv-every-step`) or on the cam-angle grid.
pub struct CsvRows {
    /// The CSV (None: no `--csv`).
    pub csv: Option<CsvOut>,
    /// One row per solver sample instead of one per grid point.
    pub every_step: bool,
}

impl CsvRows {
    /// `--csv`'s rows into `target`, opened now (None: no `--csv`), one a solver sample
    /// with `every_step`, in `units`.
    pub fn open(target: Option<FileTarget>, every_step: bool, units: Units) -> Result<Self> {
        Ok(CsvRows {
            csv: target
                .map(|t| t.open().map(|f| CsvOut::new(f, units)))
                .transpose()?,
            every_step,
        })
    }

    /// The file written, to commit (None: no `--csv`).
    pub fn finish(self) -> Result<Option<AtomicFile>> {
        self.csv.map(CsvOut::into_file).transpose()
    }
}

impl camsim_core::Observer<f64> for CsvRows {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        match self.csv.as_mut().filter(|_| self.every_step) {
            Some(c) => c.row(s),
            None => ControlFlow::Continue(()),
        }
    }
    fn observe_grid(&mut self, s: &Sample<f64>, _: camsim_core::GridPointKind) -> ControlFlow<()> {
        match self.csv.as_mut().filter(|_| !self.every_step) {
            Some(c) => c.row(s),
            None => ControlFlow::Continue(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_fields_are_the_documented_header() {
        let row = CsvRow::of(&Sample::<f64>::default(), Units::Inch);
        let mut w = csv::Writer::from_writer(Vec::new());
        w.serialize(row).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some(HEADER));
        assert_eq!(HEADER.split(',').count(), 46);
        assert_eq!(lines.next().map(|l| l.split(',').count()), Some(46));
    }

    /// One value as a CSV field.
    fn field<T: Serialize>(v: T) -> String {
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(Vec::new());
        w.serialize(v).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        text.trim_end().to_string()
    }

    #[test]
    fn numbers_are_written_as_before() {
        assert_eq!(field(Sci(83.77580409572782)), "8.377580409572782e1");
        assert_eq!(field(Sci(0.0)), "0e0");
        assert_eq!(field(Sci(-0.0)), "-0e0");
        assert_eq!(field(Sci(1.875e-8)), "1.875e-8");
        assert_eq!(field(Sci(f64::NAN)), "NaN");
        assert_eq!(field(Fixed6(0.00009)), "0.000090");
        assert_eq!(field(Fixed6(359.9999996)), "360.000000");
    }

    #[test]
    fn the_estimate_follows_revolutions_tolerance_and_the_step_cap() {
        let mut spec = RunSpec::reference();
        // 3 revolutions of 120 000 samples.
        assert_eq!(estimated_rows(&spec), 360_000);
        assert_eq!(
            estimated_bytes(&spec),
            360_000 * ROW_BYTES + HEADER.len() as u64 + 1
        );
        spec.revolutions = 16;
        assert_eq!(estimated_rows(&spec), 16 * 120_000);
        // 10^4 times tighter: 10 times the steps; looser: no fewer.
        spec.solver.rtol = 1e-10;
        assert!(estimated_rows(&spec).abs_diff(16 * 1_200_000) <= 1);
        spec.solver.rtol = 1e-3;
        assert_eq!(estimated_rows(&spec), 16 * 120_000);
        // A step cap of 1e-6 revolution forces 10^6 steps; the budget bounds them.
        spec.solver.max_step_fraction = 1e-6;
        assert_eq!(estimated_rows(&spec), 16 * 2_000_000);
        spec.solver.max_steps_per_rev = 500_000;
        assert_eq!(estimated_rows(&spec), 16 * 1_000_000);
    }
}
