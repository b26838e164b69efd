//! What `nvector bench`'s measures share: the timing (median of runs,
//! two measures in alternation) and [`Bench`], what every measure reads.
//! Below `bench` and `bench_slam`, which both use it.

use serde_json::Value;
use std::time::Instant;

/// Median wall time in milliseconds of `runs` calls of `f`, each after a
/// fresh `setup` (not timed; nor is dropping what `f` returns).
pub fn median_ms<S, T>(
    runs: usize,
    mut setup: impl FnMut() -> S,
    mut f: impl FnMut(S) -> T,
) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let input = setup();
            let t = Instant::now();
            let out = std::hint::black_box(f(input));
            let ms = t.elapsed().as_secs_f64() * 1e3;
            drop(out);
            ms
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// A measure and its baseline timed in alternation, `runs` pairs: returns
/// the medians of the baseline, of the measure and of the per-pair ratios.
/// Pairing keeps the ratio steady on a noisy machine: both sides of a pair
/// see the same load. Set-ups and the dropping of results are not timed.
pub fn paired_ms<S, T, B, U>(
    runs: usize,
    mut base_setup: impl FnMut() -> B,
    mut base: impl FnMut(B) -> U,
    mut setup: impl FnMut() -> S,
    mut f: impl FnMut(S) -> T,
) -> (f64, f64, f64) {
    let mut b = Vec::with_capacity(runs);
    let mut m = Vec::with_capacity(runs);
    let mut r = Vec::with_capacity(runs);
    for _ in 0..runs {
        let input = base_setup();
        let t = Instant::now();
        let out = std::hint::black_box(base(input));
        let tb = t.elapsed().as_secs_f64() * 1e3;
        drop(out);
        let input = setup();
        let t = Instant::now();
        let out = std::hint::black_box(f(input));
        let tm = t.elapsed().as_secs_f64() * 1e3;
        drop(out);
        b.push(tb);
        m.push(tm);
        r.push(tm / tb);
    }
    let med = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    (med(b), med(m), med(r))
}

/// What every measure reads: the sizes (`quick`), the name suffix, the
/// runs per timing, the `--only` filter and where its line goes.
pub struct Bench<'e> {
    /// Quick sizes.
    pub quick: bool,
    /// "_quick" or "".
    pub suffix: &'static str,
    /// The `--only` filter.
    pub only: Option<&'e str>,
    /// Threads of the real-data `best` lines (`--threads`).
    pub threads: usize,
    /// Where each measure's line goes.
    pub emit: &'e mut dyn FnMut(Value),
}

impl Bench<'_> {
    /// The measure's name with the suffix, when `--only` wants it.
    pub fn wanted(&self, base: &str) -> Option<String> {
        let name = format!("{base}{}", self.suffix);
        self.only.is_none_or(|o| name.contains(o)).then_some(name)
    }

    /// Hands a measure's line on.
    pub fn emit(&mut self, v: Value) {
        (self.emit)(v)
    }
}
