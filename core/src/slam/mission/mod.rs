//! `nvector-mission/1`, the typed mission (docs/formats.md, "Mission"):
//! the types here, their validation from the parsed document in
//! [`validate`] (every invalid input gets an [`InputError`] naming the
//! JSON path of the bad value), the writer back to the spec's format in
//! [`write`], and the mission restated from p for the parts of the solver
//! that know no sensor offset ([`Mission::seen_from_p`]).

use crate::error::InputError;
use crate::format;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::odometry::drift::DriftWindow;
use crate::odometry::motion_drift::MotionWindow;
use serde::{Serialize, Serializer};
use serde_json::Value;
use std::borrow::Cow;

mod validate;
mod write;

#[cfg(test)]
mod tests;

/// Format tag of a mission.
pub const FORMAT: &str = "nvector-mission/1";
/// Most steps accepted.
pub const MAX_STEPS: usize = 2_000_000;

/// Most landmarks a simulation takes (every front end refuses more, naming
/// the option): the paper scenario's work grows with steps × landmarks.
pub const MAX_LANDMARKS: usize = 64;

/// The motion model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Model {
    /// Planar unicycle: inputs speed, heading.
    Unicycle2d,
    /// 3-D AUV: inputs roll, pitch, yaw, vx, vy, vz (body frame).
    Auv3d,
    /// Planar robot whose heading is integrated from its odometry: inputs
    /// speed, turn_rate; the heading is a state (docs/formats.md).
    Odometry2d,
}

impl Model {
    /// Dimension of a position.
    pub fn dim(self) -> usize {
        match self {
            Model::Unicycle2d | Model::Odometry2d => 2,
            Model::Auv3d => 3,
        }
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Model::Unicycle2d => "unicycle2d",
            Model::Auv3d => "auv3d",
            Model::Odometry2d => "odometry2d",
        }
    }

    /// Input channels, in order.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Model::Unicycle2d => &["speed", "heading"],
            Model::Auv3d => &["roll", "pitch", "yaw", "vx", "vy", "vz"],
            Model::Odometry2d => &["speed", "turn_rate"],
        }
    }
}

/// One landmark detection.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// Step of the robot position p(step), 0..=N.
    pub step: usize,
    /// Range to the landmark (lo >= 0).
    pub range: Interval,
    /// Angle of the landmark relative to the heading (2-D) or yaw (3-D).
    pub bearing: Option<Interval>,
    /// A box known to hold the landmark.
    pub region: Option<IntervalBox>,
    /// Interval of the landmark's z (auv3d).
    pub depth: Option<Interval>,
    /// Operator's matching: the landmark id.
    pub landmark: Option<usize>,
    /// The sensor scan the detection came from: detections of one scan see
    /// pairwise distinct landmarks (evidence the solver may use; any u64,
    /// sizing nothing).
    pub scan: Option<u64>,
}

/// Points of one dimension, stored flat (`points[i]` is the i-th point as
/// a slice): a trajectory of 10^6 points takes 16 MB, not one allocation
/// per point.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Points {
    dim: usize,
    flat: Vec<f64>,
}

impl Points {
    /// Points of dimension `dim` (>= 1) from their coordinates, point after
    /// point (`flat.len()` a multiple of `dim`).
    pub fn new(dim: usize, flat: Vec<f64>) -> Points {
        debug_assert!(dim >= 1 && flat.len().is_multiple_of(dim));
        Points { dim, flat }
    }

    /// Dimension of each point.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.flat.len().checked_div(self.dim).unwrap_or(0)
    }

    /// Whether there is no point.
    pub fn is_empty(&self) -> bool {
        self.flat.is_empty()
    }

    /// The points in order, each as a slice.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.flat.chunks_exact(self.dim.max(1))
    }
}

impl std::ops::Index<usize> for Points {
    type Output = [f64];

    fn index(&self, i: usize) -> &[f64] {
        &self.flat[i * self.dim..(i + 1) * self.dim]
    }
}

impl Serialize for Points {
    /// As JSON: an array of points, each an array of numbers.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

/// Ground truth of a simulated mission: used to score and draw, never read
/// by the solver.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// N+1 true positions.
    pub positions: Points,
    /// True landmark positions.
    pub landmarks: Points,
    /// For each detection, the true landmark index; `None` (JSON `null`)
    /// for a false detection (no landmark there).
    pub matching: Vec<Option<usize>>,
    /// Which entries of `positions` are known (`None`: all of them); an
    /// unknown one (JSON `null`, a motion-capture gap) holds zeros in
    /// `positions` and is not scored.
    pub positions_known: Option<Vec<bool>>,
    /// odometry2d: N+1 true headings, `None` where unknown.
    pub headings: Option<Vec<Option<f64>>>,
}

