//! The radar scenario (`nvector simulate --scenario radar`): static
//! emitters on the ground, fixed receivers with surveyed-position and
//! clock-bias bounds, pulse trains with missing arrivals and optional false
//! arrivals; pure and deterministic for a seed (splitmix64, libm only).
//!
//! Every bound is declared wider than the largest error drawn plus a
//! margin covering the simulation's own f64 rounding (times below 10 s,
//! distances below 10^6 m: relative 1e-16), so the truth satisfies every
//! constraint except the false arrivals.

use crate::error::InputError;
use crate::format::leaf::{BoxIn, Finite, Integer, IntervalIn, List};
use crate::format::tdoa::{ArrivalDoc, PulseDoc, ReceiverDoc, TdoaDoc, TdoaTruthDoc};
use crate::slam::simulate::Rng;
use crate::Interval;
use serde_json::{json, Value};

/// `[lo, hi]` as a document's interval.
fn interval(lo: f64, hi: f64) -> IntervalIn {
    IntervalIn(Interval::new(lo, hi))
}

/// A box of three axes as a document's.
fn boxed(axes: [[f64; 2]; 3]) -> BoxIn {
    BoxIn(axes.iter().map(|&[lo, hi]| Interval::new(lo, hi)).collect())
}

/// A count or an index as a document's integer.
fn int(n: usize) -> Integer {
    Integer::Value(n as u64)
}

/// An arrival at receiver `i` within `[lo, hi]`.
fn arrival(i: usize, lo: f64, hi: f64) -> ArrivalDoc {
    ArrivalDoc {
        receiver: Some(int(i)),
        time: Some(interval(lo, hi)),
    }
}

/// Options of the radar scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadarOptions {
    /// Seed.
    pub seed: u64,
    /// Emitters (1..=64).
    pub emitters: usize,
    /// Receivers (3..=64).
    pub receivers: usize,
    /// Pulses (1..=100000).
    pub pulses: usize,
    /// Share of arrivals missing, in [0, 1).
    pub missing: f64,
    /// False arrivals added (at most the number of pulses).
    pub false_arrivals: usize,
    /// Write the true matching as operator `emitter` ids.
    pub operator: bool,
}

impl Default for RadarOptions {
    fn default() -> Self {
        RadarOptions {
            seed: 1,
            emitters: 4,
            receivers: 5,
            pulses: 200,
            missing: 0.1,
            false_arrivals: 0,
            operator: false,
        }
    }
}

impl RadarOptions {
    /// Checks the limits; errors name the option.
    pub fn check(&self) -> Result<(), InputError> {
        let bad = |f: &str, m: &str| Err(InputError::new(f, m));
        if !(1..=64).contains(&self.emitters) {
            return bad("emitters", "between 1 and 64");
        }
        if !(3..=64).contains(&self.receivers) {
            return bad("receivers", "between 3 and 64");
        }
        if !(1..=100_000).contains(&self.pulses) {
            return bad("pulses", "between 1 and 100000");
        }
        if !(0.0..1.0).contains(&self.missing) {
            return bad("missing", "a share in [0, 1)");
        }
        if self.false_arrivals > self.pulses {
            return bad("false_arrivals", "at most the number of pulses");
        }
        Ok(())
    }
}

/// True propagation speed (air) and its declared bounds.
const C_TRUE: f64 = 299_710_000.0;
const C_BOUNDS: [f64; 2] = [299_690_000.0, 299_792_458.0];
/// Declared time-stamp error (s), clock-bias bound (s), survey error (m).
const TIME_ERR: f64 = 20e-9;
const BIAS: f64 = 10e-9;
const SURVEY: f64 = 2.0;
/// Margin above every drawn error (rounding of the simulation).
const MARGIN_T: f64 = 1e-12;
const MARGIN_X: f64 = 1e-6;
/// Half side of the emitters' square (m); their heights; pulse interval.
const HALF: f64 = 50_000.0;
const PRI: f64 = 1e-3;

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    libm::sqrt(
        (a[0] - b[0]) * (a[0] - b[0])
            + (a[1] - b[1]) * (a[1] - b[1])
            + (a[2] - b[2]) * (a[2] - b[2]),
    )
}

fn emitters(rng: &mut Rng, n: usize) -> Vec<[f64; 3]> {
    let mut out: Vec<[f64; 3]> = Vec::new();
    while out.len() < n {
        let p = [rng.sym(HALF), rng.sym(HALF), 100.0 + 400.0 * rng.unit()];
        // At least 5 km apart (gives up after many tries: a dense draw).
        let far = out.iter().all(|q| dist(*q, p) > 5_000.0);
        if far || rng.unit() < 0.01 {
            out.push(p);
        }
    }
    out
}

