//! Helpers shared by the property tests (each test file that needs them
//! declares `mod common;`): the proptest configuration, the simulator's
//! generator, exact rational checks, and missions planted with their truth
//! on the boundary of every interval (`planted`).

// Each test crate uses a part of them.
#![allow(dead_code)]

pub mod planted;
pub mod world;

use num_rational::BigRational;
use nvector_core::Interval;
use proptest::test_runner::{
    Config as ProptestConfig, FileFailurePersistence, RngAlgorithm, RngSeed,
};

/// The seed of every proptest run under CI (`CI=true`) when
/// `PROPTEST_SEED` does not name another.
pub const CI_SEED: u64 = 0x6e76_6563_746f_7231;

/// The configuration of every proptest of core's tests:
/// - cases: `PROPTEST_CASES` (or the older `NVECTOR_PROPTEST_CASES`), else
///   `default_cases` (a larger count on demand: `PROPTEST_CASES=20000`);
/// - the generator: ChaCha (its stream does not change with proptest's
///   releases), seeded with `PROPTEST_SEED` (or proptest's own
///   `PROPTEST_RNG_SEED`) when given, else with [`CI_SEED`] under
///   `CI=true`, so that a CI run tests the same cases every time; else a
///   fresh random seed per run (local runs keep exploring);
/// - failures persisted next to the test file
///   (`core/tests/NAME.proptest-regressions`, to be committed: proptest
///   replays them first in every later run).
pub fn config(default_cases: u32) -> ProptestConfig {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    let cases = var("PROPTEST_CASES")
        .or_else(|| var("NVECTOR_PROPTEST_CASES"))
        .map(|v| {
            v.parse::<u32>()
                .unwrap_or_else(|_| panic!("PROPTEST_CASES={v} is not a case count"))
        })
        .unwrap_or(default_cases);
    let seed = var("PROPTEST_SEED")
        .or_else(|| var("PROPTEST_RNG_SEED"))
        .map(|v| {
            v.parse::<u64>()
                .unwrap_or_else(|_| panic!("PROPTEST_SEED={v} is not a u64"))
        });
    let rng_seed = match seed {
        Some(s) => RngSeed::Fixed(s),
        None if ci() => RngSeed::Fixed(CI_SEED),
        None => RngSeed::Random,
    };
    ProptestConfig {
        cases,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        max_global_rejects: 100_000,
        ..ProptestConfig::default()
    }
}

/// `config(cases)` with the case count divided by `div` (at least `min`):
/// for properties much slower than their file's others.
pub fn config_div(default_cases: u32, div: u32, min: u32) -> ProptestConfig {
    let c = config(default_cases);
    ProptestConfig {
        cases: (c.cases / div.max(1)).max(min),
        ..c
    }
}

/// Whether the tests run under CI (`CI=true`).
pub fn ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// The simulator's splitmix64 generator, with the draws the instances need
/// (proptest draws the seed).
pub struct Rng(nvector_core::slam::simulate::Rng);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(nvector_core::slam::simulate::Rng::new(seed))
    }
    pub fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    pub fn unit(&mut self) -> f64 {
        self.0.unit()
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    /// 0 with probability `p_zero`, else uniform in [0, w).
    pub fn slack(&mut self, p_zero: f64, w: f64) -> f64 {
        if self.chance(p_zero) {
            0.0
        } else {
            self.range(0.0, w)
        }
    }
}

/// The exact value of a finite f64.
pub fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).expect("a finite number")
}

/// Whether the exact real `v` lies in `x` (bounds compared exactly).
pub fn holds(x: Interval, v: &BigRational) -> bool {
    if x.is_empty() {
        return false;
    }
    let lo_ok = x.lo() == f64::NEG_INFINITY || (x.lo().is_finite() && rat(x.lo()) <= *v);
    let hi_ok = x.hi() == f64::INFINITY || (x.hi().is_finite() && *v <= rat(x.hi()));
    lo_ok && hi_ok
}

