//! `camsim sweep` (issue 17): its jump flags are `camsim jump-speed`'s predicate, so on a
//! grid they agree with the onset that search brackets; its speed grid is refused on one
//! line naming --rpm; its actual cams do not depend on the thread count.

use camsim::cli;
use camsim::cmd::jump_speed::{find, MAX_RPM};
use camsim::sim::RunSpec;
use camsim::study::sweep::{self, parse_rpm_grid, RpmGrid, Sweep};

fn reference() -> RunSpec {
    let mut spec = RunSpec::reference();
    spec.solver.start = camsim_core::Start::Static;
    spec
}

fn sweep_of(
    grid: RpmGrid,
    actual: Option<(camsim::actual::Cams, u64)>,
    threads: usize,
) -> sweep::SweepReport {
    sweep::run(
        &Sweep {
            spec: reference(),
            grid,
            actual,
            threads,
            progress: false,
        },
        camsim::units::Units::Inch,
    )
    .unwrap()
}

/// Every speed of the sweep at or below the highest speed `jump-speed` saw holding holds,
/// every one at or above its lowest separating speed jumps: on the bracket's own ends
/// (the same speeds, the same predicate) and on a grid across the onset.
#[test]
fn jump_flags_agree_with_the_jump_speed_onset() {
    let js = find(&reference(), 1.0, MAX_RPM).unwrap();
    let (hold, jump) = (js.no_jump_rpm, js.jump_rpm.unwrap());
    assert!(jump - hold <= 1.0);
    let ends = sweep_of(
        RpmGrid {
            from_rpm: hold,
            to_rpm: jump,
            points: 2,
        },
        None,
        2,
    );
    let flags: Vec<(f64, bool)> = ends
        .theoretical
        .iter()
        .map(|p| (p.rpm, p.response.jump))
        .collect();
    assert_eq!(flags, vec![(hold, false), (jump, true)]);
    let grid = parse_rpm_grid("800:1000:9").unwrap();
    let r = sweep_of(grid, None, 2);
    assert_eq!(r.theoretical.len(), 9);
    for p in &r.theoretical {
        if p.rpm <= hold {
            assert!(
                !p.response.jump,
                "{} rpm jumps below the onset {hold}",
                p.rpm
            );
            assert!(p.response.min_contact_force_lb.in_inch() > 0.0);
        } else if p.rpm >= jump {
            assert!(
                p.response.jump,
                "{} rpm holds above the onset {jump}",
                p.rpm
            );
            assert_eq!(p.response.min_contact_force_lb.in_inch(), 0.0);
        }
    }
    // The grid's onset brackets jump-speed's: 900 holds, 925 jumps.
    let o = r.theoretical_onset.unwrap();
    assert!(o.holds_at_rpm.unwrap() <= hold && jump <= o.jumps_at_rpm);
    assert_eq!(o.jumps_at_rpm - o.holds_at_rpm.unwrap(), r.step_rpm);
    // The operating speed's smallest contact force is the verdict's quantity on the same
    // run: below the 50 lb preload-level minimum of the slow speeds, above 0.
    let slow = r
        .theoretical
        .first()
        .unwrap()
        .response
        .min_contact_force_lb
        .in_inch();
    assert!(slow > 0.0 && slow < 50.0);
}

/// The grid's errors exit 2 on one line naming --rpm and the rule.
#[test]
fn bad_rpm_grids_exit_2_naming_the_option() {
    for (bad, rule) in [
        ("300:1200:1", "N 1"),
        ("1200:300:5", "below TO"),
        ("a:b:c", "FROM a"),
        ("300:1200", "FROM:TO:N"),
    ] {
        let argv = ["camsim", "sweep", "--rpm", bad];
        let e = cli::parse_from(argv).unwrap_err();
        let line = cli::usage_message(&e);
        assert!(
            line.contains("--rpm") && line.contains(rule),
            "{bad}: {line}"
        );
        assert!(!line.contains('\n'));
        assert_eq!(cli::main_from(argv), 2, "{bad}");
    }
    let g = parse_rpm_grid("300:1200:19").unwrap();
    assert_eq!(g.step_rpm(), 50.0);
}

/// Actual cams: the same answer on 1 and 2 threads (collected by index), P(jump) counts
/// the jumping cams, and every band is ordered.
#[test]
fn actual_sweep_is_the_same_on_1_and_2_threads() {
    let actual = camsim::actual::Cams {
        actual: true,
        ..Default::default()
    };
    let grid = parse_rpm_grid("880:940:3").unwrap();
    let a = sweep_of(grid, Some((actual.clone(), 6)), 1);
    let b = sweep_of(grid, Some((actual, 6)), 2);
    let (pa, pb) = (a.actual.unwrap(), b.actual.unwrap());
    assert_eq!(pa.points, pb.points);
    assert_eq!(pa.points.len(), 3);
    for p in &pa.points {
        assert_eq!(p.p_jump, camsim::stats::Probability::of(p.p_jump.count, 6));
        let f = p.min_contact_force_lb.unwrap();
        assert!(f.p05 <= f.median && f.median <= f.p95);
    }
    // 940 rpm is above the theoretical onset by 4 %: every actual cam jumps there.
    assert_eq!(pa.points.last().unwrap().p_jump.count, 6);
}
