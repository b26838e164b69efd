//! A random world for the shapes property tests: n landmarks in a layout
//! and a random walk among them (the truth the tests plant their boxes
//! around), and the planted instance those tests build from it.

use super::Rng;
use nvector_core::contractors::bearing::contract_bearing;
use nvector_core::contractors::distance::contract_distance;
use nvector_core::contractors::motion_chain::{sweep_backward, sweep_forward, Sweep};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::simulate::Layout;
use nvector_core::{Interval, IntervalBox};

/// A planted instance: the domains, the mission (detections) and the truth.
pub struct Planted {
    pub dim: usize,
    pub mission: Mission,
    pub pos: Vec<Interval>,
    pub disp: Vec<Interval>,
    pub det: Vec<IntervalBox>,
    pub heading_at: Vec<Interval>,
    pub truth_pos: Vec<Vec<f64>>,
    pub landmarks: Vec<Vec<f64>>,
    pub matching: Vec<usize>,
}

/// The truth of a world: landmarks, positions (one more than headings) and
/// the heading of each step.
pub struct World {
    pub landmarks: Vec<Vec<f64>>,
    pub truth_pos: Vec<Vec<f64>>,
    pub headings: Vec<f64>,
}

/// 1 to 5 landmarks in `layout` (depth -20 to -5 m when `dim` is 3), then
/// a walk of 20 to 20 + `extra_steps` - 1 steps from the origin: steps up
/// to 2 m, the heading turning by up to 0.4 rad a step.
pub fn random_world(rng: &mut Rng, dim: usize, layout: Layout, extra_steps: usize) -> World {
    let n = 1 + rng.below(5);
    let spread = rng.range(5.0, 40.0);
    let landmarks: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut l = match layout {
                Layout::Line => vec![
                    spread * (i as f64 - n as f64 / 2.0) / n as f64 * 2.0,
                    if i % 2 == 0 { 5.0 } else { -5.0 } + rng.range(-1.0, 1.0),
                ],
                Layout::Ring => {
                    let a = i as f64 / n as f64 * std::f64::consts::TAU + rng.range(-0.3, 0.3);
                    vec![spread * libm::cos(a), spread * libm::sin(a)]
                }
                Layout::Random => vec![rng.range(-spread, spread), rng.range(-spread, spread)],
            };
            if dim == 3 {
                l.push(rng.range(-20.0, -5.0));
            }
            l
        })
        .collect();
    let steps = 20 + rng.below(extra_steps);
    let mut truth_pos = vec![vec![0.0; dim]];
    let mut headings = Vec::with_capacity(steps);
    let mut h = rng.range(-3.0, 3.0);
    for _ in 0..steps {
        h += rng.range(-0.4, 0.4);
        let v = rng.range(0.0, 2.0);
        let last = truth_pos.last().expect("one").clone();
        let mut p = vec![last[0] + v * libm::cos(h), last[1] + v * libm::sin(h)];
        if dim == 3 {
            p.push(last[2] + rng.range(-0.2, 0.2));
        }
        truth_pos.push(p);
        headings.push(h);
    }
    World {
        landmarks,
        truth_pos,
        headings,
    }
}

impl Planted {
    /// The truth is in every position box and every detection's landmark box.
    pub fn truth_inside(&self) -> Result<(), String> {
        for (t, p) in self.truth_pos.iter().enumerate() {
            for a in 0..self.dim {
                if !self.pos[t * self.dim + a].contains(p[a]) {
                    return Err(format!(
                        "p({t}) lost: {:?} not in {:?}",
                        p,
                        &self.pos[t * self.dim..(t + 1) * self.dim]
                    ));
                }
            }
        }
        for (j, b) in self.det.iter().enumerate() {
            if !b.contains(&self.landmarks[self.matching[j]]) {
                return Err(format!("d({j}) lost"));
            }
        }
        Ok(())
    }

    /// The propagator's part, as in a round: each detection's own
    /// constraints, sweeps; then the groups' boxes intersected.
    pub fn own_constraints(&mut self, groups: &[Vec<usize>]) -> Result<(), String> {
        let dim = self.dim;
        for (j, d) in self.mission.detections.iter().enumerate() {
            let t = d.step;
            let p = &mut self.pos[t * dim..(t + 1) * dim];
            let mut r = d.range;
            let ok = contract_distance(p, self.det[j].axes_mut(), &mut r)
                && d.bearing.is_none_or(|b| {
                    contract_bearing(p, self.det[j].axes_mut(), self.heading_at[j], b, r)
                });
            if !ok {
                return Err(format!("detection {j} emptied"));
            }
            for s in [
                sweep_forward(&mut self.pos, &self.disp, dim, t, 1e-9),
                sweep_backward(&mut self.pos, &self.disp, dim, t, 1e-9),
            ] {
                if let Sweep::Empty(s) = s {
                    return Err(format!("chain emptied at {s}"));
                }
            }
        }
        for g in groups {
            let mut c = self.det[g[0]].clone();
            for &j in &g[1..] {
                c.intersect_with(&self.det[j]);
            }
            for &j in g {
                self.det[j] = c.clone();
            }
        }
        Ok(())
    }
}
