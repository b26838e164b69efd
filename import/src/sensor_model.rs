//! `nvector-sensor-model/1`: a robot's error bounds, fitted once on a run
//! with truth ([`crate::calibrate`]) and applied to runs without it
//! ([`crate::apply`]). docs/formats.md documents the file, docs/calibration.md
//! the workflow.
//!
//! Every bound carries its [`Fit`]: the method, the relative and absolute
//! margins, the samples it was fitted on, its coverage of them and the
//! span of the measured quantity it was fitted over (a run that measures
//! beyond that span extrapolates, and `apply` says so in the mission's
//! `meta`).

use serde::{Deserialize, Serialize};

/// The `format` of a sensor model file.
pub const FORMAT: &str = "nvector-sensor-model/1";

/// A sensor model: the bounds of one robot's odometry and exteroceptive
/// sensor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorModel {
    /// Always [`FORMAT`].
    pub format: String,
    /// The motion model: `odometry2d` or `unicycle2d`.
    pub model: String,
    /// What the model was fitted on.
    pub calibration: Calibration,
    /// The speed channel's bound.
    pub speed: SpeedBound,
    /// `unicycle2d`: the bound of the heading channel (rad); `odometry2d`:
    /// the per-step heading integration error `heading_error` (rad).
    pub heading: Bound,
    /// The per-step integration error of the position, per axis (m).
    pub motion_error: Bound,
    /// `odometry2d`: the heading drift windows (`heading_drift` of the
    /// mission, without exemptions).
    #[serde(default)]
    pub heading_drift: Vec<Window>,
    /// `odometry2d`: the motion drift windows (`motion_drift`).
    #[serde(default)]
    pub motion_drift: Vec<Window>,
    /// The range band: measured - true range, in the measured range.
    pub range: Band,
    /// The bearing band: measured - true bearing, in 1 / measured range
    /// (absent: range-only detections).
    #[serde(default)]
    pub bearing: Option<Band>,
    /// Where the range-and-bearing sensor sits in the body frame (m,
    /// forward and left), as given to the calibration.
    pub sensor_offset: [f64; 2],
    /// The bounds the data could not support, each with its reason.
    #[serde(default)]
    pub refused: Vec<Refusal>,
    /// Same-run calibration only: the steps of the calibration log that
    /// the truth flagged, each with its own bound; applied only to that
    /// log (its fingerprint), refused on another.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flagged: Option<Flagged>,
}

/// The flagged steps of a same-run calibration (docs/calibration.md,
/// "Same-run calibration"): a step whose residual is above `above` gets
/// its own bound, `factor` x its residual + `margin`, and the per-step
/// bound is fitted on the other steps. A step touching a gap of the truth
/// (completed across it, `complete_gaps`) gets at least the largest
/// ordinary heading bound + `gap_heading_margin`, so the drift windows
/// exempt it. Only the run that flagged them has these steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Flagged {
    /// The method, in words.
    pub method: String,
    /// A heading residual above this flags its step (rad; `None`: no
    /// heading step is flagged).
    pub heading_above: Option<f64>,
    /// A motion residual above this flags its step (m per axis).
    pub motion_above: Option<f64>,
    /// The factor on a flagged step's residual.
    pub factor: f64,
    /// The margin added after it.
    pub margin: f64,
    /// Whether the truth was completed across its gaps (linear
    /// interpolation between the known ends; after the last, dead
    /// reckoning) for the per-step bounds and the drift windows.
    pub complete_gaps: bool,
    /// A step touching a gap has a heading bound at least the largest
    /// ordinary one plus this (rad).
    pub gap_heading_margin: f64,
    /// `(step, bound)` of the flagged heading steps (and the gap steps).
    pub heading: Vec<(usize, f64)>,
    /// `(step, bound)` of the flagged motion steps.
    pub motion: Vec<(usize, f64)>,
}

/// The zero-velocity class of the motion error: a step whose reported
/// distance |speed|·dt is below `below` gets `error` instead of the
/// affine bound (a robot the odometry sees standing still does not
/// drift).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Still {
    /// The reported distance below which a step is still (m).
    pub below: f64,
    /// The motion error of a still step (m per axis).
    pub error: f64,
    /// How it was fitted.
    pub fit: Fit,
}

/// What a model was fitted on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Calibration {
    /// The calibration run, as the user named it (its log file and time
    /// span).
    pub source: String,
    /// A digest of the calibration log's numbers: a mission built from the
    /// same log is calibrated on its own run (`meta.calibration.same_run`).
    pub fingerprint: String,
    /// Steps of the calibration log.
    pub steps: usize,
    /// Time step of the calibration log (s).
    pub dt: f64,
    /// Detections of the calibration run.
    pub detections: usize,
    /// Steps without a true position or heading at one of their ends.
    pub truth_gaps: usize,
    /// The relative margin F: every fitted bound is multiplied by 1 + F
    /// before its absolute margin is added.
    pub relative_margin: f64,
    /// The fewest samples a bound may be fitted on for this F
    /// (docs/calibration.md, "How many samples").
    pub min_samples: usize,
}

