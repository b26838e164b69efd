//! The calibration: a [`SensorModel`] fitted on a run with truth, one
//! fitting code for every robot (docs/calibration.md).
//!
//! Pipeline: [`data::read_run`] reads the CSVs; [`residuals`] gives the
//! truth's residual against each part of the model (only where the truth
//! is known: a gap removes its steps); [`fit`] bounds them; [`calibrate`]
//! assembles the model and refuses, naming the reason, a bound the data
//! cannot support; [`verify`] counts the samples of another run with truth
//! that a model leaves outside.

pub mod convert;
pub mod data;
pub mod fit;
pub mod residuals;
pub mod same_run;

use crate::sensor_model::{
    BandOf, Bound, Calibration, Fit, Flagged, Measure, Refusal, SensorModel, SpeedBound, Still,
    Window, FORMAT,
};
use crate::ImportError;
use data::{Model, Run};
use residuals as res;

/// The absolute margins added after the relative one (docs/calibration.md).
pub mod margins {
    /// Per-step heading (rad).
    pub const HEADING: f64 = 0.005;
    /// Per-step motion, per axis (m).
    pub const MOTION: f64 = 0.005;
    /// The speed below which its sign is unknown (m/s).
    pub const SPEED_SIGN: f64 = 0.01;
    /// The range band, each side (m).
    pub const RANGE: f64 = 0.01;
    /// The bearing band, each side (rad).
    pub const BEARING: f64 = 0.01;
    /// A heading window (rad).
    pub const HEADING_WINDOW: f64 = 0.02;
    /// A motion window (m).
    pub const MOTION_WINDOW: f64 = 0.01;
    /// The bearing band's 1/r takes r at least this (m).
    pub const MIN_RANGE_FOR_BEARING: f64 = 0.1;
    /// A residual whose every sample is at most this is "identically 0".
    pub const ZERO: f64 = 1e-9;
    /// The still class of the motion error (m).
    pub const STILL: f64 = 0.001;
}

/// The heading windows also given without exemptions when some steps are
/// exempt (steps): over hundreds of steps the exempt steps' own bounds add
/// up to more than the drift they leave out.
pub const PLAIN_HEADING_WINDOWS: [usize; 6] = [30, 100, 300, 1000, 3000, 10000];

/// The heading windows tried (steps): every k of 2..=50 (the gaps
/// between sightings of a returning landmark), then a geometric ladder.
pub fn heading_windows() -> impl Iterator<Item = usize> {
    (2..=50).chain([60, 80, 100, 150, 200, 300, 1000, 3000, 10000])
}

/// The motion windows tried (steps).
pub fn motion_windows() -> impl Iterator<Item = usize> {
    (3..=60).chain([80, 100, 150, 200, 300])
}

/// What the user gives a calibration besides the data.
#[derive(Clone, Debug)]
pub struct Options {
    /// The relative margin F (> 0) of every bound [`Options::bound_margins`]
    /// does not name.
    pub relative_margin: f64,
    /// A relative margin per bound, `(name, F)`, the names of
    /// [`BOUND_NAMES`]: raise the margin of the bounds a check on a second
    /// run finds broken, and only theirs (docs/calibration.md, step 3).
    pub bound_margins: Vec<(String, f64)>,
    /// Where the sensor sits in the body frame (m).
    pub sensor_offset: [f64; 2],
    /// A heading bound the user states instead of fitting it (rad), for a
    /// truth whose heading cannot calibrate it.
    pub assume_heading: Option<f64>,
    /// What the run is, for the model's `calibration.source`.
    pub source: String,
    /// A same-run calibration (the oracle): the model is for this run
    /// alone. The sample rule does not apply (a bound claims this run's
    /// samples, all of which it covers), F may be 0, and `flag` may give
    /// steps their own bounds.
    pub same_run: bool,
    /// Same-run only: the flagged steps and the completion of the truth
    /// across its gaps.
    pub flag: Option<Flag>,
    /// The zero-velocity class of the motion error: the steps reporting
    /// a distance |speed|·dt below this (m) get their own bound, fitted on
    /// theirs.
    pub still_below: Option<f64>,
    /// The per-step bounds (heading, motion error) constant, the largest
    /// residual, instead of affine in the step's distance and turn.
    pub constant_steps: bool,
    /// The share P of the detections' residuals each band leaves out
    /// (0 <= P < 0.5): floor(P k / 2) below, the rest of floor(P k)
    /// above (docs/outliers.md); the readings then outside are counted.
    pub outlier_share: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            relative_margin: 0.1,
            bound_margins: Vec::new(),
            sensor_offset: [0.0, 0.0],
            assume_heading: None,
            source: String::new(),
            same_run: false,
            flag: None,
            still_below: None,
            constant_steps: false,
            outlier_share: 0.0,
        }
    }
}

