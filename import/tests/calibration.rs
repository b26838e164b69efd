//! The calibration on planted worlds: a robot whose errors are drawn
//! within known bounds B (uniform on [-B, B], the law the sample rule of
//! `fit::min_samples` is stated for).
//!
//! - A model fitted on one world covers a second world drawn from the
//!   same bounds whenever the calibration saw at least `min_samples(F)`
//!   samples per bound (the rule: the largest of n samples times 1 + F
//!   falls short of B with probability at most (1 + F)^-n <= 1e-3), over
//!   many seeds; the drift windows, sums of k draws, are outside the rule
//!   and leave at most one sample in a thousand outside.
//! - It never claims less than its own data needs: every sample of the
//!   calibration world lies inside its bounds (coverage 1).
//! - It refuses, naming the reason: a truth derived from the channel, too
//!   few samples, a truth without headings; it reads gaps without filling
//!   them (a gap removes its steps, never adds a residual).

use nvector_core::slam::simulate::Rng;
use nvector_import::apply;
use nvector_import::calibrate::data::{Detection, Model, Run, Truth};
use nvector_import::calibrate::{calibrate, fit, verify, Options};
use nvector_import::sensor_model::Measure;
use nvector_import::ImportError;

/// The planted bounds.
#[derive(Clone, Copy)]
struct Planted {
    heading: f64,
    motion: f64,
    range: f64,
    bearing: f64,
    /// Growth of the motion bound per radian of the step's turn.
    motion_per_turn: f64,
}

const B: Planted = Planted {
    heading: 0.01,
    motion: 0.02,
    range: 0.1,
    bearing: 0.05,
    motion_per_turn: 0.0,
};

fn landmarks(rng: &mut Rng) -> Vec<(u64, [f64; 2])> {
    (0..12)
        .map(|i| {
            (
                i as u64 * 3 + 1,
                [rng.range(-15.0, 15.0), rng.range(-15.0, 15.0)],
            )
        })
        .collect()
}

/// An odometry2d world of `n` steps: the measured turn rate and speed,
/// the true heading and position drawn step by step with per-step errors
/// uniform within the planted bounds, detections of every landmark within
/// 8 m every 4 steps with range and bearing errors uniform within theirs.
fn world(seed: u64, n: usize, b: Planted, lms: &[(u64, [f64; 2])]) -> Run {
    let mut rng = Rng::new(seed);
    let dt = 0.1;
    let mut t = Vec::with_capacity(n);
    let (mut speed, mut turn) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut p, mut th) = (vec![[0.0, 0.0]], vec![0.3]);
    for i in 0..n {
        t.push(i as f64 * dt);
        let v = 0.6 + 0.4 * (i as f64 / 37.0).sin();
        // A turn bias: the robot circles near the origin, among the
        // landmarks.
        let w = 0.35 + 0.3 * (i as f64 / 53.0).sin() + 0.1 * rng.sym(1.0);
        speed.push(v);
        turn.push(w);
        let h = th[i];
        th.push(h + dt * w + rng.sym(b.heading));
        let q: [f64; 2] = p[i];
        let e = b.motion + b.motion_per_turn * (dt * w).abs();
        p.push([
            q[0] + dt * v * h.cos() + rng.sym(e),
            q[1] + dt * v * h.sin() + rng.sym(e),
        ]);
    }
    let mut detections = Vec::new();
    for i in (0..=n).step_by(4) {
        for &(id, l) in lms {
            let (dx, dy) = (l[0] - p[i][0], l[1] - p[i][1]);
            let r = dx.hypot(dy);
            if r < 8.0 {
                detections.push(Detection {
                    step: i,
                    range: (r + rng.sym(b.range)).max(0.0),
                    bearing: Some(dy.atan2(dx) - th[i] + rng.sym(b.bearing)),
                    scan: Some(i as u64),
                    landmark: Some(id),
                    line: 0,
                });
            }
        }
    }
    Run {
        model: Model::Odometry2d,
        t,
        dt,
        speed,
        rotation: turn,
        detections,
        truth: Some(Truth {
            positions: p.into_iter().map(Some).collect(),
            headings: th.into_iter().map(Some).collect(),
            has_heading: true,
        }),
        landmarks: Some(lms.to_vec()),
        paths: Default::default(),
    }
}