/// How a bound was obtained and how well it holds on its own data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fit {
    /// The method, in words.
    pub method: String,
    /// The relative margin F applied.
    pub relative_margin: f64,
    /// The absolute margin added after it.
    pub margin: f64,
    /// Samples the bound was fitted on (for a window: the pairs of steps;
    /// `independent` counts the disjoint windows among them).
    pub samples: usize,
    /// Disjoint samples (windows that share no step); equals `samples`
    /// for per-step bounds and detections.
    pub independent: usize,
    /// Share of the samples inside the final bound (1 when every one is).
    pub coverage: f64,
    /// The largest |residual| among the samples.
    pub largest_residual: f64,
    /// The span of the measured quantity the bound was fitted over
    /// ([0, 0] for a constant bound).
    pub span: [f64; 2],
}

/// What an affine bound grows with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// Nothing: a constant bound.
    None,
    /// The distance the odometry reports for the step, |speed|·dt (m).
    Distance,
    /// The turn the odometry reports for the step, |turn_rate|·dt (rad).
    Turn,
}

/// A bound affine in one measured quantity x of the step:
/// `constant + slope·x`, margins included (slope >= 0: the bound never
/// shrinks as x grows).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bound {
    /// The bound at x = 0.
    pub constant: f64,
    /// Its growth per unit of x.
    pub slope: f64,
    /// What x is.
    pub of: Measure,
    /// `motion_error`: its growth per radian of the step's turn as the log
    /// reports it (odometry2d |turn_rate|·dt, unicycle2d the measured
    /// heading's change to the next step), >= 0; 0 for the other bounds.
    #[serde(default)]
    pub turn_slope: f64,
    /// `motion_error`: the zero-velocity class, when fitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub still: Option<Still>,
    /// How it was fitted.
    pub fit: Fit,
}

impl Bound {
    /// The bound at x (a step without turn).
    pub fn at(&self, x: f64) -> f64 {
        self.constant + self.slope * x
    }

    /// The bound of a step at x that turns by `turn` (rad): the still
    /// class's below its distance.
    pub fn at_step(&self, x: f64, turn: f64) -> f64 {
        match &self.still {
            Some(s) if x < s.below => s.error,
            _ => self.at(x) + self.turn_slope * turn,
        }
    }
}

/// The speed channel: `[v - e, v + e]` with e the [`Bound`] (in the
/// step's distance), and below `sign_unknown_below` (m/s) the sign of the
/// speed is unknown: `[-(|v| + e), |v| + e]` (an odometer that reports a
/// distance without its sign, seen backing up in the calibration run).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedBound {
    /// The error of the speed (m/s).
    pub error: Bound,
    /// Below this measured |speed| the true speed may have either sign.
    #[serde(default)]
    pub sign_unknown_below: Option<f64>,
}

/// A drift window: over k steps the residual is at most `error`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Window {
    /// k.
    pub steps: usize,
    /// The bound (rad for heading windows, m for motion windows).
    pub error: f64,
    /// Heading windows of a same-run calibration: the steps whose heading
    /// bound is above this are exempt (the mission's `exempt_above`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exempt_above: Option<f64>,
    /// How it was fitted.
    pub fit: Fit,
}

/// What a band's lines are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BandOf {
    /// The measured range r (m).
    Range,
    /// 1 / max(r, `min_range`) (1/m).
    InverseRange,
}

/// A residual band: measured - true lies in
/// `[max(constant[0], -(lower[0] + lower[1]·x)), min(constant[1], upper[0] + upper[1]·x)]`,
/// widened on each side by `relative_margin` × its half-width plus
/// `margin` (the [`Fit`]'s). Outside the fitted span of x the band is the
/// union of the band at x and at x clamped into the span (a line is never
/// trusted to narrow the band where it was not fitted).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Band {
    /// The line above the residuals: `[intercept, slope]`.
    pub upper: [f64; 2],
    /// The line above the negated residuals: `[intercept, slope]`.
    pub lower: [f64; 2],
    /// The smallest and largest residual.
    pub constant: [f64; 2],
    /// What x is.
    pub of: BandOf,
    /// For [`BandOf::InverseRange`]: the smallest r used in 1/r (m).
    #[serde(default)]
    pub min_range: f64,
    /// How it was fitted.
    pub fit: Fit,
}

impl Band {
    /// The band's x for a measured range.
    pub fn x(&self, range: f64) -> f64 {
        match self.of {
            BandOf::Range => range,
            BandOf::InverseRange => 1.0 / range.max(self.min_range),
        }
    }