/// The flagged steps of a same-run calibration ([`Flagged`]).
#[derive(Clone, Copy, Debug)]
pub struct Flag {
    /// A per-step heading residual above this flags its step (rad).
    pub heading_above: Option<f64>,
    /// A per-step motion residual above this flags its step (m per axis).
    pub motion_above: Option<f64>,
    /// A flagged step's bound: its residual x `factor` + `margin`.
    pub factor: f64,
    /// See `factor`.
    pub margin: f64,
    /// Complete the truth across its gaps for the per-step bounds and the
    /// windows ([`same_run::complete`]), the steps touching a gap exempt
    /// from the heading windows.
    pub complete_gaps: bool,
}

/// A step touching a gap of the truth has a heading bound at least the
/// largest ordinary one plus this (rad): the drift windows exempt it.
pub const GAP_HEADING_MARGIN: f64 = 1e-6;

/// The bounds a relative margin may be given for (`--margin NAME=F`).
pub const BOUND_NAMES: [&str; 6] = [
    "heading",
    "motion_error",
    "heading_drift",
    "motion_drift",
    "range",
    "bearing",
];

impl Options {
    /// The fewest samples a bound with margin F needs: the sample rule's
    /// ([`fit::min_samples`]), 1 on the same run.
    pub fn min_samples(&self, f: f64) -> usize {
        if self.same_run {
            1
        } else {
            fit::min_samples(f)
        }
    }

    /// The relative margin F of `bound` (one of [`BOUND_NAMES`]).
    pub fn margin(&self, bound: &str) -> f64 {
        self.bound_margins
            .iter()
            .rev()
            .find(|(n, _)| n == bound)
            .map_or(self.relative_margin, |m| m.1)
    }

    /// Every margin a number > 0, every named bound one of
    /// [`BOUND_NAMES`].
    fn check(&self) -> Result<(), ImportError> {
        let same_run = self.same_run;
        let positive = |f: f64| f.is_finite() && (f > 0.0 || (same_run && f == 0.0));
        if self.flag.is_some() && !self.same_run {
            return Err(ImportError::setting(
                "flag",
                "flagged steps are a same-run calibration's: their bounds hold on the calibration run only",
            ));
        }
        if !(0.0..0.5).contains(&self.outlier_share) {
            return Err(ImportError::setting(
                "outlier_share",
                format!(
                    "--outlier-share must be in [0, 0.5), found {}",
                    self.outlier_share
                ),
            ));
        }
        if !positive(self.relative_margin) {
            return Err(ImportError::setting(
                "margin",
                format!(
                    "--margin must be a number > 0 (>= 0 on the same run), found {}",
                    self.relative_margin
                ),
            ));
        }
        for (name, f) in &self.bound_margins {
            if !BOUND_NAMES.contains(&name.as_str()) {
                return Err(ImportError::setting(
                    "margin",
                    format!(
                        "--margin {name}={f}: no bound '{name}' (expected one of {})",
                        BOUND_NAMES.join(", ")
                    ),
                ));
            }
            if !positive(*f) {
                return Err(ImportError::setting(
                    "margin",
                    format!("--margin {name}={f}: F must be a number > 0 (>= 0 on the same run)"),
                ));
            }
        }
        Ok(())
    }
}

/// `(step, bound)` of the flagged steps of one per-step bound.
type StepBounds = Vec<(usize, f64)>;

/// A bound refused, or fitted.
type Fitted<T> = Result<T, Refusal>;

fn refuse<T>(bound: &str, reason: String) -> Fitted<T> {
    Err(Refusal {
        bound: bound.into(),
        reason,
    })
}

/// Refuses too few samples or residuals identically 0.
fn enough(bound: &str, samples: &[f64], min: usize, what: &str) -> Fitted<()> {
    if samples.len() < min {
        return refuse(
            bound,
            format!(
                "too few samples: {} ({what}), at least {min} needed for this margin",
                samples.len()
            ),
        );
    }
    let largest = samples.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if largest <= margins::ZERO {
        return refuse(
            bound,
            format!(
                "{bound} residual identically 0 (largest |residual| {largest:.1e} over {} samples): the truth may be derived from this channel",
                samples.len()
            ),
        );
    }
    Ok(())
}

