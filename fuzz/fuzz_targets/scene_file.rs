//! The scene parser (`camsim-scene-file`, the one reader of `camsim` and of the
//! firmware's build script) on arbitrary text.
//!
//! Asserts: no panic; a refusal is one non-empty line; an accepted scene passes the
//! core's checks, has 1-16 revolutions, and written back as TOML reads back equal (so
//! no accepted value escapes the checks as NaN, which would not compare equal, and the
//! writer and the reader agree).
#![no_main]

use camsim_scene_file::{parse, CheckedScene, RunOptions, SceneFile, MAX_REVOLUTIONS};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse(text) {
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.trim().is_empty(), "empty refusal");
            assert!(
                !msg.contains(['\n', '\r']),
                "a refusal of more than one line: {msg:?}"
            );
        }
        Ok(scene) => {
            assert!(scene.design.validate().is_ok(), "{:?}", scene.design);
            assert!(scene.solver.validate().is_ok(), "{:?}", scene.solver);
            assert!((1..=MAX_REVOLUTIONS).contains(&scene.revolutions));
            let file = SceneFile {
                run: RunOptions {
                    revolutions: scene.revolutions,
                    horizontal_motion: scene.horizontal_motion,
                    follower: scene.follower,
                    rpm: None,
                },
                solver: scene.solver,
                design: scene.design.clone(),
                limits: scene.limits,
                // A part is written as the rate and spring mass it gives (the design's).
                spring: None,
            };
            let written = toml::to_string(&file).expect("an accepted scene serializes");
            match parse(&written) {
                Ok(back) => {
                    // A motor table is written as the design's values it set.
                    let expected = CheckedScene {
                        spring: None,
                        motor_table: false,
                        // A written scene names its drive.
                        drive_given: true,
                        ..scene
                    };
                    assert_eq!(back, expected, "read back differently:\n{written}")
                }
                Err(e) => panic!("a written scene is refused: {e}\n{written}"),
            }
        }
    }
});