fn options() -> Options {
    Options {
        relative_margin: 0.1,
        bound_margins: Vec::new(),
        sensor_offset: [0.0, 0.0],
        assume_heading: None,
        source: "planted".into(),
        ..Options::default()
    }
}

/// A world among the same landmarks (drawn once).
fn circling(seed: u64, n: usize, b: Planted) -> Run {
    world(seed, n, b, &landmarks(&mut Rng::new(999)))
}

#[test]
fn a_model_fitted_on_enough_samples_covers_a_second_world_drawn_from_the_same_bounds() {
    let mut windows = (0usize, 0usize);
    for seed in 1..=12 {
        let cal = circling(seed, 3000, B);
        let model = calibrate(&cal, &options()).expect("calibration");
        // The rule's premise: every per-step bound and band saw at least
        // min_samples.
        let min = fit::min_samples(0.1);
        assert_eq!(model.calibration.min_samples, min);
        assert!(model.heading.fit.samples >= min && model.range.fit.samples >= min);
        let other = circling(seed + 1000, 3000, B);
        for c in verify(&model, &other) {
            if c.bound.contains("drift") {
                windows.0 += c.samples;
                windows.1 += c.outside;
                continue;
            }
            assert_eq!(
                c.outside, 0,
                "seed {seed}: {} leaves {} of {} samples of the second world outside (worst {})",
                c.bound, c.outside, c.samples, c.worst
            );
        }
    }
    // The drift windows are outside the rule: a sum of k uniform draws
    // puts little mass near its ends, so the largest of N / k windows
    // need not reach what a second world shows. The margin makes the
    // excess rare: at most one window sample in a thousand.
    assert!(
        windows.1 * 1000 <= windows.0,
        "{} of {} window samples outside",
        windows.1,
        windows.0
    );
}

/// The rule itself, on draws uniform on [-B, B] (its premise): the
/// largest |draw| of n = `min_samples(F)` times 1 + F reaches B in all but
/// at most (1 + F)^-n <= 1/1000 of the calibrations (2,000 per F: at most
/// 2 expected, 8 allowed), while a quarter of those samples falls short
/// far more often ((1 + F)^-(n/4), about 18 %): the count of samples is
/// what the rule rests on.
#[test]
fn the_sample_rule_holds_on_draws_at_the_planted_bound() {
    let b = 0.3;
    for f in [0.1, 0.5, 1.0] {
        let n = fit::min_samples(f);
        let mut rng = Rng::new(17);
        let mut short = |count: usize| {
            (0..2000)
                .filter(|_| {
                    let pts: Vec<(f64, f64)> =
                        (0..count).map(|_| (0.0, rng.sym(b).abs())).collect();
                    let bound = fit::affine_bound(&pts, Measure::None, f, 0.0, "rule");
                    bound.at(0.0) < b
                })
                .count()
        };
        let (enough, quarter) = (short(n), short(n / 4));
        assert!(enough <= 8, "F = {f}, n = {n}: {enough} of 2000 short of B");
        assert!(
            quarter >= 200,
            "F = {f}, n / 4 = {}: only {quarter} of 2000 short of B",
            n / 4
        );
    }
}

/// A margin given to one bound (`--margin NAME=F`) widens that bound
/// alone; an unknown bound or a margin <= 0 is refused naming it.
#[test]
fn a_bound_margin_widens_that_bound_alone() {
    let run = circling(8, 2000, B);
    let base = calibrate(&run, &options()).expect("calibration");
    let mut o = options();
    o.bound_margins = vec![("heading".into(), 1.0)];
    let m = calibrate(&run, &o).expect("calibration");
    assert_eq!(m.heading.fit.relative_margin, 1.0);
    let fitted = |x: f64, f: f64| (x - nvector_import::calibrate::margins::HEADING) / (1.0 + f);
    assert!((fitted(m.heading.constant, 1.0) - fitted(base.heading.constant, 0.1)).abs() < 1e-12);
    assert!(m.heading.constant > base.heading.constant);
    assert_eq!(m.motion_error, base.motion_error);
    assert_eq!(m.range, base.range);
    assert_eq!(m.calibration.relative_margin, 0.1);
    for (name, f, what) in [
        ("speed", 1.0, "no bound 'speed'"),
        ("range", -1.0, "F must be a number > 0"),
    ] {
        let mut o = options();
        o.bound_margins = vec![(name.into(), f)];
        let e = calibrate(&run, &o).unwrap_err().to_string();
        assert!(e.contains(what) && e.contains(name), "{e}");
    }
}

