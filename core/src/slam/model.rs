//! The constraint model of a mission: flat position domains p(0..=N), the
//! displacement boxes D(i) computed once from the inputs, and the detection
//! variables d(j) (the landmark position seen by detection j).

use super::mission::{Mission, Model as MotionModel};
use super::motion_chain::{auv_displacement, unicycle_displacement};
use crate::ibox::IntervalBox;
use crate::interval::Interval;

/// Domains and precomputed data of one mission. Memory O(N + k).
#[derive(Debug, Clone)]
pub struct Model {
    /// Dimension of positions (2 or 3).
    pub dim: usize,
    /// N.
    pub steps: usize,
    /// Displacements, N·dim, step-major.
    pub disp: Vec<Interval>,
    /// Position domains, (N+1)·dim, step-major.
    pub pos: Vec<Interval>,
    /// Detection variables (landmark positions), one box per detection.
    pub det: Vec<IntervalBox>,
    /// Heading (unicycle2d) or yaw (auv3d) at each detection's step, for the
    /// bearing constraint.
    pub heading_at: Vec<Interval>,
}

impl Model {
    /// Builds the domains: p(0) = initial box, p(N) = final box when known,
    /// every other position unbounded; detection boxes from their region,
    /// depth and the mission's landmark region. O(N).
    pub fn new(m: &Mission) -> Model {
        let dim = m.model.dim();
        let n = m.steps;
        let mut disp = Vec::with_capacity(n * dim);
        match m.model {
            MotionModel::Unicycle2d => {
                for i in 0..n {
                    let d = unicycle_displacement(
                        m.dt,
                        m.inputs[0][i],
                        m.inputs[1][i],
                        m.motion_error[i],
                    );
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
        let mut pos = vec![Interval::ENTIRE; (n + 1) * dim];
        pos[..dim].copy_from_slice(m.initial_position.axes());
        if let Some(f) = &m.final_position {
            for a in 0..dim {
                pos[n * dim + a] = pos[n * dim + a].intersect(f[a]);
            }
        }
        let heading_channel = match m.model {
            MotionModel::Unicycle2d => 1,
            MotionModel::Auv3d => 2,
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
            heading_at.push(m.inputs[heading_channel][d.step.min(n - 1)]);
        }
        Model {
            dim,
            steps: n,
            disp,
            pos,
            det,
            heading_at,
        }
    }

    /// The box of p(i).
    pub fn position(&self, i: usize) -> IntervalBox {
        IntervalBox::new(&self.pos[i * self.dim..(i + 1) * self.dim])
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