    /// The residual's interval at x, before the margins.
    fn raw(&self, x: f64) -> (f64, f64) {
        let lo = self.constant[0].max(-(self.lower[0] + self.lower[1] * x));
        let hi = self.constant[1].min(self.upper[0] + self.upper[1] * x);
        if lo <= hi {
            (lo, hi)
        } else {
            (self.constant[0], self.constant[1])
        }
    }

    /// The residual's interval at x, margins included (module doc of
    /// [`Band`]), and whether x lies outside the fitted span.
    pub fn at(&self, x: f64) -> ((f64, f64), bool) {
        let [a, b] = self.fit.span;
        let inside = (a..=b).contains(&x);
        let (mut lo, mut hi) = self.raw(x);
        if !inside {
            let (l2, h2) = self.raw(x.clamp(a, b));
            (lo, hi) = (lo.min(l2), hi.max(h2));
        }
        let widen = self.fit.relative_margin * (hi - lo) / 2.0 + self.fit.margin;
        ((lo - widen, hi + widen), !inside)
    }

    /// The interval of the true value for a measurement `m` whose range is
    /// `range`: `[m - hi, m - lo]`, and whether it extrapolates.
    pub fn interval(&self, m: f64, range: f64) -> ([f64; 2], bool) {
        let ((lo, hi), outside) = self.at(self.x(range));
        ([m - hi, m - lo], outside)
    }
}

/// A bound the calibration did not fit, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Refusal {
    /// The bound (`heading`, `heading_drift[k=120]`, ...).
    pub bound: String,
    /// Why, in words.
    pub reason: String,
}

impl SensorModel {
    /// The flagged bound of step `step` in `steps`, when the model is
    /// applied to its own calibration run (`same_run`).
    fn flagged_at(steps: Option<&Vec<(usize, f64)>>, step: usize, same_run: bool) -> Option<f64> {
        let steps = steps.filter(|_| same_run)?;
        let i = steps.binary_search_by_key(&step, |x| x.0).ok()?;
        Some(steps[i].1)
    }

    /// The per-step heading bound of odometry2d at step `step` turning by
    /// `turn` (rad): the flagged step's own on the calibration run.
    pub fn heading_error_at(&self, step: usize, turn: f64, same_run: bool) -> f64 {
        let flagged = self.flagged.as_ref().map(|f| &f.heading);
        Self::flagged_at(flagged, step, same_run).unwrap_or_else(|| self.heading.at(turn))
    }

    /// The per-step motion bound at step `step` of reported distance
    /// `dist` turning by `turn`: the flagged step's own on the calibration
    /// run.
    pub fn motion_error_at(&self, step: usize, dist: f64, turn: f64, same_run: bool) -> f64 {
        let flagged = self.flagged.as_ref().map(|f| &f.motion);
        Self::flagged_at(flagged, step, same_run)
            .unwrap_or_else(|| self.motion_error.at_step(dist, turn))
    }

    /// Parses a sensor model, naming the JSON path of a bad field.
    pub fn from_json(text: &str) -> Result<SensorModel, String> {
        let de = &mut serde_json::Deserializer::from_str(text);
        let m: SensorModel = serde::Deserialize::deserialize(de).map_err(|e| e.to_string())?;
        if m.format != FORMAT {
            return Err(format!(
                "format: expected \"{FORMAT}\", found \"{}\"",
                m.format
            ));
        }
        if m.model != "odometry2d" && m.model != "unicycle2d" {
            return Err(format!(
                "model: expected odometry2d or unicycle2d, found \"{}\"",
                m.model
            ));
        }
        m.check_numbers()?;
        Ok(m)
    }

