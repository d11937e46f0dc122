//! Puts the repository's root `memory.x` (the flash/RAM budget) on the linker search
//! path (for a real board, feature `stm32f446`, a `memory.x` at the board's origins with
//! the budget's lengths instead: `build/board_memory.rs`), compiles in the scene chosen
//! at build time and builds the chip's lift table into flash.
//!
//! The lift table (`OUT_DIR/lift_table.rs`, always): the compiled-in design in `f32` (the
//! reference, or the scene's as below) on the theoretical cam or on the measured profile
//! (below), tabulated here on the host by `camsim_chip::ChipConfig::tabulate` (the code
//! `camsim predict --f32` runs) and written out as a `static` of exactly its knots and
//! segments (`LiftTable::from_parts`, raw `f32` bits): the chip keeps it in flash, not in
//! RAM, and does no work for it at boot.
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
//! which `camsim predict --f32 --measured` calls too); the lift table is then filled on
//! that spline, which stays on the host (the chip keeps only the table). A refused file
//! fails the build with one line naming the file and the line.

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
        board_memory::check(&memory_x);
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
    // The chip's design in f32: the scene's (as `scene_bytes` compiled it in), or the
    // reference; in f64 for the measured profile's deviation knots.
    let (design64, design) = match env::var_os("CAMSIM_SCENE") {
        Some(scene) if !scene.is_empty() => {
            let scene = manifest.join(PathBuf::from(scene));
            let d = match camsim_scene_file::load(&scene) {
                Ok(s) => s.design,
                // Already refused above with its line.
                Err(e) => refuse("CAMSIM_SCENE", &e.to_string()),
            };
            match camsim_chip::chip_design_from::<f32>(&d) {
                Ok(d32) => (d, d32),
                Err(e) => refuse("CAMSIM_SCENE", &e.to_string()),
            }
        }
        _ => (
            camsim_chip::chip_design::<f64>(),
            camsim_chip::chip_design::<f32>(),
        ),
    };
    let table = match env::var_os("CAMSIM_PROFILE") {
        Some(path) if !path.is_empty() => {
            let path = manifest.join(PathBuf::from(path));
            println!("cargo:rerun-if-changed={}", path.display());
            let table = match measured_table(&path, &design64, &design) {
                Ok(src) => src,
                Err(why) => refuse("CAMSIM_PROFILE", &why),
            };
            let name = file_name(&path);
            println!("cargo:rustc-env=CAMSIM_PROFILE_NAME={name}");
            println!("cargo:rustc-cfg=camsim_profile");
            table
        }
        _ => {
            let mut table = Box::new(camsim_chip::ChipTable::<f32>::EMPTY);
            match camsim_chip::ChipConfig::new(&design).tabulate(&mut table) {
                Ok(_) => table_source(&table, 0, "the theoretical cam"),
                Err(e) => refuse("the chip's lift table", &e.to_string()),
            }
        }
    };
    let table_out = out.join("lift_table.rs");
    fs::write(&table_out, table)
        .unwrap_or_else(|e| panic!("cannot write {}: {e}", table_out.display()));
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

/// The chip's lift table on the measured profile at `path` as Rust source
/// ([`table_source`]), or why not (one line starting with the file's name; a row's error
/// names its line). The deviation knots are taken on `design64` (the scene's `f64`
/// design), narrowed to `f32` and splined by the chip's own spline, as `camsim predict
/// --f32 --measured` does; the table is then filled on `design`.
fn measured_table(
    path: &Path,
    design64: &Design<f64>,
    design: &Design<f32>,
) -> Result<String, String> {
    use camsim_chip::CHIP_PROFILE_MAX_KNOTS as MAX;
    let measured = camsim_scene_file::measured::load_limited(path, MAX - 1)?;
    let (knots, values) = measured
        .deviation_knots(design64)
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
    let mut dev = Box::new(camsim_chip::ChipDeviation::<f32, MAX>::EMPTY);
    dev.refit_periodic(&k, &v)
        .map_err(|e| format!("{}: in f32, the chip's precision: {e}", path.display()))?;
    let mut table = Box::new(camsim_chip::ChipTable::<f32>::EMPTY);
    camsim_chip::ChipConfig::new(design)
        .on(&*dev)
        .tabulate(&mut table)
        .map_err(|e| format!("{}: the chip's lift table: {e}", path.display()))?;
    let what = format!(
        "the measured profile {} ({} rows, column {})",
        path.display(),
        measured.angles_deg.len(),
        measured.column.name()
    );
    Ok(table_source(&table, k.len(), &what))
}

/// The filled lift table as Rust source: a `static` in flash of exactly its knots and
/// segments (`LiftTable::from_parts`, the values as raw `f32` bits), and `PROFILE_KNOTS`,
/// the deviation knots it was built on (0 for the theoretical cam).
fn table_source(table: &camsim_chip::ChipTable<f32>, profile_knots: usize, what: &str) -> String {
    let bits = |x: f32| format!("f32::from_bits({:#010x})", x.to_bits());
    let mut knots = String::new();
    for k in table.knots_used() {
        let row: Vec<String> = k.iter().map(|x| bits(*x)).collect();
        let _ = write!(knots, "\n    [{}],", row.join(", "));
    }
    let mut pieces = String::new();
    for p in table.pieces_used() {
        let _ = write!(
            pieces,
            "\n    camsim_core::TablePiece {{ start: {}, end: {}, h: {}, inv_h: {}, first: {}, n: {} }},",
            bits(p.start),
            bits(p.end),
            bits(p.h),
            bits(p.inv_h),
            p.first,
            p.n
        );
    }
    format!(
        "// Generated by build.rs: the chip's lift table on {what}. Do not edit.\n\
         /// Knots of the measured profile's deviation spline the table was built on (0: the\n\
         /// theoretical cam).\n\
         pub const PROFILE_KNOTS: usize = {profile_knots};\n\
         /// Knots of the lift table.\n\
         pub const TABLE_KNOTS: usize = {};\n\
         /// Program segments of the lift table.\n\
         pub const TABLE_PIECES: usize = {};\n\
         /// The lift table, in flash.\n\
         pub static LIFT_TABLE: camsim_core::LiftTable<f32, TABLE_KNOTS, TABLE_PIECES> =\n\
         camsim_core::LiftTable::from_parts([{knots}\n], [{pieces}\n], TABLE_KNOTS, TABLE_PIECES, {});\n",
        table.knots_used().len(),
        table.pieces_used().len(),
        bits(table.prime_radius()),
    )
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