/// A motion error that grows with the turn (a tracked point off the
/// axle): the plane finds the growth, and covers second worlds drawn from
/// the same bounds at every step, the turning ones included.
#[test]
fn a_motion_error_growing_with_the_turn_is_fitted_and_covers_a_second_world() {
    let planted = Planted {
        motion: 0.005,
        motion_per_turn: 0.5,
        ..B
    };
    for seed in 1..=4 {
        let model = calibrate(&circling(seed, 3000, planted), &options()).expect("calibration");
        assert!(model.motion_error.turn_slope > 0.0, "seed {seed}");
        for other in [seed + 2000, seed + 3000] {
            for c in verify(&model, &circling(other, 3000, planted)) {
                if c.bound == "motion_error" {
                    assert_eq!(c.outside, 0, "seed {seed} / {other}: {c:?}");
                }
            }
        }
    }
}

#[test]
fn a_model_never_claims_less_than_its_own_data_needs() {
    for seed in 1..=6 {
        let cal = circling(seed, 2000, B);
        let model = calibrate(&cal, &options()).expect("calibration");
        for c in verify(&model, &cal) {
            assert_eq!(
                c.outside, 0,
                "seed {seed}: {} on its own data: {c:?}",
                c.bound
            );
        }
        assert_eq!(model.heading.fit.coverage, 1.0);
        assert_eq!(model.motion_error.fit.coverage, 1.0);
        assert_eq!(model.range.fit.coverage, 1.0);
        // And the planted bound: the constant per-step bounds are at least
        // the largest residual, which on 2000 uniform draws is within 1 %
        // of B with probability 1 - 0.99^2000.
        assert!(model.heading.at(0.0).max(model.heading.at(0.02)) >= 0.99 * B.heading);
    }
}

#[test]
fn a_truth_derived_from_the_heading_channel_is_refused_naming_the_reason() {
    let mut run = circling(3, 1500, B);
    // unicycle2d whose truth heading is the measured heading itself.
    let th = run.truth.as_ref().unwrap().headings.clone();
    run.model = Model::Unicycle2d;
    run.rotation = th[..run.t.len()].iter().map(|h| h.unwrap()).collect();
    let e = calibrate(&run, &options()).unwrap_err().to_string();
    assert!(e.contains("heading residual identically 0"), "{e}");
    assert!(
        e.contains("the truth may be derived from this channel"),
        "{e}"
    );
    assert!(e.contains("--assume heading=E"), "{e}");
    // Stated by the user instead: fitted around it, and marked.
    let mut o = options();
    o.assume_heading = Some(0.02);
    let m = calibrate(&run, &o).expect("with --assume");
    assert_eq!(m.heading.at(0.0), 0.02);
    assert!(
        m.heading.fit.method.starts_with("assumed"),
        "{}",
        m.heading.fit.method
    );
}

#[test]
fn too_few_samples_are_refused_and_long_windows_left_out() {
    let min = fit::min_samples(0.1);
    assert_eq!(min, 73, "ln(1000) / ln(1.1) = 72.48");
    // Fewer steps than the rule needs: the per-step bounds are refused.
    let run = circling(4, min - 5, B);
    let e = calibrate(&run, &options()).unwrap_err().to_string();
    assert!(e.contains("too few samples"), "{e}");
    // Enough for the steps, not for windows of 50 steps (need 73 x 50).
    let run = circling(4, 2000, B);
    let m = calibrate(&run, &options()).expect("calibration");
    assert!(m.heading_drift.iter().all(|w| w.fit.independent >= min));
    assert!(m.heading_drift.iter().all(|w| w.steps * min <= 2000));
    assert!(
        m.refused
            .iter()
            .any(|r| r.bound == "heading_drift[k=50]" && r.reason.contains("too few samples")),
        "{:?}",
        m.refused
    );
    // A smaller margin asks for more samples.
    assert!(fit::min_samples(0.01) > 600);
}