/// The heading bound: `unicycle2d` the heading channel (constant),
/// `odometry2d` the per-step integration error (affine in the turn, or
/// constant), and the flagged steps.
fn heading(run: &Run, o: &Options) -> Fitted<(Bound, StepBounds)> {
    if let Some(e) = o.assume_heading {
        if !(e.is_finite() && e >= 0.0) {
            return refuse(
                "heading",
                format!("--assume heading={e}: E must be a number >= 0"),
            );
        }
        let mut b = fit::affine_bound(
            &[],
            Measure::None,
            0.0,
            e,
            "assumed by the user (--assume heading=E), not fitted: no sample",
        );
        b.fit.coverage = 1.0;
        return Ok((b, Vec::new()));
    }
    if !run.truth.as_ref().is_some_and(|t| t.has_heading) {
        return refuse(
            "heading",
            "the truth has no heading column: the heading's bound needs true headings (or --assume heading=E)".into(),
        );
    }
    let f = o.margin("heading");
    let min = o.min_samples(f);
    let hint = "; state one with --assume heading=E";
    match run.model {
        Model::Unicycle2d => {
            let r: Vec<f64> = res::heading_channel(run).iter().map(|p| p.1).collect();
            enough("heading", &r, min, "steps with a true heading").map_err(|e| Refusal {
                reason: e.reason + hint,
                ..e
            })?;
            let pts: Vec<(f64, f64)> = r.iter().map(|x| (0.0, x.abs())).collect();
            Ok((fit::affine_bound(&pts, Measure::None, f, margins::HEADING,
                "the largest |true - measured heading| over the steps with a true heading, x (1 + F) + margin"), Vec::new()))
        }
        Model::Odometry2d => {
            let pts = res::heading_steps(run);
            let (ordinary, flagged) = flag_steps(&pts, |p| (p.0, p.2), o, |f| f.heading_above);
            let r: Vec<f64> = ordinary.iter().map(|p| p.2).collect();
            enough("heading", &r, min, "steps with a true heading at both ends").map_err(|e| {
                Refusal {
                    reason: e.reason + hint,
                    ..e
                }
            })?;
            let pts: Vec<(f64, f64)> = ordinary.iter().map(|p| (p.1, p.2.abs())).collect();
            let (of, shape) = if o.constant_steps {
                (Measure::None, "the largest of")
            } else {
                (
                    Measure::Turn,
                    "the narrowest line in the step's turn |turn_rate| dt (slope >= 0) over",
                )
            };
            let method = format!("|th(i+1) - th(i) - dt turn_rate(i)| of the truth over the steps with a true heading at both ends{}: {shape} them, x (1 + F) + margin", flagged_note(o, flagged.len()));
            Ok((
                fit::affine_bound(&pts, of, f, margins::HEADING, &method),
                flagged,
            ))
        }
    }
}

/// The per-step samples split into the ordinary ones and the flagged
/// steps with their own bounds (none unless [`Options::flag`] sets a
/// threshold for this bound).
fn flag_steps<T: Copy>(
    samples: &[T],
    residual: impl Fn(&T) -> (usize, f64),
    o: &Options,
    above: impl Fn(&Flag) -> Option<f64>,
) -> (Vec<T>, Vec<(usize, f64)>) {
    match &o.flag {
        Some(f) => same_run::flag(samples, residual, above(f), f.factor, f.margin),
        None => (samples.to_vec(), Vec::new()),
    }
}

/// The method's words for the flagged steps, if any.
fn flagged_note(o: &Options, flagged: usize) -> String {
    match &o.flag {
        Some(f) if flagged > 0 => format!(
            " but the {flagged} flagged ones (residual above the threshold: their own residual x {} + {})",
            f.factor, f.margin
        ),
        _ => String::new(),
    }
}

/// The speed channel: exact (the motion error holds its error), and when
/// the log never reports a negative speed but the truth moves backwards at
/// steps with a positive speed v (its along-track speed u nearer -v than
/// 0: v < 2|u|, a reversal the odometer reported without its sign, not a
/// glitch of the odometry that the flipped sign would not explain), the
/// sign is unknown below the largest such speed × (1 + F) + margin.
fn speed(run: &Run, o: &Options) -> SpeedBound {
    let signless = run.speed.iter().all(|&v| v >= 0.0);
    let reversals: Vec<f64> = res::along_track(run)
        .into_iter()
        .filter(|&(_, v, u)| signless && v > 0.0 && u < 0.0 && v < 2.0 * -u)
        .map(|(_, v, _)| v)
        .collect();
    let largest = reversals.iter().fold(0.0f64, |a, &v| a.max(v));
    let mut error = fit::affine_bound(
        &[],
        Measure::None,
        0.0,
        0.0,
        "0: the speed is taken as measured; the per-step motion error holds its error",
    );
    error.fit.coverage = 1.0;
    SpeedBound {
        error,
        sign_unknown_below: (!reversals.is_empty())
            .then_some(largest * (1.0 + o.relative_margin) + margins::SPEED_SIGN),
    }
}

