//! What the check reports (a [`Violation`] per broken constraint) and the
//! sound measures it is decided with ([`gap`], [`angle_gap`]).

use crate::interval::Interval;
use crate::json;
use crate::odometry::angle::{contract_periodic, TWO_PI};
use crate::slam::mission::Mission;
use serde_json::{json, Value};

/// The kind of a constraint, with its unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A coordinate of p(0) outside `initial_position` (m).
    InitialPosition,
    /// A coordinate of p(N) outside `final_position` (m).
    FinalPosition,
    /// th(0) outside `initial_heading` (rad).
    InitialHeading,
    /// th(N) outside `final_heading` (rad).
    FinalHeading,
    /// A step's position residual beyond its `motion_error` (m, per axis).
    MotionStep,
    /// An odometry2d step's heading residual beyond its `heading_error`
    /// (rad).
    HeadingStep,
    /// A `heading_drift` window's residual beyond its bound (rad).
    HeadingDrift,
    /// A `motion_drift` window's residual norm beyond its bound (m).
    MotionDrift,
    /// The distance from the sensor to the landmark outside `range` (m).
    Range,
    /// The landmark's direction outside `bearing` (rad, modulo 2π).
    Bearing,
    /// Range and bearing each hold but no heading of the step's interval
    /// satisfies both (the solver's detection contractor proves it).
    Detection,
    /// A landmark coordinate outside the detection's `region` (m).
    Region,
    /// The landmark's z outside the detection's `depth` (m).
    Depth,
    /// Detections with one operator `landmark` id that see different true
    /// landmarks (detections).
    Landmark,
    /// Two detections of one `scan` that see one landmark (detections).
    Scan,
    /// A landmark coordinate outside `landmark_region` (m).
    LandmarkRegion,
    /// More landmarks seen than `landmark_count` (landmarks).
    LandmarkCount,
    /// Two landmarks seen closer than `landmark_min_separation` (m).
    LandmarkMinSeparation,
}

impl Kind {
    /// The name in the JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Kind::InitialPosition => "initial_position",
            Kind::FinalPosition => "final_position",
            Kind::InitialHeading => "initial_heading",
            Kind::FinalHeading => "final_heading",
            Kind::MotionStep => "motion_step",
            Kind::HeadingStep => "heading_step",
            Kind::HeadingDrift => "heading_drift",
            Kind::MotionDrift => "motion_drift",
            Kind::Range => "range",
            Kind::Bearing => "bearing",
            Kind::Detection => "detection",
            Kind::Region => "region",
            Kind::Depth => "depth",
            Kind::Landmark => "landmark",
            Kind::Scan => "scan",
            Kind::LandmarkRegion => "landmark_region",
            Kind::LandmarkCount => "landmark_count",
            Kind::LandmarkMinSeparation => "landmark_min_separation",
        }
    }

    /// The unit of the value, bound and excess.
    pub fn unit(self) -> &'static str {
        match self {
            Kind::InitialHeading
            | Kind::FinalHeading
            | Kind::HeadingStep
            | Kind::HeadingDrift
            | Kind::Bearing => "rad",
            Kind::Detection | Kind::Landmark | Kind::Scan => "detections",
            Kind::LandmarkCount => "landmarks",
            _ => "m",
        }
    }

    /// Whether the constraint is one detection's (dropping the detection
    /// removes it: what `max_outliers` allows).
    pub fn of_a_detection(self) -> bool {
        matches!(
            self,
            Kind::Range
                | Kind::Bearing
                | Kind::Detection
                | Kind::Region
                | Kind::Depth
                | Kind::Landmark
                | Kind::Scan
        )
    }
}

/// The bound a value must keep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// The value must lie in `[lo, hi]` (bounds may be infinite).
    Within(f64, f64),
    /// The value must be at most this.
    AtMost(f64),
    /// The value must be at least this.
    AtLeast(f64),
}

impl Bound {
    fn to_json(self) -> Value {
        match self {
            Bound::Within(lo, hi) => json!([json::bound_to_json(lo), json::bound_to_json(hi)]),
            Bound::AtMost(x) | Bound::AtLeast(x) => json::bound_to_json(x),
        }
    }

    fn relation(self) -> &'static str {
        match self {
            Bound::Within(..) => "within",
            Bound::AtMost(_) => "at_most",
            Bound::AtLeast(_) => "at_least",
        }
    }
}

/// One constraint the truth breaks.
#[derive(Debug, Clone, PartialEq)]
pub struct Violation {
    /// The JSON path of the constraint in the mission (e.g.
    /// `detections[5].range`, `motion_error[12]`, `heading_drift[0]`).
    pub path: String,
    /// What kind of constraint.
    pub kind: Kind,
    /// The step it is about (a step's, a window's first step, a
    /// detection's step), when one.
    pub step: Option<usize>,
    /// The detection it is about, when one.
    pub detection: Option<usize>,
    /// The landmark it is about (the detection's true landmark, or the
    /// landmark it was measured against), when one.
    pub landmark: Option<usize>,
    /// The second landmark of a pair (`landmark_min_separation`).
    pub other_landmark: Option<usize>,
    /// The truth's value (a coordinate, a residual, a distance, an angle,
    /// a count), in [`Kind::unit`].
    pub value: f64,
    /// The bound the value breaks.
    pub bound: Bound,
    /// How far beyond the bound, a lower bound rounded down (> 0 when the
    /// check proved the violation itself; 0 when only the solver's own
    /// contractor, which rounds its own way, proves it).
    pub excess: f64,
    /// A detection's violation that `max_outliers` covers: the broken
    /// detections are no more than `max_outliers` (docs/formats.md).
    pub outlier: bool,
}

