//! Issue 30: a scene file written in SI keys gives SI output without `--units`; `--units`
//! given on the command line decides over the scene; an inch scene, a scene mixing the
//! families and no scene give inch, as before. Under an SI scene a bare number on an
//! option whose bare number is inch is refused, naming the option, the value and the
//! scene.
//!
//! The SI scene is `camsim scene --new --units si`'s template (mm, kg, N/mm keys); the
//! inch scene is `camsim scene --default`'s.

use std::path::{Path, PathBuf};

use camsim::cli::{self, Command};
use camsim::cmd::run;
use camsim::report::Report;
use camsim::units::{self, Units, UnitsFrom};

mod common;

/// The text `camsim scene --new|--default` prints, in `family`.
fn scene_text(what: &str, family: Units) -> String {
    let argv = ["camsim", "scene", what];
    let Command::Scene(a) = cli::parse_from(argv).unwrap().command else {
        panic!("not scene")
    };
    camsim::cmd::scene::output(&a, family).unwrap()
}

/// A directory holding `si.toml` (the SI template), `inch.toml` (the reference in inch
/// keys), `mixed.toml` (the SI template with one inch key) and `plain.toml` (no key with
/// a unit).
fn scenes(name: &str) -> PathBuf {
    let dir = common::scratch(name);
    std::fs::create_dir_all(&dir).unwrap();
    let si = scene_text("--new", Units::Si);
    assert!(si.contains("base_radius_mm = "), "{si}");
    std::fs::write(dir.join("si.toml"), &si).unwrap();
    std::fs::write(dir.join("inch.toml"), scene_text("--default", Units::Inch)).unwrap();
    let mixed = si.replace("e1_mm = 150.0", "e1_in = 5.905511811");
    assert_ne!(mixed, si);
    std::fs::write(dir.join("mixed.toml"), mixed).unwrap();
    std::fs::write(dir.join("plain.toml"), "[run]\nrpm = 300.0\n").unwrap();
    dir
}

fn argv<'a>(args: &[&'a str]) -> Vec<&'a str> {
    std::iter::once("camsim")
        .chain(args.iter().copied())
        .collect()
}

/// `args` with `scene` put where `{}` stands.
fn with_scene<'a>(args: &[&'a str], scene: &'a str) -> Vec<&'a str> {
    args.iter()
        .map(|a| if *a == "{}" { scene } else { a })
        .collect()
}

/// Every command that reads a scene file, with what else it requires.
const SCENE_COMMANDS: [&[&str]; 15] = [
    &["run", "{}"],
    &["sweep", "{}", "--rpm", "100:200:2"],
    &["jump-speed", "{}"],
    &["design", "spring", "{}"],
    &["design", "speed", "{}"],
    &["design", "tolerance", "{}"],
    &["montecarlo", "{}", "--samples", "2"],
    &["compare", "{}"],
    &["sensitivity", "{}"],
    &["tolerance-study", "{}"],
    &["profile", "{}"],
    &["modal", "{}"],
    &["contact", "{}", "--force", "10N"],
    &["predict", "{}"],
    &["predict", "--scene", "{}"],
];

#[test]
fn every_scene_command_answers_in_the_family_of_its_scene_unless_units_is_given() {
    let dir = scenes("units-scene-family");
    let path = |f: &str| dir.join(f).display().to_string();
    let (si, inch, mixed, plain) = (
        path("si.toml"),
        path("inch.toml"),
        path("mixed.toml"),
        path("plain.toml"),
    );
    let missing = path("absent.toml");
    for cmd in SCENE_COMMANDS {
        let decided = |scene: &str, extra: &[&str]| {
            let mut a = argv(&with_scene(cmd, scene));
            a.extend_from_slice(extra);
            let c = cli::parse_from(a).unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
            (c.units, c.units_from)
        };
        assert_eq!(
            decided(&si, &[]),
            (Units::Si, UnitsFrom::Scene(PathBuf::from(&si))),
            "{cmd:?}"
        );
        assert_eq!(
            decided(&si, &["--units", "inch"]),
            (Units::Inch, UnitsFrom::Option),
            "{cmd:?}"
        );
        assert_eq!(
            decided(&inch, &["--units", "si"]),
            (Units::Si, UnitsFrom::Option),
            "{cmd:?}"
        );
        // Inch unless every key with a unit is SI; a file that cannot be read decides
        // nothing (the command's own reading reports it).
        for scene in [&inch, &mixed, &plain, &missing] {
            assert_eq!(
                decided(scene, &[]),
                (Units::Inch, UnitsFrom::Default),
                "{cmd:?} {scene}"
            );
        }
    }
    // No scene: inch, as before.
    let c = cli::parse_from(argv(&["run"])).unwrap();
    assert_eq!((c.units, c.units_from), (Units::Inch, UnitsFrom::Default));
    // A name that is not a scene file (firmware-check's --scene NAME) decides nothing.
    let c = cli::parse_from(argv(&["firmware-check", "--fits", &si, "--scene", &si])).unwrap();
    assert_eq!(c.units, Units::Inch);
}

