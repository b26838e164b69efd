//! The constraint model of a mission: flat position domains p(0..=N), the
//! displacement boxes D(i) computed once from the inputs, and the detection
//! variables d(j) (the landmark position seen by detection j); for
//! odometry2d also the headings th(0..=N) and the odometry chain that ties
//! them to the positions ([`crate::odometry::chain`]).

use super::mission::{Mission, Model as MotionModel};
use crate::contractors::motion_chain::{
    auv_displacement, sweep_backward, sweep_forward, unicycle_displacement, Sweep,
};
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::odometry::chain::OdometryChain;
use crate::odometry::sensor::OffsetDetection;

/// Domains and precomputed data of one mission. Memory O(N + k).
#[derive(Debug, Clone)]
pub struct Model {
    /// Dimension of positions (2 or 3).
    pub dim: usize,
    /// N.
    pub steps: usize,
    /// Displacements, N·dim, step-major. odometry2d: a bound of the step's
    /// displacement for the current headings ([`Model::refresh_displacements`];
    /// the chain itself is [`Model::odometry`]), read only by the shapes
    /// reasoning and the robust propagation.
    pub disp: Vec<Interval>,
    /// Position domains, (N+1)·dim, step-major.
    pub pos: Vec<Interval>,
    /// Detection variables (landmark positions), one box per detection.
    pub det: Vec<IntervalBox>,
    /// Heading (unicycle2d) or yaw (auv3d) at each detection's step, for the
    /// bearing constraint; odometry2d: th(step) as of the last
    /// [`Model::refresh_headings_at`].
    pub heading_at: Vec<Interval>,
    /// odometry2d: th(0..=N), real numbers (never wrapped); empty for the
    /// other models.
    pub heading: Vec<Interval>,
    /// odometry2d: the motion chain over (p, th).
    pub odometry: Option<OdometryChain>,
    /// The sensor's place in the body frame (`sensor_offset`, [0, 0] when
    /// absent).
    pub sensor_offset: [f64; 2],
    /// At most this many detections may be false (the mission's
    /// `max_outliers`): a group's landmark box is then the q-relaxed
    /// intersection of its members' boxes.
    pub max_outliers: usize,
    /// Landmark regions (mode `shapes`, [`crate::shapes`]): per detection,
    /// the paving of its group's landmark when one was built, held at the
    /// group's smallest member; empty when none was.
    pub landmark_regions: Vec<Option<Vec<IntervalBox>>>,
}

impl Model {
    /// Builds the domains: p(0) = initial box, p(N) = final box when known,
    /// every other position unbounded; detection boxes from their region,
    /// depth and the mission's landmark region. O(N).
    pub fn new(m: &Mission) -> Model {
        let dim = m.model.dim();
        let n = m.steps;
        let (heading, odometry) = initial_headings(m);
        let (det, heading_at) = detection_boxes(m);
        Model {
            dim,
            steps: n,
            disp: displacements(m),
            pos: initial_positions(m),
            det,
            heading_at,
            heading,
            odometry,
            sensor_offset: m.sensor_offset.unwrap_or([0.0, 0.0]),
            max_outliers: m.max_outliers,
            landmark_regions: Vec::new(),
        }
    }

    /// Whether a detection is measured from p itself with a known heading
    /// (the plain distance and bearing contractors) rather than from an
    /// offset sensor or under a heading that is a variable
    /// ([`OffsetDetection`]).
    pub fn plain_detections(&self) -> bool {
        self.odometry.is_none() && self.sensor_offset == [0.0, 0.0]
    }

    /// odometry2d: `heading_at[j] = th(step of j)`. O(k).
    pub fn refresh_headings_at(&mut self, m: &Mission) {
        if self.heading.is_empty() {
            return;
        }
        for (h, d) in self.heading_at.iter_mut().zip(&m.detections) {
            *h = self.heading[d.step.min(self.steps)];
        }
    }