/// A validated mission.
#[derive(Debug, Clone, PartialEq)]
pub struct Mission {
    /// `name` field.
    pub name: String,
    /// Motion model.
    pub model: Model,
    /// Time step (s).
    pub dt: f64,
    /// N, the number of steps.
    pub steps: usize,
    /// Number of detections.
    pub detection_count: usize,
    /// Box of p(0).
    pub initial_position: IntervalBox,
    /// Box of p(N), when known.
    pub final_position: Option<IntervalBox>,
    /// Input channels in the order of [`Model::channels`], N intervals each.
    pub inputs: Vec<Vec<Interval>>,
    /// Per-step integration error bound (N entries).
    pub motion_error: Vec<f64>,
    /// Detections, in input order.
    pub detections: Vec<Detection>,
    /// n, the known number of landmarks (at most u32::MAX). An input
    /// number that the mission's size does not bound: n >= k (detections)
    /// constrains nothing more than n = k, and nothing may be sized by n.
    pub landmark_count: Option<usize>,
    /// A box holding every landmark.
    pub landmark_region: Option<IntervalBox>,
    /// q: at most this many detections may be false (`max_outliers`,
    /// default 0, at most u32::MAX). Carried for the propagator; q = 0
    /// changes nothing, and q >= k (detections) is the same as q = k, which
    /// is how the propagator reads it: nothing may be sized by q itself.
    pub max_outliers: usize,
    /// Free-form metadata, carried through.
    pub meta: Value,
    /// Ground truth (scoring and drawing only).
    pub truth: Option<Truth>,
    /// odometry2d: interval of the heading th(0) (required there, refused
    /// for the other models).
    pub initial_heading: Option<Interval>,
    /// odometry2d: interval of th(N), when known.
    pub final_heading: Option<Interval>,
    /// odometry2d: per-step heading integration error bound (N entries;
    /// empty for the other models).
    pub heading_error: Vec<f64>,
    /// odometry2d: the heading drift windows (`heading_drift`:
    /// `|th(i+k) - th(i) - sum dt turn_rate| <= b + sum of the exempt
    /// steps' heading_error`), k >= 1 (possibly above N: no constraint),
    /// b >= 0, `exempt_above` >= 0 when given (at most
    /// [`MAX_EXEMPT_LEVELS`](crate::odometry::drift::MAX_EXEMPT_LEVELS) distinct values); empty when none (always
    /// for the other models).
    pub heading_drift: Vec<DriftWindow>,
    /// odometry2d: the motion drift windows (`motion_drift`: the norm of
    /// `p(i+k) - p(i) - sum dt speed (cos th, sin th)` is at most c), k >= 1
    /// (possibly above N: no constraint), c >= 0; empty when none (always
    /// for the other models).
    pub motion_drift: Vec<MotionWindow>,
    /// Where the sensor sits in the body frame, metres forward and left of
    /// p (2-D models; `None` is `[0, 0]`).
    pub sensor_offset: Option<[f64; 2]>,
    /// Distinct landmarks are at least this far apart (metres, >= 0,
    /// default 0: no constraint).
    pub landmark_min_separation: f64,
}

impl Mission {
    /// Parses JSON text straight into typed data (the large arrays never
    /// become JSON values) and validates it; errors name the JSON path.
    pub fn from_json(text: &str) -> Result<Mission, InputError> {
        Mission::from_doc(format::from_str(text)?)
    }

    /// Parses and validates a mission; errors name the JSON path (the same
    /// as [`Mission::from_json`] of its text).
    pub fn from_value(v: &Value) -> Result<Mission, InputError> {
        Mission::from_doc(format::from_value(v)?)
    }

    /// The mission with every detection restated as seen from p itself
    /// (`sensor_offset` folded in, then dropped): for the parts of the
    /// solver that know no offset (the shapes reasoning, the robust
    /// propagation). Borrows `self` when it has no sensor offset (nothing
    /// to restate, no copy).
    ///
    /// Math: with the sensor at `p + R(th)·o`, the landmark is
    /// `d = p + R(th)·L`, `L = o + r·(cos b, sin b)`; so `|d - p| = |L|`
    /// and the direction of `d - p` is `th + angle(L)`. For the boxes
    /// `r`, `b`: range' = `sqrt(Lx² + Ly²)` over the box L (outward
    /// rounded), bearing' = the direction arc of the box L
    /// ([`crate::odometry::angle::box_angle`]; none when L may hold the
    /// origin). Without a bearing: range' = `r + [-|o|, |o|]` (cut at 0),
    /// no bearing.
    ///
    /// Soundness: the true (r, b) are in their intervals, so the true L is
    /// in the box L, its norm in range' and its angle in bearing' + 2πZ,
    /// which is how every bearing contractor reads a bearing. O(k).
    pub fn seen_from_p(&self) -> Cow<'_, Mission> {
        if !self.sensor_offset.is_some_and(|o| o != [0.0, 0.0]) {
            return Cow::Borrowed(self);
        }
        Cow::Owned(self.restated_from_p())
    }

    /// The restatement of [`Mission::seen_from_p`] (a copy).
    fn restated_from_p(&self) -> Mission {
        let mut m = self.clone();
        let Some(o) = m.sensor_offset.take() else {
            return m;
        };
        if o == [0.0, 0.0] {
            return m;
        }
        let (ox, oy) = (Interval::point(o[0]), Interval::point(o[1]));
        let norm = (ox.sqr() + oy.sqr()).sqrt();
        let half_line = Interval::new(0.0, f64::INFINITY);
        for d in &mut m.detections {
            let r = d.range.intersect(half_line);
            match d.bearing {
                Some(b) if !r.is_empty() && !b.is_empty() => {
                    let lx = ox + r * b.cos();
                    let ly = oy + r * b.sin();
                    d.range = (lx.sqr() + ly.sqr()).sqrt();
                    d.bearing = crate::odometry::angle::box_angle(lx, ly);
                }
                _ => {
                    let widened = r + Interval::new(-norm.hi(), norm.hi());
                    d.range = if r.is_empty() {
                        r
                    } else {
                        widened.intersect(half_line)
                    };
                    d.bearing = None;
                }
            }
        }
        m
    }
}