/// The per-step motion error, affine in the step's distance and turn (or
/// constant), with its still class, and the flagged steps.
fn motion(run: &Run, o: &Options, s: &SpeedBound, h: &Bound) -> Fitted<(Bound, StepBounds)> {
    let f = o.margin("motion_error");
    let min = o.min_samples(f);
    let eh = match run.model {
        Model::Unicycle2d => h.constant,
        Model::Odometry2d => 0.0,
    };
    let pts = res::motion_steps(run, &|x| s.error.at(x), s.sign_unknown_below, eh);
    let (ordinary, flagged) = flag_steps(&pts, |p| (p.0, p.3), o, |f| f.motion_above);
    let still = o
        .still_below
        .and_then(|below| still_class(&ordinary, below, f, min));
    let moving: Vec<(f64, f64, f64)> = ordinary
        .iter()
        .filter(|p| still.as_ref().is_none_or(|s| p.1 >= s.below))
        .map(|p| (p.1, p.2, p.3))
        .collect();
    let r: Vec<f64> = moving.iter().map(|p| p.2).collect();
    let note = flagged_note(o, flagged.len());
    let mut bound = if moving.len() >= min && r.iter().all(|&x| x <= margins::ZERO) {
        // Inside the model's intervals everywhere: no error to bound.
        let line: Vec<(f64, f64)> = moving.iter().map(|p| (p.0, p.2)).collect();
        fit::affine_bound(
            &line,
            Measure::Distance,
            f,
            margins::MOTION,
            "the true steps all lie inside the model's intervals: the margin alone",
        )
    } else {
        enough(
            "motion_error",
            &r,
            min,
            "steps with a true position at both ends",
        )?;
        let what = format!("per axis, the distance from the true step to the hull of dt s (cos h, sin h) over the step's speed and heading intervals (odometry2d: the true heading), over the steps with a true position at both ends{note}{}", if still.is_some() { " and the still ones" } else { "" });
        if o.constant_steps {
            let line: Vec<(f64, f64)> = moving.iter().map(|p| (p.0, p.2)).collect();
            fit::affine_bound(
                &line,
                Measure::None,
                f,
                margins::MOTION,
                &format!("{what}: the largest, x (1 + F) + margin"),
            )
        } else {
            fit::plane_bound(&moving, f, margins::MOTION, &format!("{what}, bounded by the narrowest plane in the step's distance |speed| dt and turn (odometry2d |turn_rate| dt, unicycle2d the measured heading's change; slopes >= 0), x (1 + F) + margin"))
        }
    };
    bound.still = still;
    Ok((bound, flagged))
}

/// The still class of the motion error: the largest residual of the
/// steps reporting less than `below`, x (1 + F) + margin; none when they
/// are fewer than `min`.
fn still_class(pts: &[(usize, f64, f64, f64)], below: f64, f: f64, min: usize) -> Option<Still> {
    let r: Vec<(f64, f64)> = pts
        .iter()
        .filter(|p| p.1 < below)
        .map(|p| (0.0, p.3))
        .collect();
    if r.len() < min || !(below.is_finite() && below > 0.0) {
        return None;
    }
    let b = fit::affine_bound(&r, Measure::None, f, margins::STILL,
        "the largest residual of the steps reporting a distance |speed| dt below `below` (the odometry sees the robot standing still), x (1 + F) + margin");
    Some(Still {
        below,
        error: b.constant,
        fit: b.fit,
    })
}

/// A window's bound from its residuals, or why not.
fn window(
    name: &str,
    k: usize,
    r: &[f64],
    (f, min): (f64, usize),
    margin: f64,
    method: &str,
) -> Fitted<Window> {
    // Disjoint windows: samples / k, and one as soon as there is a sample.
    let independent = (r.len() / k).max(usize::from(!r.is_empty()));
    if independent < min {
        return refuse(
            &format!("{name}[k={k}]"),
            format!("too few samples: {independent} disjoint windows of {k} steps with the truth at their ends, at least {min} needed for this margin"),
        );
    }
    let largest = r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let error = largest * (1.0 + f) + margin;
    Ok(Window {
        steps: k,
        error,
        exempt_above: None,
        fit: Fit {
            method: method.into(),
            relative_margin: f,
            margin,
            samples: r.len(),
            independent,
            coverage: r.iter().filter(|x| x.abs() <= error).count() as f64 / r.len() as f64,
            largest_residual: largest,
            span: [0.0, 0.0],
        },
    })
}

