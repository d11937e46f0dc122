//! `camsim jump-speed --actual`: the onset of machined cams as a distribution, the same
//! on any number of threads, each sample's onset its own search's.

use camsim::actual::Cams;
use camsim::cmd::jump_speed::find;
use camsim::cmd::run::{spec_from, SceneArgs};
use camsim::study::jump_speed_actual::study;

fn spec() -> camsim::sim::RunSpec {
    // The cheap reduced follower, static start (jump-speed's default).
    spec_from(&SceneArgs {
        follower: Some(camsim::args::FollowerArg::QuasiStaticRod),
        start: Some(camsim::args::StartArg::Static),
        ..Default::default()
    })
    .unwrap()
}

#[test]
fn the_distribution_is_the_samples_own_searches_on_any_thread_count() {
    let spec = spec();
    let actual = Cams {
        actual: true,
        seed: Some(5),
        ..Default::default()
    };
    let (res, max) = (20.0, 3000.0);
    let one = study(&spec, &actual, 3, 1, res, max).unwrap();
    let two = study(&spec, &actual, 3, 2, res, max).unwrap();
    assert_eq!(one.onset_rpm_or_max, two.onset_rpm_or_max);
    assert_eq!(
        (one.median_rpm, one.simulations),
        (two.median_rpm, two.simulations)
    );
    // Sample 1's onset is the search on actual cam 1 alone.
    let (dev, _) = camsim::actual::build_profile(&spec.design, &actual, 1).unwrap();
    let mut s1 = spec.clone();
    s1.profile = Some(std::sync::Arc::new(dev));
    let alone = find(&s1, res, max).unwrap();
    assert_eq!(Some(one.onset_rpm_or_max[1]), alone.jump_rpm);
    // The theoretical onset is the theoretical search's.
    assert_eq!(
        one.theoretical_jump_rpm,
        find(&spec, res, max).unwrap().jump_rpm
    );
    // Order statistics of three: min, median and max are the sorted onsets.
    let mut v = one.onset_rpm_or_max.clone();
    v.sort_by(f64::total_cmp);
    assert_eq!(
        (one.min_rpm, one.median_rpm, one.max_onset_rpm),
        (Some(v[0]), Some(v[1]), Some(v[2]))
    );
    assert_eq!(one.samples, 3);
}