    /// odometry2d: `D(i) = dt·v(i)·(cos th(i), sin th(i)) + E(i)` for the
    /// current th(i) (sound: the true heading is in th(i)). O(N).
    pub fn refresh_displacements(&mut self) {
        let Some(chain) = &self.odometry else { return };
        for i in 0..self.steps {
            let d = chain.displacement(i, self.heading[i]);
            self.disp[2 * i] = d[0];
            self.disp[2 * i + 1] = d[1];
        }
    }

    /// The width of the widest heading (0 for the models without a
    /// heading state).
    pub fn max_heading_width(&self) -> f64 {
        self.heading
            .iter()
            .map(|h| if h.is_empty() { 0.0 } else { h.width() })
            .fold(0.0, f64::max)
    }

    /// Contracts detection `j` of `m` with p(step) and d(j) through
    /// [`OffsetDetection`] (odometry2d: the heading th(step) too;
    /// unicycle2d: a copy of the input heading, whose contraction is
    /// dropped). `false` when a domain became empty.
    pub fn contract_offset_detection(&mut self, m: &Mission, j: usize) -> bool {
        let det = &m.detections[j];
        let t = det.step.min(self.steps);
        let od = OffsetDetection::new(det.range, det.bearing, self.sensor_offset);
        let mut p = [self.pos[2 * t], self.pos[2 * t + 1]];
        let mut d = [self.det[j][0], self.det[j][1]];
        let mut h = if self.heading.is_empty() {
            self.heading_at[j]
        } else {
            self.heading[t]
        };
        let ok = od.contract(&mut p, &mut h, &mut d);
        if !ok {
            return false;
        }
        (self.pos[2 * t], self.pos[2 * t + 1]) = (p[0], p[1]);
        self.det[j][0] = d[0];
        self.det[j][1] = d[1];
        if !self.heading.is_empty() {
            self.heading[t] = h;
            self.heading_at[j] = h;
        }
        true
    }

    /// The box of p(i).
    pub fn position(&self, i: usize) -> IntervalBox {
        IntervalBox::new(&self.pos[i * self.dim..(i + 1) * self.dim])
    }

    /// Largest diameter of the trajectory boxes: the first value of
    /// [`Model::trajectory_diameters`], bit for bit, in one pass that
    /// rounds only the widths that can be the largest. O(N·d).
    pub fn max_trajectory_diameter(&self) -> f64 {
        // Widths rounded to nearest order the exact widths weakly (rounding
        // is monotone), and the rounded-up width is monotone too: the
        // largest rounded-up width is among the axes whose nearest width is
        // the largest. Empty axes give a negative width (0 in the result);
        // unbounded ones +inf (never NaN: lo < +inf and hi > -inf).
        let mut near = 0.0f64;
        let mut best = 0.0f64;
        for x in &self.pos {
            let w = x.hi() - x.lo();
            if w >= near {
                let up = x.width();
                best = if w > near { up } else { best.max(up) };
                near = w;
            }
        }
        best
    }

    /// Largest and mean diameter of the trajectory boxes.
    pub fn trajectory_diameters(&self) -> (f64, f64) {
        let mut max = 0.0f64;
        let mut sum = 0.0f64;
        for p in self.pos.chunks_exact(self.dim) {
            let w = p
                .iter()
                .map(|x| if x.is_empty() { 0.0 } else { x.width() })
                .fold(0.0, f64::max);
            max = max.max(w);
            sum += w;
        }
        (max, sum / (self.steps + 1) as f64)
    }
}