/// The refusal of a bare number, if any (as the binary prints it).
fn refusal(args: &[&str]) -> Option<String> {
    let a: Vec<std::ffi::OsString> = argv(args).into_iter().map(Into::into).collect();
    cli::bare_inch_number(&a)
}

#[test]
fn a_bare_number_beside_an_si_scene_is_refused_naming_the_option_value_and_scene() {
    let dir = scenes("units-scene-bare");
    let si = dir.join("si.toml").display().to_string();
    let inch = dir.join("inch.toml").display().to_string();
    let cases: [(&[&str], &str, &str, &str); 4] = [
        (
            &["profile", &si, "--cutter-radius", "10"],
            "--cutter-radius 10",
            "10mm",
            "10in",
        ),
        (
            &["run", &si, "--spring-rate", "10"],
            "--spring-rate 10",
            "10N/mm",
            "10lb/in",
        ),
        (
            &["contact", &si, "--force", "50"],
            "--force 50",
            "50N",
            "50lb",
        ),
        (
            &["design", "spring", &si, "--preload-length", "1"],
            "--preload-length 1",
            "1mm",
            "1in",
        ),
    ];
    for (args, option, si_value, inch_value) in cases {
        let e = refusal(args).unwrap_or_else(|| panic!("{args:?} accepted"));
        assert!(!e.contains('\n'), "{e}");
        for part in [
            option,
            si_value,
            inch_value,
            "--units inch",
            si.as_str(),
            "SI keys",
        ] {
            assert!(e.contains(part), "{args:?}: no {part:?} in {e}");
        }
        // With the unit, with --units inch, or beside an inch scene: read as given.
        let mut with_unit = args.to_vec();
        if let Some(last) = with_unit.last_mut() {
            *last = si_value;
        }
        assert_eq!(refusal(&with_unit), None, "{with_unit:?}");
        let mut explicit = args.to_vec();
        explicit.extend(["--units", "inch"]);
        assert_eq!(refusal(&explicit), None, "{explicit:?}");
        let beside_inch: Vec<&str> = args
            .iter()
            .map(|a| if *a == si { inch.as_str() } else { a })
            .collect();
        assert_eq!(refusal(&beside_inch), None, "{beside_inch:?}");
    }
    // --units si given: the rule as before, its message naming --units si.
    let e = refusal(&["run", &inch, "--units", "si", "--spring-rate", "10"]).unwrap();
    assert!(
        e.contains("with --units si give its unit, 10N/mm or 10lb/in"),
        "{e}"
    );
    // The binary refuses it as a usage error (exit 2) before anything runs.
    assert_eq!(
        cli::main_from(argv(&["run", &si, "--spring-rate", "10"])),
        2
    );
}

/// `args`' run report in the family the command line decides (as `cli::execute` sets
/// it): its text and its JSON as printed.
fn run_outputs(args: &[&str]) -> (String, String) {
    let c = cli::parse_from(argv(args)).unwrap();
    let units = c.units;
    let Command::Run(a) = c.command else {
        panic!("not run")
    };
    let r = run::report(&a, units).unwrap();
    let json = units::json(&r.json().unwrap(), units).unwrap();
    let text = r.text(units);
    // The run time is the clock's, not the model's.
    let timeless = |s: String| -> String {
        s.lines()
            .filter(|l| !l.starts_with("run time:") && !l.contains("\"wall_ms\""))
            .collect::<Vec<_>>()
            .join("\n")
    };
    (timeless(text), timeless(json))
}

