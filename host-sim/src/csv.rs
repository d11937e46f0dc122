//! `--csv FILE`: one row per sample of everything the observer sees, plus the theoretical values.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use camsim_core::Sample;

/// The CSV header (units in the column names).
pub const HEADER: &str =
    "t_s,revolution,cam_angle_deg,period,theta_c_rad,theta_cp_rad,theta_m_rad,\
omega_c_rad_s,omega_cp_rad_s,omega_m_rad_s,\
y1_in,x1_in,y2_in,x2_in,y3_in,x3_in,y4_in,y5_in,\
v_y1_in_s,v_x1_in_s,v_y2_in_s,v_x2_in_s,v_y3_in_s,v_x3_in_s,v_y4_in_s,v_y5_in_s,\
a_y1_in_s2,a_x1_in_s2,a_y2_in_s2,a_x2_in_s2,a_y3_in_s2,a_x3_in_s2,a_y4_in_s2,a_y5_in_s2,\
lift_in,pressure_angle_deg,k_h_lb_in,surface_radius_in,contact_force_lb,in_contact,\
torque_out_lb_in,torque_drive_lb_in,contact_stress_psi,theory_y_in,theory_v_in_s,theory_a_in_s2";

/// Streams samples to a CSV file.
pub struct CsvWriter {
    out: BufWriter<File>,
    path: PathBuf,
    err: Option<std::io::Error>,
}

impl CsvWriter {
    /// Creates (truncates) the file and writes the header.
    pub fn create(path: &Path) -> Result<Self> {
        let f = File::create(path)
            .with_context(|| format!("--csv {}: cannot create the file", path.display()))?;
        let mut out = BufWriter::new(f);
        writeln!(out, "{HEADER}")?;
        Ok(Self {
            out,
            path: path.to_owned(),
            err: None,
        })
    }

    /// Writes one sample (the first I/O error is kept and reported by `finish`).
    pub fn row(&mut self, s: &Sample<f64>) {
        if self.err.is_some() {
            return;
        }
        let p = &s.point;
        let mut line = format!(
            "{:e},{},{:.6},{},{:e},{:e},{:e},{:e},{:e},{:e}",
            p.t,
            s.revolution,
            s.angle_deg,
            s.segment,
            p.theta_c,
            p.theta_cp,
            p.theta_m,
            p.omega_c,
            p.omega_cp,
            p.omega_m
        );
        for v in p.pos.iter().chain(p.vel.iter()).chain(p.acc.iter()) {
            line.push_str(&format!(",{v:e}"));
        }
        line.push_str(&format!(
            ",{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e},{:e}",
            p.lift.y,
            p.pressure_angle.to_degrees(),
            p.k_h,
            p.surface_radius,
            p.contact_force,
            p.in_contact as u8,
            p.torque_out,
            p.torque_drive,
            s.contact_stress,
            s.theory.y,
            s.theory.v,
            s.theory.a
        ));
        if let Err(e) = writeln!(self.out, "{line}") {
            self.err = Some(e);
        }
    }

    /// Flushes and reports any write error.
    pub fn finish(mut self) -> Result<()> {
        if let Some(e) = self.err.take() {
            return Err(e).with_context(|| format!("--csv {}: write failed", self.path.display()));
        }
        self.out
            .flush()
            .with_context(|| format!("--csv {}: write failed", self.path.display()))
    }
}