/// Receivers on a ring of 60 km: (true position, surveyed centre, bias).
fn receivers(rng: &mut Rng, m: usize) -> Vec<([f64; 3], [f64; 3], f64)> {
    (0..m)
        .map(|i| {
            let a = 2.0 * std::f64::consts::PI * (i as f64 + 0.2 * rng.unit()) / m as f64;
            let r = 60_000.0 + rng.sym(5_000.0);
            let p = [
                r * libm::cos(a),
                r * libm::sin(a),
                50.0 + 300.0 * rng.unit(),
            ];
            let s = [
                p[0] + rng.sym(SURVEY),
                p[1] + rng.sym(SURVEY),
                p[2] + rng.sym(SURVEY),
            ];
            (p, s, rng.sym(BIAS))
        })
        .collect()
}

fn pulses(
    rng: &mut Rng,
    o: &RadarOptions,
    em: &[[f64; 3]],
    rx: &[([f64; 3], [f64; 3], f64)],
) -> (Vec<PulseDoc>, Vec<usize>) {
    let mut out = Vec::with_capacity(o.pulses);
    let mut who = Vec::with_capacity(o.pulses);
    for k in 0..o.pulses {
        let e = (rng.next_u64() % em.len() as u64) as usize;
        let tau = k as f64 * PRI + rng.sym(0.1 * PRI);
        let mut arrivals = Vec::new();
        for (i, (p, _, b)) in rx.iter().enumerate() {
            if rng.unit() < o.missing {
                continue;
            }
            let t = tau + dist(em[e], *p) / C_TRUE + b + rng.sym(TIME_ERR);
            let w = TIME_ERR + MARGIN_T;
            arrivals.push(arrival(i, t - w, t + w));
        }
        let z = em[e][2];
        out.push(PulseDoc {
            arrivals: Some(List(arrivals)),
            altitude: Some(interval(z - 20.0, z + 20.0)),
            emitter: o.operator.then(|| int(e)),
            ..PulseDoc::default()
        });
        who.push(e);
    }
    (out, who)
}

/// A simulated `nvector-tdoa/1` problem with its truth.
pub fn simulate_radar(o: &RadarOptions) -> Result<Value, InputError> {
    o.check()?;
    let mut rng = Rng::new(o.seed);
    let em = emitters(&mut rng, o.emitters);
    let rx = receivers(&mut rng, o.receivers);
    let (mut ps, who) = pulses(&mut rng, o, &em, &rx);
    let mut false_list = Vec::new();
    for _ in 0..o.false_arrivals {
        let k = (rng.next_u64() % o.pulses as u64) as usize;
        let i = (rng.next_u64() % o.receivers as u64) as usize;
        let t = k as f64 * PRI + 0.5 * PRI * rng.unit();
        if let Some(List(list)) = &mut ps[k].arrivals {
            false_list.push(json!([k, list.len()]));
            list.push(arrival(i, t - TIME_ERR, t + TIME_ERR));
        }
    }
    let receivers = rx
        .iter()
        .map(|(_, s, _)| {
            let w = SURVEY + MARGIN_X;
            ReceiverDoc {
                position: Some(boxed([
                    [s[0] - w, s[0] + w],
                    [s[1] - w, s[1] + w],
                    [s[2] - w, s[2] + w],
                ])),
                clock_bias: Some(interval(-BIAS - MARGIN_T, BIAS + MARGIN_T)),
            }
        })
        .collect();
    let point = |p: [f64; 3]| List(p.map(Finite).to_vec());
    let doc = TdoaDoc {
        format: Some(super::problem::FORMAT.into()),
        name: Some(format!("radar-{}-emitters-seed-{}", o.emitters, o.seed)),
        propagation_speed: Some(interval(C_BOUNDS[0], C_BOUNDS[1])),
        receivers: Some(List(receivers)),
        pulses: Some(List(ps)),
        emitter_count: Some(int(o.emitters)),
        emitter_region: Some(boxed([
            [-HALF - 1.0, HALF + 1.0],
            [-HALF - 1.0, HALF + 1.0],
            [0.0, 1000.0],
        ])),
        max_outliers: Some(int(o.false_arrivals)),
        meta: Some(
            json!({"scenario": "radar", "seed": o.seed, "missing": o.missing,
                 "false_arrivals": false_list, "time_error_s": TIME_ERR,
                 "clock_bias_s": BIAS, "survey_error_m": SURVEY}),
        ),
        truth: Some(TdoaTruthDoc {
            positions: Some(List(who.iter().map(|&e| Some(point(em[e]))).collect())),
            emitters: Some(List(em.iter().map(|&e| point(e)).collect())),
            matching: Some(List(who.iter().map(|&e| Some(int(e))).collect())),
        }),
    };
    Ok(crate::format::to_value(&doc))
}