#[test]
fn an_si_scene_runs_in_si_and_an_inch_scene_is_unchanged() {
    let dir = scenes("units-scene-run");
    let si = dir.join("si.toml").display().to_string();
    let inch = dir.join("inch.toml").display().to_string();
    let (text, json) = run_outputs(&["run", &si, "--revolutions", "1"]);
    assert!(
        text.contains("\nunits: mm, N, s; torque N m; stress MPa"),
        "{text}"
    );
    assert!(
        json.contains("\"rate_n_per_mm\"") && !json.contains("_lb_per_in\""),
        "{json}"
    );
    // The same scene under --units inch: inch, and the same results as --units si
    // converted (the text's preload line: lb times 4.4482216152605 is N).
    let (inch_text, inch_json) =
        run_outputs(&["run", &si, "--revolutions", "1", "--units", "inch"]);
    assert!(inch_text.contains("\nunits: in, lb, s;"), "{inch_text}");
    assert!(inch_json.contains("\"rate_lb_per_in\"") && !inch_json.contains("_n_per_mm\""));
    let (explicit_si, explicit_si_json) =
        run_outputs(&["run", &si, "--revolutions", "1", "--units", "si"]);
    assert_eq!((explicit_si, explicit_si_json), (text, json));
    // An inch scene without --units is byte for byte the inch output it always was.
    assert_eq!(
        run_outputs(&["run", &inch, "--revolutions", "1"]),
        run_outputs(&["run", &inch, "--revolutions", "1", "--units", "inch"])
    );
}

/// The first line of `file`.
fn header(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap();
    text.lines().next().unwrap().to_string()
}

#[test]
fn an_si_scene_writes_si_csv_headers_and_drawings() {
    let dir = scenes("units-scene-files");
    let si = dir.join("si.toml").display().to_string();
    let out = |name: &str| dir.join(name).display().to_string();
    let main = |args: &[&str]| cli::main_from(argv(args));
    // run --csv: every dimensional column named in SI; under --units inch in inch.
    assert_eq!(
        main(&["run", &si, "--revolutions", "1", "--csv", &out("si.csv")]),
        0
    );
    let h = header(&dir.join("si.csv"));
    assert!(
        h.contains("y1_mm,") && h.contains("contact_force_n,"),
        "{h}"
    );
    assert_eq!(
        main(&[
            "run",
            &si,
            "--revolutions",
            "1",
            "--csv",
            &out("in.csv"),
            "--units",
            "inch"
        ]),
        0
    );
    let h = header(&dir.join("in.csv"));
    assert!(
        h.contains("y1_in,") && h.contains("contact_force_lb,"),
        "{h}"
    );
    // profile --out: the surface in mm, the DXF's note in mm; a cutter given in mm.
    let cam = out("cam");
    assert_eq!(
        main(&["profile", &si, "--out", &cam, "--cutter-radius", "10mm"]),
        0
    );
    let cam = Path::new(&cam);
    let csv = std::fs::read_to_string(cam.join(camsim::cmd::profile::SURFACE_RADIUS_FILE)).unwrap();
    assert!(csv.lines().any(|l| l == "angle_deg,radius_mm"), "{csv}");
    assert!(
        csv.contains("# Units: lengths in millimetres (mm)"),
        "{csv}"
    );
    let dxf = std::fs::read_to_string(cam.join("cam.dxf")).unwrap();
    assert!(
        dxf.contains("Units: lengths in millimetres (mm)"),
        "the DXF's note is not in mm"
    );
}

#[test]
fn an_si_scene_sweeps_and_designs_in_si() {
    let dir = scenes("units-scene-study");
    let si = dir.join("si.toml").display().to_string();
    let out = |name: &str| dir.join(name).display().to_string();
    // sweep --csv: the columns named in N and mm; under --units inch in lb.
    let sweep = |csv: &str, extra: &[&str]| {
        let mut a = argv(&["sweep", &si, "--rpm", "100:300:2", "--csv", csv]);
        a.extend_from_slice(extra);
        assert_eq!(cli::main_from(a), 0);
        header(Path::new(csv))
    };
    let h = sweep(&out("sweep-si.csv"), &[]);
    assert!(h.starts_with("rpm,jump,min_contact_force_n,"), "{h}");
    let h = sweep(&out("sweep-in.csv"), &["--units", "inch"]);
    assert!(h.starts_with("rpm,jump,min_contact_force_lb,"), "{h}");
    // design spring: the answer in N/mm and the scene's preload length in mm.
    let c = cli::parse_from(argv(&["design", "spring", &si, "--quick"])).unwrap();
    let units = c.units;
    let Command::Design(a) = c.command else {
        panic!("not design")
    };
    let camsim::cmd::design::What::Spring(s) = a.what else {
        panic!("not design spring")
    };
    let text = camsim::cmd::design::spring(&s, units).unwrap().text(units);
    let first = text.lines().next().unwrap_or("");
    assert!(
        first.starts_with("camsim design spring: ")
            && first.contains(" N/mm at preload length 25 mm"),
        "{first}"
    );
}