#[test]
fn a_truth_without_headings_is_refused_for_odometry2d() {
    let mut run = circling(5, 1000, B);
    let t = run.truth.as_mut().unwrap();
    t.headings.iter_mut().for_each(|h| *h = None);
    t.has_heading = false;
    let e = calibrate(&run, &options()).unwrap_err().to_string();
    assert!(e.contains("no heading column"), "{e}");
}

#[test]
fn gaps_in_the_truth_remove_their_steps_and_never_add_a_residual() {
    let run = circling(6, 3000, B);
    let full = calibrate(&run, &options()).expect("calibration");
    // A gap of 200 steps: the truth unknown there. A completion across it
    // (interpolation) would add residuals the planted bounds never made;
    // reading only known ends adds none.
    let mut gapped = run.clone();
    let t = gapped.truth.as_mut().unwrap();
    for k in 1000..1200 {
        t.positions[k] = None;
        t.headings[k] = None;
    }
    let m = calibrate(&gapped, &options()).expect("calibration with a gap");
    assert_eq!(m.calibration.truth_gaps, 201);
    assert!(m.heading.fit.samples < full.heading.fit.samples);
    assert!(m.heading.fit.largest_residual <= full.heading.fit.largest_residual);
    assert!(m.motion_error.fit.largest_residual <= full.motion_error.fit.largest_residual);
    for (a, b) in m.heading_drift.iter().zip(&full.heading_drift) {
        assert_eq!(a.steps, b.steps);
        assert!(
            a.fit.largest_residual <= b.fit.largest_residual,
            "k = {}",
            a.steps
        );
    }
    // A truth with gaps everywhere: too few samples, refused.
    let mut sparse = run.clone();
    let t = sparse.truth.as_mut().unwrap();
    for k in (0..t.positions.len()).filter(|k| k % 2 == 1) {
        t.positions[k] = None;
        t.headings[k] = None;
    }
    let e = calibrate(&sparse, &options()).unwrap_err().to_string();
    assert!(e.contains("heading: too few samples: 0"), "{e}");
}

#[test]
fn a_model_round_trips_through_its_json_and_a_bad_field_is_named() {
    let m = calibrate(&circling(7, 1000, B), &options()).expect("calibration");
    let text = serde_json::to_string(&m).unwrap();
    let back = nvector_import::sensor_model::SensorModel::from_json(&text).unwrap();
    assert_eq!(back, m);
    let bad = text.replacen(
        "\"format\":\"nvector-sensor-model/1\"",
        "\"format\":\"x\"",
        1,
    );
    let e = nvector_import::sensor_model::SensorModel::from_json(&bad).unwrap_err();
    assert!(e.contains("format"), "{e}");
    let mut neg = m.clone();
    neg.motion_error.constant = -1.0;
    let e =
        nvector_import::sensor_model::SensorModel::from_json(&serde_json::to_string(&neg).unwrap())
            .unwrap_err();
    assert!(e.contains("motion_error"), "{e}");
}