impl Violation {
    /// A violation at `path` of `kind` (no step, detection, landmark).
    pub fn new(path: impl Into<String>, kind: Kind, value: f64, bound: Bound, excess: f64) -> Self {
        Violation {
            path: path.into(),
            kind,
            step: None,
            detection: None,
            landmark: None,
            other_landmark: None,
            value,
            bound,
            excess: excess.max(0.0),
            outlier: false,
        }
    }

    /// With its step.
    pub fn at_step(mut self, step: usize) -> Self {
        self.step = Some(step);
        self
    }

    /// With its detection and landmark.
    pub fn of(mut self, detection: Option<usize>, landmark: Option<usize>) -> Self {
        self.detection = detection;
        self.landmark = landmark;
        self
    }

    /// As JSON (docs/formats.md, "Check").
    pub fn to_json(&self) -> Value {
        let mut o = json!({
            "path": self.path,
            "kind": self.kind.name(),
            "unit": self.kind.unit(),
            "value": json::bound_to_json(self.value),
            "bound": self.bound.to_json(),
            "relation": self.bound.relation(),
            "excess": json::bound_to_json(self.excess),
            "outlier": self.outlier,
        });
        for (k, v) in [
            ("step", self.step),
            ("detection", self.detection),
            ("landmark", self.landmark),
            ("other_landmark", self.other_landmark),
        ] {
            if let Some(v) = v {
                o[k] = v.into();
            }
        }
        o
    }
}

/// The truth of a mission as the check reads it: a position or heading
/// is `None` where the truth does not know it.
pub struct Truthy<'a> {
    /// The mission.
    pub m: &'a Mission,
    /// Constraints left unchecked because the truth does not know a value
    /// they need.
    pub unchecked: usize,
}

impl<'a> Truthy<'a> {
    /// The true p(i), when known.
    pub fn position(&self, i: usize) -> Option<&'a [f64]> {
        let t = self.m.truth.as_ref()?;
        if t.positions_known.as_ref().is_some_and(|k| !k[i]) {
            return None;
        }
        Some(&t.positions[i])
    }

    /// The true th(i) (odometry2d), when known.
    pub fn heading(&self, i: usize) -> Option<f64> {
        let t = self.m.truth.as_ref()?;
        t.headings.as_ref()?.get(i).copied().flatten()
    }
}

/// A lower bound, rounded down, of the distance from the interval `x` to
/// the interval `b` (0 when they meet or either is empty).
pub fn gap(x: Interval, b: Interval) -> f64 {
    if x.is_empty() || b.is_empty() {
        return 0.0;
    }
    let d = if x.lo() > b.hi() {
        Interval::point(x.lo()).sub(Interval::point(b.hi())).lo()
    } else if x.hi() < b.lo() {
        Interval::point(b.lo()).sub(Interval::point(x.hi())).lo()
    } else {
        0.0
    };
    if d.is_nan() {
        0.0
    } else {
        d.max(0.0)
    }
}

/// The gap of `x` to `b` as a value and an excess: the bound of `x`
/// nearest to `b` (its value) and [`gap`].
pub fn nearest(x: Interval, b: Interval) -> f64 {
    if x.lo() > b.hi() {
        x.lo()
    } else if x.hi() < b.lo() {
        x.hi()
    } else {
        x.lo().max(b.lo()).min(x.hi())
    }
}

/// `x - y` rounded down (a lower bound of an excess).
pub fn minus_down(x: f64, y: f64) -> f64 {
    if !(x.is_finite() && y.is_finite()) {
        return 0.0;
    }
    Interval::point(x).sub(Interval::point(y)).lo()
}

/// `x + y` rounded up (an upper bound of a sum of bounds).
pub fn plus_up(x: f64, y: f64) -> f64 {
    if !(x.is_finite() && y.is_finite()) {
        return f64::INFINITY;
    }
    Interval::point(x).add(Interval::point(y)).hi()
}

/// A lower bound, rounded down, of the distance between the angle `a`
/// and the arc `b` modulo 2π: 0 when some copy `b + 2πk` meets `a`
/// ([`contract_periodic`], the solver's test), else the least gap over
/// the copies next to `a`.
pub fn angle_gap(a: Interval, b: Interval) -> f64 {
    if a.is_empty() || b.is_empty() || !contract_periodic(a, b).is_empty() {
        return 0.0;
    }
    let k = ((a.mid() - b.mid()) / TWO_PI.mid()).round();
    [k - 1.0, k, k + 1.0]
        .iter()
        .map(|&k| gap(a, b + TWO_PI.scale(k)))
        .fold(f64::INFINITY, f64::min)
}

/// The copy of the angle `a`'s nearest bound to the arc `b`, brought
/// within a turn of `b` (a value to print; not used to decide).
pub fn angle_value(a: Interval, b: Interval) -> f64 {
    let k = ((a.mid() - b.mid()) / TWO_PI.mid()).round();
    nearest(a - TWO_PI.scale(k), b)
}