impl Model {
    /// Dead reckoning: p(0..=N) swept forward from the initial position,
    /// and back from the final position when the mission gives one
    /// (`to_final`), every step (tolerance 0). Err: the position that
    /// became empty, as the reason of an infeasible mission. The one dead
    /// reckoning of both propagations.
    pub fn dead_reckoning(&mut self, to_final: bool) -> Result<(), String> {
        let (dim, n) = (self.dim, self.steps);
        let chain_empty = |s: usize| {
            format!("motion chain: the position of step {s} is empty (the inputs cannot join the initial and final positions)")
        };
        if let Some(chain) = &self.odometry {
            let (pos, heading) = (&mut self.pos, &mut self.heading);
            if let Sweep::Empty(s) = chain.sweep_forward_flat(pos, heading, 0, n, 0.0) {
                return Err(chain_empty(s));
            }
            // Always back too: a final heading (or position) bounds the
            // end, and the backward step contracts the headings from the
            // displacements.
            if let Sweep::Empty(s) = chain.sweep_backward_flat(pos, heading, n, 0, 0.0) {
                return Err(chain_empty(s));
            }
            // The heading drift windows (heading_drift), and the chain
            // again from what they moved.
            if let Err(e) = chain.drift_flat(pos, heading, 0.0) {
                return Err(format!("heading_drift: the heading of step {} is empty (the windows cannot join the initial and final headings)", e.step));
            }
            self.refresh_displacements();
            return Ok(());
        }
        if let Sweep::Empty(s) = sweep_forward(&mut self.pos, &self.disp, dim, 0, 0.0) {
            return Err(chain_empty(s));
        }
        if to_final {
            if let Sweep::Empty(s) = sweep_backward(&mut self.pos, &self.disp, dim, n, 0.0) {
                return Err(chain_empty(s));
            }
        }
        Ok(())
    }
}

/// The operator's groups: detections by `landmark` label (groups of one
/// included), members sorted, groups by label. Written once for both
/// propagations (the rounds tie them before the first round; the robust
/// propagation reads them as the groups to prove).
pub fn operator_groups(mission: &Mission) -> Vec<Vec<usize>> {
    let mut by_landmark: Vec<(usize, usize)> = mission
        .detections
        .iter()
        .enumerate()
        .filter_map(|(j, d)| d.landmark.map(|l| (l, j)))
        .collect();
    crate::sort::sort_ord(&mut by_landmark);
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (x, &(l, j)) in by_landmark.iter().enumerate() {
        if x > 0 && by_landmark[x - 1].0 == l {
            groups.last_mut().expect("a group was opened").push(j);
        } else {
            groups.push(vec![j]);
        }
    }
    groups
}

/// The displacement boxes D(i), `dim` intervals per step. For odometry2d
/// the chain is `odometry`; until the headings are known each displacement
/// is bounded by |speed| dt on each axis (sound), then by
/// `refresh_displacements`.
fn displacements(m: &Mission) -> Vec<Interval> {
    let n = m.steps;
    let mut disp = Vec::with_capacity(n * m.model.dim());
    match m.model {
        MotionModel::Unicycle2d | MotionModel::Odometry2d => {
            let odometry = m.model == MotionModel::Odometry2d;
            for i in 0..n {
                let heading = if odometry {
                    Interval::ENTIRE
                } else {
                    m.inputs[1][i]
                };
                let d = unicycle_displacement(m.dt, m.inputs[0][i], heading, m.motion_error[i]);
                disp.extend_from_slice(&d);
            }
        }
        MotionModel::Auv3d => {
            let c = &m.inputs;
            #[allow(clippy::needless_range_loop)] // six parallel channels
            for i in 0..n {
                let v = [c[3][i], c[4][i], c[5][i]];
                let d = auv_displacement(m.dt, c[0][i], c[1][i], c[2][i], v, m.motion_error[i]);
                disp.extend_from_slice(&d);
            }
        }
    }
    disp
}

/// p(0) = the initial box, p(N) = the final box when known, every other
/// position unbounded.
fn initial_positions(m: &Mission) -> Vec<Interval> {
    let (dim, n) = (m.model.dim(), m.steps);
    let mut pos = vec![Interval::ENTIRE; (n + 1) * dim];
    pos[..dim].copy_from_slice(m.initial_position.axes());
    if let Some(f) = &m.final_position {
        for a in 0..dim {
            pos[n * dim + a] = pos[n * dim + a].intersect(f[a]);
        }
    }
    pos
}