/// A same-run calibration with every method (steps flagged by the truth,
/// the truth completed across a gap, a still class, constant per-step
/// bounds, F = 0) never claims less than its own run needs: the truth
/// breaks none of its bounds (the exempt heading windows with their
/// exempt steps' own bounds, as the mission states them), the planted
/// glitches are flagged, and the model is refused on another run.
#[test]
fn a_same_run_model_covers_its_own_run_and_no_other() {
    use nvector_import::calibrate::Flag;
    let mut run = circling(3, 2000, B);
    let t = run.truth.as_mut().unwrap();
    // Five glitches: the true position jumps 0.3 m at the step (the later
    // steps keep their own residuals).
    for g in [300usize, 700, 1100, 1500, 1900] {
        for p in t.positions[g + 1..].iter_mut().flatten() {
            p[0] += 0.3;
        }
    }
    // A gap of the motion capture.
    for k in 1000..1010 {
        t.positions[k] = None;
        t.headings[k] = None;
    }
    let o = Options {
        relative_margin: 0.0,
        same_run: true,
        flag: Some(Flag {
            heading_above: Some(0.008),
            motion_above: Some(0.1),
            factor: 1.5,
            margin: 0.01,
            complete_gaps: true,
        }),
        still_below: Some(0.065),
        constant_steps: true,
        ..options()
    };
    let model = calibrate(&run, &o).expect("same-run calibration");
    for c in verify(&model, &run) {
        assert_eq!(c.outside, 0, "{} on its own run: {c:?}", c.bound);
    }
    let flagged = model.flagged.as_ref().expect("flagged steps");
    let motion: Vec<usize> = flagged.motion.iter().map(|f| f.0).collect();
    for g in [300, 700, 1100, 1500, 1900] {
        assert!(motion.contains(&g), "glitch {g} not flagged: {motion:?}");
    }
    assert!(model.motion_error.still.is_some());
    assert!(model.heading_drift.iter().any(|w| w.exempt_above.is_some()));
    // The gap's steps are exempt from the heading windows.
    assert!((999..1010).all(|i| flagged.heading.iter().any(|f| f.0 == i)));
    let mission = apply::mission(&run, &model, &apply::Options::default()).expect("its own run");
    assert_eq!(mission["meta"]["calibration"]["same_run"], true);
    let other = circling(4, 2000, B);
    let e = apply::mission(&other, &model, &apply::Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("flagged steps"), "{e}");
}

/// `holdout`: the margins a held-out part asks for leave none of its
/// samples outside (or the ladder ended), and never lower a margin.
#[test]
fn the_held_out_part_chooses_margins_it_is_covered_by() {
    use nvector_import::calibrate::{holdout, BOUND_NAMES, HOLDOUT_LADDER};
    for seed in [5, 8] {
        let run = circling(seed, 4000, B);
        let (chosen, cov) = holdout(&run, &options(), 0.5).expect("holdout");
        let ladder_end = BOUND_NAMES
            .iter()
            .any(|n| chosen.margin(n) == HOLDOUT_LADDER[HOLDOUT_LADDER.len() - 1]);
        assert!(
            cov.iter().all(|c| c.outside == 0) || ladder_end,
            "seed {seed}: {cov:?}"
        );
        for n in BOUND_NAMES {
            assert!(chosen.margin(n) >= options().margin(n), "{n}");
        }
    }
    assert!(holdout(&circling(5, 100, B), &options(), 1.5).is_err());
}

/// The user's initial box and heading are refused, naming the setting,
/// unless finite with lo <= hi; a good one is the mission's.
#[test]
fn an_initial_box_or_heading_not_finite_with_lo_below_hi_is_refused() {
    let run = circling(3, 3000, B);
    let model = calibrate(&run, &options()).expect("calibration");
    let with = |initial, initial_heading| apply::Options {
        initial,
        initial_heading,
        ..apply::Options::default()
    };
    let good = with(Some([[-1.0, 1.0], [-2.0, 2.5]]), Some([-0.1, 0.1]));
    let m = apply::mission(&run, &model, &good).expect("a good box");
    assert_eq!(
        m["initial_position"],
        serde_json::json!([[-1.0, 1.0], [-2.0, 2.5]])
    );
    assert_eq!(m["initial_heading"], serde_json::json!([-0.1, 0.1]));
    let box_of = |lo: f64, hi: f64| Some([[lo, hi], [0.0, 0.0]]);
    for (initial, heading, setting) in [
        (box_of(1.0, 0.0), None, "initial"),
        (box_of(f64::NEG_INFINITY, 0.0), None, "initial"),
        (box_of(0.0, f64::NAN), None, "initial"),
        (None, Some([0.2, 0.1]), "initial_heading"),
        (None, Some([0.0, f64::INFINITY]), "initial_heading"),
    ] {
        let e = apply::mission(&run, &model, &with(initial, heading)).unwrap_err();
        assert!(
            matches!(e, ImportError::Setting { option, .. } if option == setting),
            "{initial:?} {heading:?}: {e}"
        );
    }
}
