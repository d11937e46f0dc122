//! `camsim run`'s `--csv` argument group: the file, its rows (a cam-angle grid, or every
//! solver sample) and the largest file it may write.

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::AngleGrid;

use crate::sim::RunSpec;

/// The default of `--csv-every-deg`: a row every half degree of cam angle.
pub const DEFAULT_CSV_EVERY_DEG: f64 = 0.5;

/// The default of `--max-csv-mb`: 1000 MB = 1 GB.
pub const DEFAULT_MAX_CSV_MB: u64 = 1000;

/// `--csv-every-deg`: a grid step the core's [`camsim_core::AngleGrid`] accepts.
fn csv_every_deg(s: &str) -> Result<f64, String> {
    let x = super::positive_finite(s)?;
    match AngleGrid::new(x) {
        Ok(_) => Ok(x),
        Err(_) => Err("must be between 3.6e-4 and 360 degrees".into()),
    }
}

/// `camsim run`'s CSV of the response.
#[derive(clap::Args, Debug, Clone)]
pub struct CsvArgs {
    /// Write the response to FILE as CSV: one row every --csv-every-deg degrees of cam
    /// angle (written whole at the end of a successful run; an existing FILE needs --force).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// --csv's row spacing, degrees of cam angle (3.6e-4 to 360; default 0.5), plus a row
    /// at every segment's start; taken from the solver's continuous output, as accurate as
    /// its steps.
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_CSV_EVERY_DEG, allow_hyphen_values = true, value_parser = csv_every_deg, conflicts_with = "csv_every_step")]
    pub csv_every_deg: f64,
    /// --csv gets one row per solver sample (the midpoint and end of every step: uneven,
    /// and hundreds of times larger than the default grid) instead of the angle grid.
    #[arg(long)]
    pub csv_every_step: bool,
    /// Largest --csv file, MB (10^6 bytes; the default is 1 GB). The size is estimated
    /// before the run (about 850 B a row; the grid's rows are counted, --csv-every-step's
    /// estimated from the tolerance) and a larger one is refused; a run that writes more
    /// stops with an error and leaves no file.
    #[arg(long, value_name = "MB", default_value_t = DEFAULT_MAX_CSV_MB, allow_hyphen_values = true, value_parser = super::megabytes)]
    pub max_csv_mb: u64,
}

impl Default for CsvArgs {
    fn default() -> Self {
        CsvArgs {
            csv: None,
            csv_every_deg: DEFAULT_CSV_EVERY_DEG,
            csv_every_step: false,
            max_csv_mb: DEFAULT_MAX_CSV_MB,
        }
    }
}

impl CsvArgs {
    /// The cam-angle grid the run's observer is given points on: every
    /// `--csv-every-deg` degrees, or only the segments' starts with `--csv-every-step`
    /// (its rows are the solver's samples). The step was checked by the option's parser.
    pub fn grid(&self) -> Result<AngleGrid<f64>> {
        Ok(match self.csv_every_step {
            false => AngleGrid::new(self.csv_every_deg)?,
            true => AngleGrid::segment_starts(),
        })
    }

    /// The bytes the CSV of a run of `run` on `grid` will have: its rows on the grid
    /// counted, or (`--csv-every-step`) estimated from the solver's steps.
    pub fn expected_bytes(&self, run: &RunSpec, grid: &AngleGrid<f64>) -> u64 {
        match self.csv_every_step {
            false => crate::csv::rows_bytes(crate::csv::grid_rows(run, grid)),
            true => crate::csv::estimated_bytes(run),
        }
    }

    /// `--max-csv-mb` in bytes.
    pub fn max_bytes(&self) -> u64 {
        self.max_csv_mb.saturating_mul(1_000_000)
    }
}
