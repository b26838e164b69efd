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
use crate::slam::simulate::Rng;
use serde_json::{json, Value};

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
) -> (Vec<Value>, Vec<usize>) {
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
            arrivals.push(json!({"receiver": i, "time": [t - w, t + w]}));
        }
        let z = em[e][2];
        let mut pulse = json!({"arrivals": arrivals, "altitude": [z - 20.0, z + 20.0]});
        if o.operator {
            pulse["emitter"] = e.into();
        }
        out.push(pulse);
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
        let list = ps[k]["arrivals"].as_array_mut().expect("an array");
        false_list.push(json!([k, list.len()]));
        list.push(json!({"receiver": i, "time": [t - TIME_ERR, t + TIME_ERR]}));
    }
    let receivers: Vec<Value> = rx
        .iter()
        .map(|(_, s, _)| {
            let w = SURVEY + MARGIN_X;
            json!({"position": [[s[0] - w, s[0] + w], [s[1] - w, s[1] + w], [s[2] - w, s[2] + w]],
                   "clock_bias": [-BIAS - MARGIN_T, BIAS + MARGIN_T]})
        })
        .collect();
    let positions: Vec<Value> = who.iter().map(|&e| json!(em[e])).collect();
    Ok(json!({
        "format": super::problem::FORMAT,
        "name": format!("radar-{}-emitters-seed-{}", o.emitters, o.seed),
        "propagation_speed": C_BOUNDS,
        "receivers": receivers,
        "pulses": ps,
        "emitter_count": o.emitters,
        "emitter_region": [[-HALF - 1.0, HALF + 1.0], [-HALF - 1.0, HALF + 1.0], [0.0, 1000.0]],
        "max_outliers": o.false_arrivals,
        "meta": {"scenario": "radar", "seed": o.seed, "missing": o.missing,
                 "false_arrivals": false_list, "time_error_s": TIME_ERR,
                 "clock_bias_s": BIAS, "survey_error_m": SURVEY},
        "truth": {"positions": positions, "emitters": em, "matching": who},
    }))
}