/// odometry2d: the headings (initial and final known, the rest unbounded)
/// and the chain; other models: none.
fn initial_headings(m: &Mission) -> (Vec<Interval>, Option<OdometryChain>) {
    if m.model != MotionModel::Odometry2d {
        return (Vec::new(), None);
    }
    let n = m.steps;
    let mut h = vec![Interval::ENTIRE; n + 1];
    h[0] = m.initial_heading.unwrap_or(Interval::ENTIRE);
    if let Some(f) = m.final_heading {
        h[n] = h[n].intersect(f);
    }
    let chain = OdometryChain::new(
        m.dt,
        &m.inputs[0],
        &m.inputs[1],
        &m.heading_error,
        &m.motion_error,
    )
    .with_drift(m.dt, &m.inputs[1], &m.heading_error, &m.heading_drift)
    .with_motion_drift(&m.motion_drift);
    (h, Some(chain))
}

/// Each detection's box (its region, depth and the mission's landmark
/// region) and the heading input at its step (unbounded for odometry2d,
/// whose headings are variables).
fn detection_boxes(m: &Mission) -> (Vec<IntervalBox>, Vec<Interval>) {
    let (dim, n) = (m.model.dim(), m.steps);
    let heading_channel = match m.model {
        MotionModel::Unicycle2d => Some(1),
        MotionModel::Auv3d => Some(2),
        MotionModel::Odometry2d => None,
    };
    let mut det = Vec::with_capacity(m.detections.len());
    let mut heading_at = Vec::with_capacity(m.detections.len());
    for d in &m.detections {
        let mut b = IntervalBox::entire(dim);
        if let Some(r) = &m.landmark_region {
            b.intersect_with(r);
        }
        if let Some(r) = &d.region {
            b.intersect_with(r);
        }
        if let Some(z) = d.depth {
            b[2] = b[2].intersect(z);
        }
        det.push(b);
        heading_at
            .push(heading_channel.map_or(Interval::ENTIRE, |c| m.inputs[c][d.step.min(n - 1)]));
    }
    (det, heading_at)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass maximum gives the bits of `trajectory_diameters` on
    /// positions with equal, nearly equal, unbounded, empty and degenerate
    /// widths.
    #[test]
    fn max_trajectory_diameter_is_the_same_bits() {
        let mission = Mission::from_value(&serde_json::json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [1.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": []
        }))
        .unwrap();
        let mut rng = crate::test_rng::Lcg::new(12);
        for case in 0..2000 {
            let dim = 2 + case % 2;
            let steps = 1 + (rng.bits() % 40) as usize;
            let pos: Vec<Interval> = (0..(steps + 1) * dim)
                .map(|_| {
                    let lo = match rng.bits() % 4 {
                        0 => 0.1,
                        1 => 1e16 + (rng.bits() % 4) as f64,
                        _ => (rng.bits() % 1000) as f64 * 0.37 - 100.0,
                    };
                    match rng.bits() % 10 {
                        0 => Interval::EMPTY,
                        1 => Interval::new(f64::NEG_INFINITY, lo),
                        2 => Interval::point(lo),
                        3 => Interval::new(lo, lo + 0.3),
                        _ => Interval::new(lo, lo + (rng.bits() % 5) as f64 * 0.1 + 0.2),
                    }
                })
                .collect();
            let mut model = Model::new(&mission);
            (model.dim, model.steps, model.pos) = (dim, steps, pos);
            let (max, _) = model.trajectory_diameters();
            assert_eq!(
                model.max_trajectory_diameter().to_bits(),
                max.to_bits(),
                "case {case}"
            );
        }
    }
}