/// The drift windows of odometry2d, those below k mean per-step bounds.
/// With `exempt` steps (sorted) the heading windows leave them out
/// (`exempt_above` t: their heading bounds are above t), and the
/// [`PLAIN_HEADING_WINDOWS`] are given without exemptions too.
fn windows(
    run: &Run,
    o: &Options,
    (h, m): (&Bound, &Bound),
    (exempt, t): (&[usize], f64),
    refused: &mut Vec<Refusal>,
) -> (Vec<Window>, Vec<Window>) {
    let n = run.steps().max(1) as f64;
    let turns: Vec<f64> = (0..run.steps()).map(|i| res::step_turn(run, i)).collect();
    let per_h = turns.iter().map(|&x| h.at(x)).sum::<f64>() / n;
    let per_m = (0..run.steps())
        .map(|i| m.at_step((run.speed[i] * run.dt).abs(), turns[i]))
        .sum::<f64>()
        / n
        * std::f64::consts::SQRT_2;
    let fh = o.margin("heading_drift");
    let mut hw = Vec::new();
    let exempting = heading_windows().map(|k| (k, !exempt.is_empty()));
    let plain = PLAIN_HEADING_WINDOWS.into_iter().map(|k| (k, false));
    let ladder: Vec<(usize, bool)> = match exempt.is_empty() {
        true => exempting.collect(),
        false => exempting.chain(plain).collect(),
    };
    let (turn, turn_exempting) = (
        res::prefix_turn(run),
        res::prefix_turn_exempting(run, exempt),
    );
    for (k, x) in ladder.into_iter().filter(|&(k, _)| k <= run.steps()) {
        let prefix = if x { &turn_exempting } else { &turn };
        let method = if x {
            "the largest |th(i+k) - th(i) - sum dt turn_rate - the exempt steps' residuals| of the truth over the pairs with both headings true, x (1 + F) + margin; the exempt steps (heading bound above exempt_above) add their own bounds"
        } else {
            "the largest |th(i+k) - th(i) - sum dt turn_rate| of the truth over the pairs with both headings true, x (1 + F) + margin"
        };
        match window(
            "heading_drift",
            k,
            &res::heading_window(run, prefix, k),
            (fh, o.min_samples(fh)),
            margins::HEADING_WINDOW,
            method,
        ) {
            Ok(w) if w.error < k as f64 * per_h => hw.push(Window {
                exempt_above: x.then_some(t),
                ..w
            }),
            Ok(_) => {}
            Err(e) => refused.push(e),
        }
    }
    let prefix = res::prefix_motion(run);
    let fm = o.margin("motion_drift");
    let mut mw = Vec::new();
    for k in motion_windows().filter(|&k| k <= run.steps()) {
        match window("motion_drift", k, &res::motion_window(run, &prefix, k), (fm, o.min_samples(fm)), margins::MOTION_WINDOW,
            "the largest Euclidean |p(i+k) - p(i) - sum dt v (cos th, sin th)| of the truth over the windows with true positions at the ends and true headings inside, x (1 + F) + margin") {
            Ok(w) if w.error < k as f64 * per_m => mw.push(w),
            Ok(_) => {}
            Err(e) => refused.push(e),
        }
    }
    (hw, mw)
}

/// The detection residuals: (range, range residual, bearing residual).
fn detection_residuals(run: &Run, offset: [f64; 2]) -> Vec<(f64, f64, Option<f64>)> {
    (0..run.detections.len())
        .filter_map(|j| res::detection(run, j, offset))
        .collect()
}

