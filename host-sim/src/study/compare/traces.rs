//! The responses the comparison's figure shows: revolution 2 of a few laws (the two best
//! overall and the reference program's two), each on the theoretical cam and on the
//! actual cam (sample 0).

use std::sync::Arc;

use anyhow::{anyhow, Result};
use camsim_core::{MotionLaw, Sample};

use super::{with_law, LawStudy, Spec};
use crate::actual;
use crate::sim::{self, RunSpec};

/// Revolution-2 samples of one run: (cam angle in degrees, acceleration deviation,
/// contact force), in the inch family.
pub type Trace = Vec<(f64, f64, f64)>;

/// One law's responses: its name, its theoretical cam's trace, its actual cam's.
pub type LawTraces = (String, Trace, Trace);

fn trace(spec: &RunSpec) -> Result<Trace> {
    let mut out = Vec::new();
    let mut obs = |s: &Sample<f64>| {
        if s.revolution == 2 {
            out.push((
                s.angle_deg,
                s.point.load_acceleration() - s.theory.a,
                s.point.contact_force,
            ));
        }
        std::ops::ControlFlow::Continue(())
    };
    sim::run(spec, &mut obs)?;
    Ok(out)
}

/// The laws whose responses the figure draws (the two best overall and the reference
/// program's two, each once), as indices into `laws`.
fn picks(laws: &[LawStudy]) -> Vec<usize> {
    let mut picks: Vec<usize> = Vec::new();
    let by_rank = |r: usize| laws.iter().position(|l| l.ranks.overall == r);
    for i in [by_rank(1), by_rank(2)].into_iter().flatten().chain(
        ["modified-trapezoidal", "4-5-6-7"]
            .iter()
            .filter_map(|n| laws.iter().position(|l| l.name == *n)),
    ) {
        if !picks.contains(&i) {
            picks.push(i);
        }
    }
    picks
}

/// The responses of the laws `picks` chooses from the ranked `laws` of the study
/// `spec`, each on the theoretical cam and on its actual cam.
pub fn response_traces(laws: &[LawStudy], spec: &Spec) -> Result<Vec<LawTraces>> {
    let mut traces = Vec::new();
    for i in picks(laws) {
        let name = &laws[i].name;
        let law = MotionLaw::from_name(name).ok_or_else(|| anyhow!("unknown law {name}"))?;
        let run = with_law(&spec.base, law)?;
        let theo = trace(&run)?;
        let (dev, _) = actual::build_profile(&run.design, &spec.actual, 0)?;
        let mut s = run.clone();
        s.profile = Some(Arc::new(dev));
        traces.push((name.clone(), theo, trace(&s)?));
    }
    Ok(traces)
}
