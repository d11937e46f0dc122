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

use std::env;
use std::fs;
use std::path::{Path, PathBuf};

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
            let name = path.file_name().map_or_else(
                || path.display().to_string(),
                |n| n.to_string_lossy().into(),
            );
            println!("cargo:rustc-env=CAMSIM_SCENE_NAME={name}");
            println!("cargo:rustc-cfg=camsim_scene");
        }
        _ => {
            let _ = fs::remove_file(&scene_out);
        }
    }
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