/// The range and bearing bands.
fn bands(
    run: &Run,
    o: &Options,
) -> Fitted<(crate::sensor_model::Band, Option<crate::sensor_model::Band>)> {
    let d = detection_residuals(run, o.sensor_offset);
    let r: Vec<f64> = d.iter().map(|x| x.1).collect();
    let f = o.margin("range");
    enough(
        "range",
        &r,
        o.min_samples(f),
        "detections of a known landmark at a step with a true pose",
    )?;
    let pts: Vec<(f64, f64)> = d.iter().map(|x| (x.0, x.1)).collect();
    let range = fit::band(&pts, (BandOf::Range, 0.0), share_skip(o, pts.len()), (f, margins::RANGE),
        "measured - true range over the detections of a known landmark at a step with a true pose, between the narrowest lines in the measured range r above and below every residual, within the smallest and largest residual; each side widened by F x the half-width + margin");
    let min_r = margins::MIN_RANGE_FOR_BEARING;
    let bpts: Vec<(f64, f64)> = d
        .iter()
        .filter_map(|x| Some((1.0 / x.0.max(min_r), x.2?)))
        .collect();
    if bpts.is_empty() {
        return Ok((range, None));
    }
    let b: Vec<f64> = bpts.iter().map(|p| p.1).collect();
    let f = o.margin("bearing");
    enough(
        "bearing",
        &b,
        o.min_samples(f),
        "detections with a bearing of a known landmark at a step with a true pose",
    )?;
    let bearing = fit::band(&bpts, (BandOf::InverseRange, min_r), share_skip(o, bpts.len()), (f, margins::BEARING),
        "measured - true bearing (wrapped) over the detections with a bearing, between the narrowest lines in 1/r above and below every residual, within the smallest and largest residual; each side widened by F x the half-width + margin");
    Ok((range, Some(bearing)))
}

/// The residuals a band of k leaves out below and above for the outlier
/// share P: floor(P k / 2) below, the rest of floor(P k) above.
fn share_skip(o: &Options, k: usize) -> (usize, usize) {
    let dropped = ((o.outlier_share * k as f64).floor() as usize).min(k.saturating_sub(1));
    (dropped / 2, dropped - dropped / 2)
}

/// A calibration that gives no model: the error names the run's log
/// (the data cannot support a bound), or the setting when the run was
/// built in memory.
fn no_model(run: &Run, why: String) -> ImportError {
    let message = format!("no sensor model: {why}");
    if run.paths.log.as_os_str().is_empty() {
        ImportError::setting("sensor_model", message)
    } else {
        ImportError::file(&run.paths.log, message)
    }
}

/// Fits a sensor model on a run with truth and landmarks. An error lists
/// every bound refused (too few samples, a residual identically 0, no
/// true heading); drift windows the data cannot support are left out and
/// listed in `refused`.
pub fn calibrate(run: &Run, o: &Options) -> Result<SensorModel, ImportError> {
    o.check()?;
    let Some(truth) = run.truth.as_ref() else {
        return Err(ImportError::setting(
            "truth",
            "a calibration needs the truth (--truth)",
        ));
    };
    if run.landmarks.is_none() {
        return Err(ImportError::setting(
            "landmarks",
            "a calibration needs the landmarks (--landmarks)",
        ));
    }
    let min = o.min_samples(o.relative_margin);
    let mut refused = Vec::new();
    let complete = o.flag.is_some_and(|f| f.complete_gaps);
    let (fitted, gap_step) = match complete {
        true => same_run::complete(run),
        false => (run.clone(), vec![false; run.steps()]),
    };
    let h = heading(&fitted, o);
    let s = speed(run, o);
    let placeholder = fit::affine_bound(&[], Measure::None, 0.0, 0.0, "");
    let m = motion(&fitted, o, &s, h.as_ref().map_or(&placeholder, |h| &h.0));
    let b = bands(run, o);
    let fatal: Vec<Refusal> = [h.as_ref().err(), m.as_ref().err(), b.as_ref().err()]
        .into_iter()
        .flatten()
        .cloned()
        .collect();
    let (Ok((h, flagged_h)), Ok((m, flagged_m)), Ok((range, bearing))) = (h, m, b) else {
        let why: Vec<String> = fatal
            .iter()
            .map(|r| format!("{}: {}", r.bound, r.reason))
            .collect();
        return Err(no_model(run, why.join("; ")));
    };
    let (flagged, exempt) = flagged_steps(&fitted, o, &h, (flagged_h, flagged_m), &gap_step);
    let (heading_drift, motion_drift) = match run.model {
        Model::Odometry2d => windows(&fitted, o, (&h, &m), (&exempt.0, exempt.1), &mut refused),
        Model::Unicycle2d => (Vec::new(), Vec::new()),
    };
    let gaps = gap_step.iter().filter(|&&g| g).count();
    let gaps = if complete {
        gaps
    } else {
        (0..run.steps())
            .filter(|&i| {
                let known = |k: usize| {
                    truth.positions[k].is_some()
                        && (!truth.has_heading || truth.headings[k].is_some())
                };
                !(known(i) && known(i + 1))
            })
            .count()
    };
    let model = SensorModel {
        format: FORMAT.into(),
        model: run.model.name().into(),
        calibration: Calibration {
            source: o.source.clone(),
            fingerprint: run.fingerprint(),
            steps: run.steps(),
            dt: run.dt,
            detections: run.detections.len(),
            truth_gaps: gaps,
            relative_margin: o.relative_margin,
            min_samples: min,
        },
        speed: s,
        heading: h,
        motion_error: m,
        heading_drift,
        motion_drift,
        range,
        bearing,
        sensor_offset: o.sensor_offset,
        refused,
        flagged,
    };
    // Readings so large that a fit overflows give no bound.
    model
        .check_numbers()
        .map_err(|e| no_model(run, format!("{e} (readings too large for a bound?)")))?;
    Ok(model)
}

