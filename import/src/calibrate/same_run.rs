//! The methods of a same-run calibration (the oracle: a model fitted for
//! the run it is applied to, docs/calibration.md "Same-run calibration"):
//! the truth completed across its gaps, and the flagged steps. Any robot's
//! run with truth may use them; their bounds hold on that run only.

use super::data::{Model, Run, Truth};

/// The truth of `run` completed across its gaps, for the per-step bounds
/// and the drift windows of a same-run calibration, and the steps that
/// touch a gap (a missing position or heading at one of their ends).
///
/// A gap between two known poses is filled by linear interpolation of the
/// position and the heading; after the last known pose, by dead reckoning
/// of the log (odometry2d: the turn rate and speed; unicycle2d: the
/// measured heading and speed). Before the first known pose nothing is
/// filled. The completion is a witness, not the truth: a mission whose
/// bounds hold it is consistent with a trajectory through the known poses.
pub fn complete(run: &Run) -> (Run, Vec<bool>) {
    let Some(t) = run.truth.as_ref() else {
        return (run.clone(), vec![false; run.steps()]);
    };
    let n = run.steps();
    let known = |k: usize| t.positions[k].is_some() && (!t.has_heading || t.headings[k].is_some());
    let gap_step: Vec<bool> = (0..n).map(|i| !(known(i) && known(i + 1))).collect();
    let mut c = Truth {
        positions: t.positions.clone(),
        headings: t.headings.clone(),
        has_heading: t.has_heading,
    };
    let Some(first) = (0..=n).find(|&k| known(k)) else {
        return (run.clone(), gap_step);
    };
    let mut a = first;
    while a < n {
        match (a + 1..=n).find(|&k| known(k)) {
            Some(b) => {
                for j in a + 1..b {
                    let s = (j - a) as f64 / (b - a) as f64;
                    let (pa, pb) = (
                        c.positions[a].unwrap_or_default(),
                        c.positions[b].unwrap_or_default(),
                    );
                    c.positions[j] =
                        Some([pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])]);
                    if t.has_heading {
                        let (ha, hb) = (c.headings[a].unwrap_or(0.0), c.headings[b].unwrap_or(0.0));
                        c.headings[j] = Some(ha + s * (hb - ha));
                    }
                }
                a = b;
            }
            None => {
                dead_reckon(run, &mut c, a);
                a = n;
            }
        }
    }
    let mut out = run.clone();
    out.truth = Some(c);
    (out, gap_step)
}

/// Fills the truth after the known pose `a` by the log's dead reckoning.
fn dead_reckon(run: &Run, c: &mut Truth, a: usize) {
    for j in a..run.steps() {
        let h = match run.model {
            Model::Odometry2d => c.headings[j].unwrap_or(0.0),
            Model::Unicycle2d => run.rotation[j],
        };
        let p = c.positions[j].unwrap_or_default();
        let d = run.dt * run.speed[j];
        c.positions[j + 1] = Some([p[0] + d * h.cos(), p[1] + d * h.sin()]);
        if c.has_heading {
            c.headings[j + 1] = Some(match run.model {
                Model::Odometry2d => h + run.dt * run.rotation[j],
                Model::Unicycle2d => run.rotation.get(j + 1).copied().unwrap_or(h),
            });
        }
    }
}

/// The flagged steps of one per-step bound: the `(step, residual)` samples
/// above `above` each get `factor` x |residual| + `margin`; the others are
/// returned for the ordinary fit.
pub fn flag<T: Copy>(
    samples: &[T],
    residual: impl Fn(&T) -> (usize, f64),
    above: Option<f64>,
    factor: f64,
    margin: f64,
) -> (Vec<T>, Vec<(usize, f64)>) {
    let Some(above) = above else {
        return (samples.to_vec(), Vec::new());
    };
    let mut ordinary = Vec::with_capacity(samples.len());
    let mut flagged = Vec::new();
    for s in samples {
        let (i, r) = residual(s);
        if r.abs() > above {
            flagged.push((i, r.abs() * factor + margin));
        } else {
            ordinary.push(*s);
        }
    }
    (ordinary, flagged)
}