    /// Every bound finite and >= 0 where a bound must be (an error names
    /// the bound).
    pub fn check_numbers(&self) -> Result<(), String> {
        let bound = |name: &str, b: &Bound| {
            let ok = |x: f64| x.is_finite() && x >= 0.0;
            if ok(b.constant) && ok(b.slope) && ok(b.turn_slope) {
                Ok(())
            } else {
                Err(format!(
                    "{name}: constant, slope and turn_slope must be finite numbers >= 0"
                ))
            }
        };
        bound("speed.error", &self.speed.error)?;
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if let Some(s) = &self.motion_error.still {
            if !(ok(s.below) && ok(s.error)) {
                return Err(
                    "motion_error.still: below and error must be finite numbers >= 0".into(),
                );
            }
        }
        if let Some(f) = &self.flagged {
            for (name, steps) in [("heading", &f.heading), ("motion", &f.motion)] {
                if let Some((i, _)) = steps.iter().enumerate().find(|(_, s)| !ok(s.1)) {
                    return Err(format!(
                        "flagged.{name}[{i}]: the bound must be a finite number >= 0"
                    ));
                }
            }
        }
        bound("heading", &self.heading)?;
        bound("motion_error", &self.motion_error)?;
        for (name, ws) in [
            ("heading_drift", &self.heading_drift),
            ("motion_drift", &self.motion_drift),
        ] {
            for (i, w) in ws.iter().enumerate() {
                if w.steps == 0 || !(w.error.is_finite() && w.error >= 0.0) {
                    return Err(format!(
                        "{name}[{i}]: steps must be >= 1 and error a finite number >= 0"
                    ));
                }
            }
        }
        for (name, b) in [
            ("range", Some(&self.range)),
            ("bearing", self.bearing.as_ref()),
        ] {
            let Some(b) = b else { continue };
            let all = [b.upper, b.lower, b.constant, b.fit.span]
                .iter()
                .flatten()
                .all(|x| x.is_finite());
            if !all || b.fit.margin < 0.0 || b.fit.relative_margin < 0.0 {
                return Err(format!(
                    "{name}: the band's numbers must be finite, its margins >= 0"
                ));
            }
        }
        if !self.sensor_offset.iter().all(|x| x.is_finite()) {
            return Err("sensor_offset: expected two finite numbers".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fit(span: [f64; 2]) -> Fit {
        Fit {
            method: String::new(),
            relative_margin: 0.1,
            margin: 0.01,
            samples: 100,
            independent: 100,
            coverage: 1.0,
            largest_residual: 1.0,
            span,
        }
    }

    /// A band whose lines narrow it as x grows (a negative slope above)
    /// is never trusted beyond its span: outside, it is at least as wide
    /// as at the span's end, and holds the band there.
    #[test]
    fn a_band_never_narrows_outside_its_span() {
        let b = Band {
            upper: [0.5, -0.1],
            lower: [0.2, 0.05],
            constant: [-1.0, 1.0],
            of: BandOf::Range,
            min_range: 0.0,
            fit: fit([1.0, 4.0]),
        };
        let ((lo4, hi4), out4) = b.at(4.0);
        assert!(!out4);
        for x in [4.5, 10.0, 1e6, 1e300] {
            let ((lo, hi), outside) = b.at(x);
            assert!(outside && lo <= lo4 && hi >= hi4, "x = {x}: [{lo}, {hi}]");
        }
        let ((lo1, hi1), _) = b.at(1.0);
        for x in [0.0, 0.5, 0.999] {
            let ((lo, hi), outside) = b.at(x);
            assert!(outside && lo <= lo1 && hi >= hi1, "x = {x}");
        }
        // Crossing lines fall back to the constant band, never an empty one.
        let crossing = Band {
            upper: [-5.0, 0.0],
            ..b.clone()
        };
        let ((lo, hi), _) = crossing.at(2.0);
        assert!(lo <= -1.0 && hi >= 1.0);
        // The true value's interval is [m - hi, m - lo].
        let ([a, c], _) = b.interval(10.0, 2.0);
        let ((lo, hi), _) = b.at(2.0);
        assert_eq!([a, c], [10.0 - hi, 10.0 - lo]);
    }

    #[test]
    fn a_negative_or_infinite_bound_is_refused_naming_it() {
        let b = Bound {
            constant: f64::INFINITY,
            slope: 0.0,
            turn_slope: 0.0,
            still: None,
            of: Measure::None,
            fit: fit([0.0, 0.0]),
        };
        let band = Band {
            upper: [0.0, 0.0],
            lower: [0.0, 0.0],
            constant: [0.0, 0.0],
            of: BandOf::Range,
            min_range: 0.0,
            fit: fit([0.0, 1.0]),
        };
        let mut m = SensorModel {
            format: FORMAT.into(),
            model: "odometry2d".into(),
            calibration: Calibration {
                source: String::new(),
                fingerprint: String::new(),
                steps: 1,
                dt: 0.1,
                detections: 0,
                truth_gaps: 0,
                relative_margin: 0.1,
                min_samples: 73,
            },
            speed: SpeedBound {
                error: Bound {
                    constant: 0.0,
                    ..b.clone()
                },
                sign_unknown_below: None,
            },
            heading: b.clone(),
            motion_error: Bound {
                constant: 0.1,
                ..b.clone()
            },
            heading_drift: vec![],
            motion_drift: vec![],
            range: band,
            bearing: None,
            sensor_offset: [0.0, 0.0],
            refused: vec![],
            flagged: None,
        };
        assert!(m.check_numbers().unwrap_err().starts_with("heading"));
        m.heading.constant = 0.1;
        m.motion_error.slope = -1.0;
        assert!(m.check_numbers().unwrap_err().starts_with("motion_error"));
        m.motion_error.slope = 0.0;
        m.check_numbers().unwrap();
    }
}
