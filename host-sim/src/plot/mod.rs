//! PNG plots of a run against cam angle (`camsim run --plot DIR`), after the thesis's
//! figures (chapter VI): the follower (load) displacement, velocity and acceleration,
//! each over its theoretical curve with the deviation below; the pressure angle; the
//! motor, coupling and cam angular velocities; the contact force and stress; and the
//! output and drive torques.
//!
//! The cam angle axis is continuous over the revolutions (0 to 360 per revolution, in
//! degrees) with the revolution boundaries marked, and every jump interval (the follower
//! off the cam, Eq. V.20) is shaded. Long series are decimated to the first, lowest,
//! highest and last point of each pixel column, so peaks survive. Text uses DejaVu Sans,
//! embedded in the binary (no system fonts needed).

use anyhow::{anyhow, Result};

use crate::figure::palette::{BLUE, DARK_GREY, GREEN, LIGHT_GREY, LIGHT_RED, ORANGE, RED};
use crate::figure::Colour;
use crate::output::AtomicDir;

pub mod axis;
pub mod charts;
pub mod compare;
pub mod montecarlo;
pub mod profile;
pub mod run;
pub mod sensitivity;
pub mod svaj;
pub mod sweep;
pub mod tolerance;

pub(crate) use axis::fmt_tick;
pub use axis::{decimate, log_key_points};
pub use profile::{draw_profile, PROFILE_FILE};
pub use run::{draw_all, draw_run, PlotData, FILES, FILES_WITH_PROFILE};
pub use svaj::draw_svaj;

/// Writes an RGB buffer of `size` pixels as the PNG `file` into the directory output
/// `out` (to the file's temporary: the caller commits `out`). Every plot is saved here.
pub fn save_png(out: &mut AtomicDir, file: &str, rgb: &[u8], size: (u32, u32)) -> Result<()> {
    let path = out.path(file)?;
    image::save_buffer_with_format(
        &path,
        rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| anyhow!("cannot write plot {}: {e}", out.dir().join(file).display()))
}

/// Size of a single-panel plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1200, 600);
/// Size of a follower-output plot (curves over the theoretical, deviation below), pixels.
pub const FOLLOWER_PLOT_SIZE: (u32, u32) = (1200, 800);
/// Size of the SVAJ plot (four panels), pixels.
pub const SVAJ_PLOT_SIZE: (u32, u32) = (1200, 1400);

/// Colours: the simulated curve, the theoretical, the second and third curves; a jump's
/// shading and its opacity; a revolution's boundary; a period's start.
const SIMULATED: Colour = BLUE;
const THEORY: Colour = RED;
const SECOND: Colour = ORANGE;
const THIRD: Colour = GREEN;
const JUMP_FILL: Colour = LIGHT_RED;
const JUMP_ALPHA: f64 = 0.45;
const REV_LINE: Colour = DARK_GREY;
const PERIOD_LINE: Colour = LIGHT_GREY;