/// The flagged steps of a same-run calibration ([`Flagged`]), the steps
/// touching a gap of a completed truth among them (heading bound at least
/// the largest ordinary one + [`GAP_HEADING_MARGIN`]), and the steps the
/// heading windows exempt with their threshold: those whose heading bound
/// is above the largest ordinary one.
fn flagged_steps(
    run: &Run,
    o: &Options,
    h: &Bound,
    (mut heading, motion): (StepBounds, StepBounds),
    gap_step: &[bool],
) -> (Option<Flagged>, (Vec<usize>, f64)) {
    let Some(f) = o.flag else {
        return (None, (Vec::new(), 0.0));
    };
    let turn = |i: usize| res::step_turn(run, i);
    let ordinary = (0..run.steps()).map(|i| h.at(turn(i))).fold(0.0, f64::max);
    if run.model == Model::Odometry2d {
        let gap = ordinary + GAP_HEADING_MARGIN;
        for (i, _) in gap_step.iter().enumerate().filter(|g| *g.1) {
            match heading.iter_mut().find(|x| x.0 == i) {
                Some(x) => x.1 = x.1.max(gap),
                None => heading.push((i, h.at(turn(i)).max(gap))),
            }
        }
    }
    heading.sort_by_key(|x| x.0);
    let exempt: Vec<usize> = heading
        .iter()
        .filter(|x| x.1 > ordinary)
        .map(|x| x.0)
        .collect();
    let flagged = Flagged {
        method: "a step whose residual (of the truth, completed across its gaps when complete_gaps) is above the threshold gets its own bound, residual x factor + margin; the per-step bound is fitted on the other steps; a step touching a gap gets a heading bound at least the largest ordinary one + gap_heading_margin: the heading windows exempt the steps whose bound is above the largest ordinary one".into(),
        heading_above: f.heading_above,
        motion_above: f.motion_above,
        factor: f.factor,
        margin: f.margin,
        complete_gaps: f.complete_gaps,
        gap_heading_margin: GAP_HEADING_MARGIN,
        heading,
        motion,
    };
    (Some(flagged), (exempt, ordinary))
}

/// How a model holds on a run with truth: per bound, the samples and how
/// many the model leaves outside, with the worst excess.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Coverage {
    /// The bound.
    pub bound: String,
    /// Samples checked.
    pub samples: usize,
    /// Samples outside the bound.
    pub outside: usize,
    /// The largest amount by which a sample exceeds the bound (0 when none).
    pub worst: f64,
}

fn count(bound: String, excess: impl Iterator<Item = f64>) -> Coverage {
    let (mut samples, mut outside, mut worst) = (0, 0, 0.0f64);
    for e in excess {
        samples += 1;
        if e > 0.0 {
            outside += 1;
            worst = worst.max(e);
        }
    }
    Coverage {
        bound,
        samples,
        outside,
        worst,
    }
}

