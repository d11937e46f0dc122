//! Seeds of the fuzz corpora, from the shipped scenes: `cargo run -p camsim-fuzz-seed --
//! ROOT` (ROOT the repository) writes `fuzz/corpus/<target>/seed-*` (overwriting the
//! seeds only; libFuzzer's own finds keep their hash names).
//!
//! - scene_file: every file of `scenes/`, the complete default scene, an empty file.
//! - measured_profile: the lift of each scene's program as `angle_deg,lift_in` rows
//!   (every degree and every 10 degrees, with a header).
//! - core_rhs: each scene's design (postcard) behind the control bytes for several scenes,
//!   precisions and starts, with and without state offsets.

use std::fs;
use std::path::{Path, PathBuf};

use camsim_core::Design;
use camsim_scene_file::SceneFile;

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    fs::create_dir_all(dir).expect("corpus directory");
    fs::write(dir.join(format!("seed-{name}")), bytes).expect("seed file");
}

fn main() {
    let root = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    let corpus = root.join("fuzz/corpus");
    let mut scenes: Vec<(String, String)> = vec![(
        "default".into(),
        toml::to_string(&SceneFile::default()).expect("the default scene serializes"),
    )];
    let mut entries: Vec<_> = fs::read_dir(root.join("scenes"))
        .expect("scenes/")
        .map(|e| e.expect("scene entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    entries.sort();
    for p in entries {
        let name = p
            .file_stem()
            .expect("a name")
            .to_string_lossy()
            .into_owned();
        scenes.push((name, fs::read_to_string(&p).expect("a scene file")));
    }

    let dir = corpus.join("scene_file");
    write(&dir, "empty.toml", b"");
    for (name, text) in &scenes {
        write(&dir, &format!("{name}.toml"), text.as_bytes());
    }

    for (name, text) in &scenes {
        let scene = camsim_scene_file::parse(text).expect("a shipped scene reads");
        let d: Design<f64> = scene.design;

        let dir = corpus.join("measured_profile");
        for step in [1usize, 10] {
            let mut csv = String::from("angle_deg,lift_in\n");
            for deg in (0..=360).step_by(step) {
                let y = d.program.follower((deg as f64).to_radians()).y;
                csv.push_str(&format!("{deg},{y}\n"));
            }
            write(&dir, &format!("{name}-{step}deg.csv"), csv.as_bytes());
        }

        let dir = corpus.join("core_rhs");
        let design = postcard::to_allocvec(&d).expect("a design serializes");
        // (control byte, label): scene in the low 3 bits, bit 3 f32, bit 4 static start.
        for (k, label) in [
            (0x00u8, "full-thesis"),
            (0x11, "vertical-static"),
            (0x19, "vertical-static-f32"),
            (0x13, "constmotor-vertical-static"),
            (0x15, "constcam-vertical-static"),
        ] {
            let mut bytes = vec![k, 63];
            bytes.extend_from_slice(&design);
            write(&dir, &format!("{name}-{label}"), &bytes);
        }
        // The static start moved by small offsets (1e-4 of each unit) on every state.
        let mut bytes = vec![0x11u8, 15];
        bytes.extend_from_slice(&design);
        for _ in 0..22 {
            bytes.extend_from_slice(&1e-4f64.to_le_bytes());
        }
        write(&dir, &format!("{name}-vertical-offsets"), &bytes);
    }
}