/// The greatest f64 at most `v` (-inf below every finite one).
pub fn floor_f64(v: &BigRational) -> f64 {
    use num_traits::ToPrimitive;
    let mut f = v.to_f64().unwrap_or(0.0);
    if f.is_nan() {
        f = 0.0;
    }
    // Move to the exact neighbour (to_f64 is within an ulp or two).
    while f.is_infinite() && f > 0.0 || f.is_finite() && rat(f) > *v {
        f = f.next_down();
    }
    while f.next_up().is_finite() && rat(f.next_up()) <= *v {
        f = f.next_up();
    }
    if f == f64::NEG_INFINITY && rat(f64::MIN) <= *v {
        f = f64::MIN;
    }
    f
}

/// The least f64 at least `v` (+inf above every finite one).
pub fn ceil_f64(v: &BigRational) -> f64 {
    -floor_f64(&-v.clone())
}

/// The tightest interval of f64 holding the exact real `v`.
pub fn enclose(v: &BigRational) -> Interval {
    Interval::new(floor_f64(v), ceil_f64(v))
}

/// sin or cos of an exact rational by its Taylor series with the remainder
/// bound: an interval `[s - r, s + r]` of rationals holding the true value
/// (alternating series; summed until the term is below 2^-120 and
/// decreasing). For |x| up to a few tens.
pub fn taylor(x: &BigRational, cosine: bool) -> (BigRational, BigRational) {
    use num_bigint::BigInt;
    use num_traits::{One, Signed, Zero};
    let eps = BigRational::new(BigInt::one(), BigInt::one() << 120);
    let x2 = x * x;
    let mut term = if cosine {
        BigRational::one()
    } else {
        x.clone()
    };
    let mut k: i64 = if cosine { 0 } else { 1 };
    let mut sum = BigRational::zero();
    loop {
        sum += &term;
        let next = -(&term * &x2) / BigRational::from_integer(BigInt::from((k + 1) * (k + 2)));
        k += 2;
        // Once terms decrease in magnitude, the tail of an alternating
        // series is bounded by the next term.
        if next.abs() < eps && BigInt::from(k) > x.abs().to_integer() {
            let r = next.abs();
            return (&sum - &r, &sum + &r);
        }
        term = next;
    }
}

/// The paper scenario (seed, steps) with the operator's labels, as JSON,
/// and its true matching (the landmark of each detection).
pub fn operator_paper(seed: u64, steps: usize) -> (serde_json::Value, Vec<u64>) {
    use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
    let mut o = SimulateOptions::new(Scenario::Paper, seed);
    o.steps = Some(steps);
    o.operator = true;
    let v = simulate(&o);
    let truth = v["truth"]["matching"]
        .as_array()
        .expect("the simulation's truth has a matching")
        .iter()
        .map(|x| x.as_u64().expect("a landmark index"))
        .collect();
    (v, truth)
}

/// The basic propagation and the four nvector contractors of the paper's
/// comparison.
pub const ASSOCIATIONS: [nvector_core::slam::types::Association; 5] = {
    use nvector_core::nvector::Contractor;
    use nvector_core::slam::types::Association;
    [
        Association::None,
        Association::NVector(Contractor::Nvalue),
        Association::NVector(Contractor::Projection),
        Association::NVector(Contractor::Independent),
        Association::NVector(Contractor::Best),
    ]
};

/// The result document of solving `mission` with `association` and the
/// default options.
pub fn solve_json(
    mission: &nvector_core::slam::mission::Mission,
    association: nvector_core::slam::types::Association,
) -> serde_json::Value {
    let options = nvector_core::slam::types::SolveOptions {
        association,
        ..Default::default()
    };
    nvector_core::slam::solve::solve(
        mission,
        &options,
        &mut |_| {},
        &std::sync::atomic::AtomicBool::new(false),
    )
}