/// The samples of `run` (with truth and landmarks) that `model` leaves
/// outside, bound by bound (the same residuals the calibration fits).
pub fn verify(model: &SensorModel, run: &Run) -> Vec<Coverage> {
    let mut out = Vec::new();
    let same = model.calibration.fingerprint == run.fingerprint();
    let h = &model.heading;
    if h.fit.method.starts_with("assumed") || run.truth.as_ref().is_some_and(|t| t.has_heading) {
        let ex: Vec<f64> = match run.model {
            Model::Unicycle2d => res::heading_channel(run)
                .iter()
                .map(|p| p.1.abs() - h.at(0.0))
                .collect(),
            Model::Odometry2d => res::heading_steps(run)
                .iter()
                .map(|p| p.2.abs() - model.heading_error_at(p.0, p.1, same))
                .collect(),
        };
        out.push(count("heading".into(), ex.into_iter()));
    }
    let eh = if run.model == Model::Unicycle2d {
        h.constant
    } else {
        0.0
    };
    let s = &model.speed;
    let pts = res::motion_steps(run, &|x| s.error.at(x), s.sign_unknown_below, eh);
    out.push(count(
        "motion_error".into(),
        pts.iter()
            .map(|p| p.3 - model.motion_error_at(p.0, p.1, p.2, same)),
    ));
    let turn = res::prefix_turn(run);
    // An exempt window's statement, as the mission's: |th(i+k) - th(i) -
    // S| <= error + the exempt steps' own bounds in the window.
    let exempt_sum = |t: f64| -> Vec<f64> {
        let mut p = vec![0.0];
        for i in 0..run.steps() {
            let e = model.heading_error_at(i, res::step_turn(run, i), same);
            p.push(p[i] + if e > t { e } else { 0.0 });
        }
        p
    };
    for w in &model.heading_drift {
        let k = w.steps;
        let slack = w.exempt_above.map(exempt_sum);
        let r: Vec<f64> = res::heading_window_at(run, &turn, k)
            .into_iter()
            .map(|(i, r)| r.abs() - slack.as_ref().map_or(0.0, |x| x[i + k] - x[i]))
            .collect();
        out.push(count(
            format!("heading_drift[k={}]", w.steps),
            r.iter().map(|x| x - w.error),
        ));
    }
    let prefix = res::prefix_motion(run);
    for w in &model.motion_drift {
        let r = res::motion_window(run, &prefix, w.steps);
        out.push(count(
            format!("motion_drift[k={}]", w.steps),
            r.iter().map(|x| x - w.error),
        ));
    }
    let d = detection_residuals(run, model.sensor_offset);
    let outside = |b: &crate::sensor_model::Band, r: f64, e: f64| {
        let ((lo, hi), _) = b.at(b.x(r));
        (lo - e).max(e - hi)
    };
    out.push(count(
        "range".into(),
        d.iter().map(|x| outside(&model.range, x.0, x.1)),
    ));
    if let Some(b) = &model.bearing {
        out.push(count(
            "bearing".into(),
            d.iter().filter_map(|x| Some(outside(b, x.0, x.2?))),
        ));
    }
    out
}

/// The relative margins tried by [`holdout`], in order.
pub const HOLDOUT_LADDER: [f64; 8] = [0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0];

/// The margins a held-out part of the calibration run asks for: the run's
/// steps before `1 - fraction` of them calibrate a model, checked
/// ([`verify`]) on the rest; each bound the rest breaks gets the next
/// margin of [`HOLDOUT_LADDER`] above its own, until the check is clean or
/// the ladder ends. Returns the margins (every bound's F, the raised ones
/// included) and the last check. A rule a user can apply without the truth
/// of the run they solve (docs/calibration.md, step 3).
pub fn holdout(
    run: &Run,
    o: &Options,
    fraction: f64,
) -> Result<(Options, Vec<Coverage>), ImportError> {
    if !(fraction > 0.0 && fraction < 1.0) {
        return Err(ImportError::setting(
            "holdout",
            format!("--holdout must be in (0, 1), found {fraction}"),
        ));
    }
    let n = run.steps();
    let cut = ((1.0 - fraction) * n as f64).round() as usize;
    if cut < 2 || n - cut < 2 {
        return Err(ImportError::setting(
            "holdout",
            format!("--holdout {fraction}: {n} steps leave fewer than 2 on a side"),
        ));
    }
    let (fit_part, check_part) = (run.steps_between(0, cut), run.steps_between(cut, n));
    let mut o = o.clone();
    loop {
        let model = calibrate(&fit_part, &o)?;
        let cov = verify(&model, &check_part);
        let broken: Vec<&str> = BOUND_NAMES
            .iter()
            .copied()
            .filter(|name| {
                cov.iter()
                    .any(|c| c.outside > 0 && bound_name(&c.bound) == *name)
            })
            .collect();
        let mut raised = false;
        for name in broken {
            if let Some(&f) = HOLDOUT_LADDER.iter().find(|&&f| f > o.margin(name)) {
                o.bound_margins.push((name.to_string(), f));
                raised = true;
            }
        }
        if !raised {
            return Ok((o, cov));
        }
    }
}

/// The bound of a coverage line (`heading_drift[k=30]` is `heading_drift`).
fn bound_name(line: &str) -> &str {
    line.split('[').next().unwrap_or(line)
}
