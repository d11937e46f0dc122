//! Puts the repository's root `memory.x` (the flash/RAM budget) on the linker search
//! path (for a real board, feature `stm32f446`, a `memory.x` at the board's origins with
//! the budget's lengths instead: `build/board_memory.rs`), and compiles in the scene
//! chosen at build time.
//!
//! `CAMSIM_SCENE=path/to/scene.toml` (a host scene file, `camsim scene --default`'s
//! schema; a relative path is taken from this `firmware/` directory): the file is read
//! and checked by the host's own reader (`camsim_scene_file::load`: `[run]`, `[solver]`
//! and `[design]` all checked, `run.rpm` applied), its design narrowed to the chip's
//! `f32` and checked again there (`camsim_chip::chip_design_from`, which `camsim predict
//! --f32 --scene` calls too), then written with postcard to `OUT_DIR/scene.postcard`;
//! the firmware decodes it at boot (`workload::chip_design`). A refused scene fails the
//! build with one line: the file, the line, the key, the value and the rule. Without
//! `CAMSIM_SCENE` the reference design is compiled in.
//!
//! `CAMSIM_PROFILE=path/to/measured.csv` (the CSV of `camsim run --measured`; a relative
//! path is taken from `firmware/`): a measured cam profile the roller rides on in the
//! product's table. Read by the host's reader (`camsim_scene_file::measured`, at most
//! `camsim_chip::CHIP_PROFILE_MAX_KNOTS` − 1 rows), turned into the deviation knots on
//! the scene's `f64` design (`Measured::deviation_knots`: rows as they are, a lift minus
//! the program, or a radius profile's roller envelope), narrowed to `f32` and checked by
//! the chip's own spline (`DeviatedLift::refit_periodic` on the chip's `ChipDeviation`,
//! which the firmware and `camsim predict --f32 --measured` call too), then written as two `f32` arrays (angle, rad, and
//! deviation, in, as raw bits) into `OUT_DIR/profile.rs`, compiled into flash
//! (`workload::chip_lift` splines them at boot). A refused file fails the build with one
//! line naming the file and the line.

use std::env;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use camsim_core::{Design, Real};

#[path = "build/board_memory.rs"]
mod board_memory;

fn main() {
    let manifest =
        PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let memory_x = manifest.join("..").join("memory.x");
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if env::var_os("CARGO_FEATURE_STM32F446").is_some() {
        board_memory::write(&memory_x, &out.join("memory.x"), &board_memory::STM32F446);
    } else {
        fs::copy(&memory_x, out.join("memory.x"))
            .unwrap_or_else(|e| panic!("cannot copy {}: {e}", memory_x.display()));
    }
    println!("cargo:rerun-if-changed=build/board_memory.rs");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", memory_x.display());
    println!("cargo:rerun-if-changed=build.rs");

    println!("cargo:rustc-check-cfg=cfg(camsim_scene)");
    println!("cargo:rerun-if-env-changed=CAMSIM_SCENE");
    let scene_out = out.join("scene.postcard");
    match env::var_os("CAMSIM_SCENE") {
        Some(path) if !path.is_empty() => {
            let path = manifest.join(PathBuf::from(path));
            println!("cargo:rerun-if-changed={}", path.display());
            match scene_bytes(&path) {
                Ok(bytes) => {
                    fs::write(&scene_out, bytes)
                        .unwrap_or_else(|e| panic!("cannot write {}: {e}", scene_out.display()));
                }
                Err(why) => {
                    eprintln!("error: CAMSIM_SCENE={}: {why}", path.display());
                    std::process::exit(1);
                }
            }
            let name = file_name(&path);
            println!("cargo:rustc-env=CAMSIM_SCENE_NAME={name}");
            println!("cargo:rustc-cfg=camsim_scene");
        }
        _ => {
            let _ = fs::remove_file(&scene_out);
        }
    }

    println!("cargo:rustc-check-cfg=cfg(camsim_profile)");
    println!("cargo:rerun-if-env-changed=CAMSIM_PROFILE");
    let profile_out = out.join("profile.rs");
    match env::var_os("CAMSIM_PROFILE") {
        Some(path) if !path.is_empty() => {
            let path = manifest.join(PathBuf::from(path));
            println!("cargo:rerun-if-changed={}", path.display());
            // The design the deviation is taken on: the scene's, or the reference.
            let design = match env::var_os("CAMSIM_SCENE") {
                Some(scene) if !scene.is_empty() => {
                    let scene = manifest.join(PathBuf::from(scene));
                    match camsim_scene_file::load(&scene) {
                        Ok(s) => s.design,
                        // Already refused above with its line.
                        Err(e) => refuse("CAMSIM_SCENE", &e.to_string()),
                    }
                }
                _ => camsim_chip::chip_design::<f64>(),
            };
            match profile_source(&path, &design) {
                Ok(src) => fs::write(&profile_out, src)
                    .unwrap_or_else(|e| panic!("cannot write {}: {e}", profile_out.display())),
                Err(why) => refuse("CAMSIM_PROFILE", &why),
            }
            let name = file_name(&path);
            println!("cargo:rustc-env=CAMSIM_PROFILE_NAME={name}");
            println!("cargo:rustc-cfg=camsim_profile");
        }
        _ => {
            let _ = fs::remove_file(&profile_out);
        }
    }
}

