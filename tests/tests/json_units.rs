//! Issue 32: a report's dimensional number cannot stay in the wrong unit unnoticed.
//!
//! Each command's report (its smoke arguments of scripts/test-all.sh where they are
//! cheap), as its JSON serializes before `units::json` converts it:
//! - no `units::Measure` marker object survives the conversion, in either family;
//! - the keys still converted by their NAME (`units::by_name`: a plain number under a
//!   key with an inch-family suffix, or under a shared bare key) are exactly the list
//!   checked in as scripts/units-by-name.allowed, one `command key` a line. A report
//!   field made a `Measure` leaves the list; a new field named by its suffix joins it
//!   and fails this test: the list may only shrink. Its count is printed.
//!
//! After converting fields to `Measure`, regenerate the list with
//! `UNITS_BY_NAME_BLESS=1 cargo test -p camsim-tests --test json_units`.

use std::collections::BTreeSet;

use camsim::cli::{self, Command};
use camsim::report::Report;
use camsim::units::{self, Units};

/// The checked-in list of keys converted by name.
const ALLOWED: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../scripts/units-by-name.allowed"
);

/// `argv` (after `camsim`) parsed.
fn parse(argv: &[&str]) -> cli::Cli {
    cli::parse_from(std::iter::once("camsim").chain(argv.iter().copied())).unwrap()
}

/// The report's JSON, as it serializes, of each command checked here.
fn reports() -> Vec<(&'static str, String)> {
    use camsim::cmd::{design, run, sensitivity, sweep};
    let mut out = vec![
        ("laws", camsim::cmd::laws::report().json().unwrap()),
        (
            "modal",
            camsim::cmd::modal::analyse().unwrap().json().unwrap(),
        ),
        (
            "contact",
            camsim::study::contact::compute(100.0)
                .unwrap()
                .json()
                .unwrap(),
        ),
    ];
    let Command::Run(a) = parse(&["run", "--revolutions", "2"]).command else {
        panic!("not run")
    };
    out.push((
        "run",
        run::report(&a, camsim::units::Units::Inch)
            .unwrap()
            .json()
            .unwrap(),
    ));
    let Command::Design(d) = parse(&["design", "spring", "--quick"]).command else {
        panic!("not design")
    };
    let design::What::Spring(s) = d.what else {
        panic!("not design spring")
    };
    out.push((
        "design spring",
        design::spring(&s, camsim::units::Units::Inch)
            .unwrap()
            .json()
            .unwrap(),
    ));
    let Command::Sweep(a) = parse(&["sweep", "--rpm", "700:1000:4"]).command else {
        panic!("not sweep")
    };
    let sw = sweep::sweep_of(&a).unwrap();
    let report = camsim::study::sweep::run(&sw, Units::Inch).unwrap();
    out.push(("sweep", report.json().unwrap()));
    let Command::Sensitivity(a) = parse(&["sensitivity", "--quick"]).command else {
        panic!("not sensitivity")
    };
    let report = sensitivity::report(&a, Units::Inch).unwrap();
    out.push(("sensitivity", report.json().unwrap()));
    use camsim::cmd::predict;
    let p = predict::compute::<f64>(None, None).unwrap();
    let r = predict::PredictReport::of(&p, false, predict::REFERENCE_SCENE, None);
    out.push(("predict", r.json().unwrap()));
    use camsim::cmd::{compare, tolerance_study, waviness};
    let Command::Compare(a) = parse(&["compare", "--quick"]).command else {
        panic!("not compare")
    };
    out.push(("compare", compare::report(&a).unwrap().json().unwrap()));
    let Command::ToleranceStudy(a) = parse(&["tolerance-study", "--quick"]).command else {
        panic!("not tolerance-study")
    };
    let r = tolerance_study::report(&a, Units::Inch).unwrap();
    out.push(("tolerance-study", r.json().unwrap()));
    let w = waviness::report(&waviness::spec(&waviness::Args {
        seeds: vec![1],
        measured: None,
        json: false,
    }))
    .unwrap();
    out.push(("waviness", w.json().unwrap()));
    use camsim::cmd::{montecarlo, profile};
    let Command::Profile(a) = parse(&["profile"]).command else {
        panic!("not profile")
    };
    let r = profile::report(&a, Units::Inch).unwrap();
    out.push(("profile", r.json().unwrap()));
    let Command::Montecarlo(a) = parse(&["montecarlo", "--samples", "8"]).command else {
        panic!("not montecarlo")
    };
    let json = match montecarlo::execute(&a, Units::Inch).unwrap() {
        montecarlo::Outcome::Study(r) => r.json().unwrap(),
        montecarlo::Outcome::Shard(r) => r.json().unwrap(),
    };
    out.push(("montecarlo", json));
    let Command::Models(a) = parse(&["models", "--quick"]).command else {
        panic!("not models")
    };
    let spec = camsim::study::models::Spec {
        rpm: a.rpm,
        quick: a.quick,
        progress: false,
    };
    let r = camsim::study::models::report(&spec).unwrap();
    out.push(("models", r.json().unwrap()));
    out
}

/// The checked-in list's lines (comments and blank lines aside).
fn allowed() -> BTreeSet<String> {
    std::fs::read_to_string(ALLOWED)
        .unwrap_or_default()
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

#[test]
fn no_marker_survives_and_the_keys_converted_by_name_only_shrink() {
    let mut found = BTreeSet::new();
    for (command, json) in reports() {
        for family in [Units::Inch, Units::Si] {
            let printed = units::json(&json, family).unwrap();
            assert!(
                !printed.contains(units::measure::MARKER),
                "{command} --units {family:?}: a marker survives: {printed}"
            );
        }
        let value: serde_json::Value = serde_json::from_str(&json).unwrap();
        for key in units::by_name(&value) {
            found.insert(format!("{command} {key}"));
        }
    }
    println!("{} keys converted by name", found.len());
    if std::env::var_os("UNITS_BY_NAME_BLESS").is_some() {
        let mut text = String::from(
            "# Report keys still converted by their name (camsim::units::by_name), one\n\
             # `command key` a line: the list may only shrink. Regenerate it with\n\
             # UNITS_BY_NAME_BLESS=1 cargo test -p camsim-tests --test json_units\n",
        );
        for line in &found {
            text.push_str(line);
            text.push('\n');
        }
        std::fs::write(ALLOWED, text).unwrap();
        return;
    }
    let allowed = allowed();
    let new: Vec<_> = found.difference(&allowed).collect();
    assert!(
        new.is_empty(),
        "keys converted by their name, not in {ALLOWED}: make each field a units::Measure \
         (its key keeps its name): {new:?}"
    );
    let gone: Vec<_> = allowed.difference(&found).collect();
    assert!(
        gone.is_empty(),
        "keys in {ALLOWED} no longer converted by name: lower the list \
         (UNITS_BY_NAME_BLESS=1 cargo test -p camsim-tests --test json_units): {gone:?}"
    );
}