/// The file name a boot line reports (the whole path if it has none).
fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    )
}

/// Stops the build with one line: `error: VAR: why`.
fn refuse(var: &str, why: &str) -> ! {
    eprintln!("error: {var}: {why}");
    std::process::exit(1)
}

/// The measured profile at `path` on `design` as Rust source: `PROFILE_KNOTS` and the two
/// `f32` arrays of the deviation knots (raw bits), or why not (one line starting with the
/// file's name; a row's error names its line).
fn profile_source(path: &Path, design: &Design<f64>) -> Result<String, String> {
    use camsim_chip::CHIP_PROFILE_MAX_KNOTS as MAX;
    let measured = camsim_scene_file::measured::load_limited(path, MAX - 1)?;
    let (knots, values) = measured
        .deviation_knots(design)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if knots.len() > MAX {
        return Err(format!(
            "{}: the deviation has {} knots, more than the chip's {MAX} (a radius profile's envelope has 8 a row)",
            path.display(),
            knots.len()
        ));
    }
    // The chip's precision, narrowed as `camsim predict --f32 --measured` does.
    let k: Vec<f32> = knots.iter().map(|x| f32::from_f64(*x)).collect();
    let v: Vec<f32> = values.iter().map(|x| f32::from_f64(*x)).collect();
    // The chip's own spline must accept them (the firmware builds it at boot).
    let mut dev = Box::new(camsim_chip::ChipDeviation::<f32, MAX>::EMPTY);
    dev.refit_periodic(&k, &v)
        .map_err(|e| format!("{}: in f32, the chip's precision: {e}", path.display()))?;
    let n = k.len();
    let array = |xs: &[f32]| {
        let mut s = String::new();
        for (i, x) in xs.iter().enumerate() {
            let sep = if i % 6 == 0 { "\n    " } else { " " };
            let _ = write!(s, "{sep}f32::from_bits({:#010x}),", x.to_bits());
        }
        s
    };
    Ok(format!(
        "// Generated by build.rs from {} ({} rows, column {}): do not edit.\n\
         /// Knots of the measured profile's deviation spline (the closing knot included).\n\
         pub const PROFILE_KNOTS: usize = {n};\n\
         /// The knots' cam angles, rad.\n\
         pub static PROFILE_KNOTS_RAD: [f32; PROFILE_KNOTS] = [{}\n];\n\
         /// The lift deviation at the knots, in.\n\
         pub static PROFILE_DEVIATION_IN: [f32; PROFILE_KNOTS] = [{}\n];\n",
        path.display(),
        measured.angles_deg.len(),
        measured.column.name(),
        array(&k),
        array(&v)
    ))
}

/// The scene file at `path` as the chip's `Design<f32>` in postcard, or why not (one
/// line; the reader's errors start with the file's name, so this one's do not).
fn scene_bytes(path: &Path) -> Result<Vec<u8>, String> {
    let scene = camsim_scene_file::load(path).map_err(|e| {
        // "PATH: line N: ...": the path is already in front of the whole message.
        let msg = e.to_string();
        let prefix = format!("{}: ", path.display());
        msg.strip_prefix(&prefix).map(str::to_string).unwrap_or(msg)
    })?;
    let design = camsim_chip::chip_design_from::<f32>(&scene.design).map_err(|e| {
        let text = fs::read_to_string(path).unwrap_or_default();
        let why = camsim_scene_file::refusal("design", e).at_line_in(&text);
        format!("{why} (in f32, the chip's precision)")
    })?;
    postcard::to_stdvec(&design).map_err(|e| format!("cannot encode the design: {e}"))
}
