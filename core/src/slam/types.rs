//! The types every layer of the SLAM pipeline shares: the options of a
//! job ([`SolveOptions`], [`Association`]), the progress it reports
//! ([`Progress`], `WorkEstimate`) and what it ends with ([`Solution`],
//! [`SolveStatus`]). They sit at the bottom of the propagation layers so
//! that the rounds, the robust propagation, the diagnosis and the output
//! import them from here and never from each other (core/tests/layers.rs).
//!
//! May import: `mission`, `model`, `crate::nvector` (the contractor names).

use super::model::Model;
use crate::nvector::Contractor;

/// How to tie detections to landmarks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Association {
    /// Basic model: only operator `landmark` fields tie detections.
    None,
    /// atmost_nvector with this contractor (with the operator's fields too).
    NVector(Contractor),
}

impl Association {
    /// The names a job accepts, in the order of the spec: `none` and every
    /// contractor but `exact` (exponential).
    pub fn names() -> Vec<&'static str> {
        std::iter::once("none")
            .chain(Contractor::ALL.map(Contractor::name))
            .filter(|n| Association::parse(n).is_some())
            .collect()
    }

    /// Parses `--contractor`: `none`, `nvalue`, `projection`, `independent`,
    /// `shapes`, `best` (`exact` is refused: it is exponential).
    pub fn parse(s: &str) -> Option<Association> {
        match s {
            "none" => Some(Association::None),
            "exact" => None,
            _ => Contractor::parse(s).map(Association::NVector),
        }
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Association::None => "none",
            Association::NVector(m) => m.name(),
        }
    }
}

/// The OpenAPI schema of a SLAM job's `contractor`: the names of
/// [`Association::names`].
#[cfg(feature = "openapi")]
impl utoipa::PartialSchema for Association {
    fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
        use utoipa::openapi::schema::{ObjectBuilder, Type};
        ObjectBuilder::new()
            .schema_type(Type::String)
            .enum_values(Some(Association::names()))
            .description(Some(
                "The contractor of a SLAM job: none (the basic model: operator matches \
                 only) or atmost_nvector with one of its box contractors (exact is refused \
                 for jobs: exponential).",
            ))
            .into()
    }
}

#[cfg(feature = "openapi")]
impl utoipa::ToSchema for Association {}

/// Options of a SLAM job.
#[derive(Debug, Clone)]
pub struct SolveOptions {
    /// Association mode (`--contractor`).
    pub association: Association,
    /// Most propagation rounds.
    pub max_rounds: u32,
    /// A bound moving by at most this much counts as no change.
    pub tolerance: f64,
    /// Threads the solve may use for independent work ([`crate::par`]):
    /// the same result bits for any count. 1 by default (core reads
    /// nothing of the machine); the CLI, the service and Python pass the
    /// machine's available parallelism. Without the `threads` feature and
    /// in the browser's build every count works on one thread.
    pub threads: usize,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            association: Association::NVector(Contractor::Best),
            max_rounds: 10_000,
            tolerance: 1e-9,
            threads: 1,
        }
    }
}

/// Progress report: sent about 32 times per pass (with the detections
/// processed so far) and at the end of each round (with the new diameter
/// and the count of detections still moving).
#[derive(Debug, Clone, Default)]
pub struct Progress {
    /// Current round (1-based).
    pub round: u32,
    /// Max trajectory diameter at the end of the last finished round
    /// (before the first one ends: after dead reckoning).
    pub max_trajectory_diameter: f64,
    /// Estimated share of the work done, 0..=1, never decreasing, 1 at the
    /// fixpoint: the work done over the work done and left. Without false
    /// detections a round's work is half the detections (the passes visit
    /// every one) plus those still moving, and the rounds left are
    /// extrapolated from the fall of the boxes' change per round (see
    /// `WorkEstimate::end_round_converging`); with `max_outliers`, a round's
    /// work is the detections whose change it carries, the work left
    /// extrapolated from the fall of that count.
    pub fraction: f64,
    /// What runs: `"forward"` or `"backward"` (the passes along the
    /// chain), `"association"`, or `"round"` (a round just ended).
    pub pass: &'static str,
    /// Detections processed in this pass so far.
    pub detections_done: usize,
    /// Detections of the mission.
    pub detections: usize,
    /// Detections whose box or position moved by more than the tolerance
    /// in the last finished round (all of them before the first ends); 0
    /// at the fixpoint.
    pub moving: usize,
    /// Max trajectory diameter after dead reckoning, before any detection:
    /// where the fall of `max_trajectory_diameter` starts.
    pub initial_max_trajectory_diameter: f64,
}

/// The estimate behind [`Progress::fraction`], in detections to settle:
/// a round's work is the count of detections whose change it carries
/// (those that moved in the round before; all of them in the first), and
/// the counts are taken to fall geometrically with the last ratio r (capped
/// at 0.9): what is left is m / (1 - r) for m detections still moving. The
/// fraction is the work done over done plus left, 1 at the fixpoint.
///
/// The rounds without false detections use
/// [`WorkEstimate::end_round_converging`] instead: the count of moving
/// detections can stay flat for most of a run (CMU Plaza 1: about 600 of
/// 3529 from round 9 to round 49 of 52) while the rounds cost the same, and
/// the geometric series then said 97 % from round 9 on.
#[derive(Debug, Clone)]
pub(crate) struct WorkEstimate {
    /// Done in the finished rounds.
    done: f64,
    /// To do in this round.
    round: f64,
    /// Left from the start of this round.
    left: f64,
    /// The sums of the boxes' widths at the ends of the last rounds
    /// (newest last, at most [`WIDTH_WINDOW`] + 1), for
    /// [`WorkEstimate::end_round_converging`].
    widths: Vec<f64>,
    /// Rounds left at the last estimate that had a fall to extrapolate.
    rounds_left: Option<f64>,
}

/// Rounds over which the fall of the boxes' change per round is measured.
const WIDTH_WINDOW: usize = 4;
/// Rounds left assumed while no fall can be measured (the first rounds,
/// a round whose change grew).
const ROUNDS_LEFT_UNKNOWN: f64 = 10.0;
/// Most rounds left an estimate gives.
const MAX_ROUNDS_LEFT: f64 = 1e4;

/// log2 of a positive finite `x`, to within 0.09: the exponent plus the
/// mantissa's excess over 1 (a line between the powers of two). Enough for
/// an estimate of rounds, and no transcendental function in the solver's
/// wasm. 0 for what is not a positive normal number.
fn log2(x: f64) -> f64 {
    if !(x.is_normal() && x > 0.0) {
        return 0.0;
    }
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as f64 - 1023.0;
    let mantissa = f64::from_bits((bits & ((1 << 52) - 1)) | (1023 << 52));
    exponent + (mantissa - 1.0)
}

/// The sum of the finite widths of the positions and the detection boxes:
/// the propagation only shrinks them, so its fall per round is the change
/// that round made (an unbounded axis counts 0 until bounded).
pub(crate) fn width_sum(model: &Model) -> f64 {
    let width = |i: &crate::interval::Interval| {
        let w = i.hi() - i.lo();
        if w.is_finite() {
            w
        } else {
            0.0
        }
    };
    let pos: f64 = model.pos.iter().map(width).sum();
    let det: f64 = model
        .det
        .iter()
        .flat_map(|b| b.axes().iter())
        .map(width)
        .sum();
    pos + det
}

impl WorkEstimate {
    /// Before the first round of k detections: as pessimistic as later
    /// rounds can be.
    pub(crate) fn new(k: usize) -> WorkEstimate {
        WorkEstimate {
            done: 0.0,
            round: k as f64,
            left: 10.0 * k as f64,
            widths: Vec::with_capacity(WIDTH_WINDOW + 1),
            rounds_left: None,
        }
    }

    /// Ends a round of the rounds without false detections, after which
    /// `moving` of the `k` detections still move and the boxes' widths sum
    /// to `widths` ([`width_sum`]); `floor`: the change per round below
    /// which nothing counts as moving (the tolerance times the bounds of the
    /// moving detections). Returns the fraction (1 when none moves).
    ///
    /// Math: a round costs k/2 + m for m detections moving (the passes
    /// visit every detection; the contractions and the association step
    /// grow with the moving ones: on CMU Plaza 1 a round of 700 moving
    /// takes half the time of one of 3529). The fixpoint is approached
    /// linearly: the change per round Δ (the fall of `widths`) falls by a
    /// steady ratio ρ (measured over the last [`WIDTH_WINDOW`] rounds and
    /// over the last one, the slower kept), so that the rounds left are
    /// log(Δ / floor) / log ρ, each costing as this one. On CMU Plaza 1 the
    /// fraction is then within about 0.15 of the share of the run's time
    /// (it was 0.97 from 45 % of the time on). Complexity: O(1).
    pub(crate) fn end_round_converging(
        &mut self,
        k: usize,
        moving: usize,
        widths: f64,
        floor: f64,
    ) -> f64 {
        if self.widths.len() > WIDTH_WINDOW {
            self.widths.remove(0);
        }
        self.widths.push(widths);
        self.done += self.round;
        self.round = k as f64 / 2.0 + moving as f64;
        if moving == 0 {
            self.left = 0.0;
            return 1.0;
        }
        let rounds = self.rounds_left(floor.max(widths * 1e-15));
        self.left = rounds * self.round;
        (self.done / (self.done + self.left)).min(0.99)
    }

    /// The rounds left, from the fall of the change per round over the
    /// remembered sums of widths; while no fall shows, the last estimate
    /// less one round (at least one), or [`ROUNDS_LEFT_UNKNOWN`].
    fn rounds_left(&mut self, floor: f64) -> f64 {
        let w = &self.widths;
        let n = w.len();
        let fallback = self
            .rounds_left
            .map_or(ROUNDS_LEFT_UNKNOWN, |r| (r - 1.0).max(1.0));
        if n < 3 {
            return fallback;
        }
        // The changes of the first and the last remembered rounds, and the
        // rounds between them.
        let (first, last, span) = (w[0] - w[1], w[n - 2] - w[n - 1], (n - 2) as f64);
        if !(first > last && last > 0.0 && first.is_finite()) {
            return fallback;
        }
        let rounds = if last <= floor {
            1.0
        } else {
            // The slower of the window's fall and the last round's: the
            // first rounds fall fastest, and an estimate from them alone
            // ends too soon.
            let mut per_round = (log2(first) - log2(last)) / span;
            let before = w[n - 3] - w[n - 2];
            if before > last {
                per_round = per_round.min(log2(before) - log2(last));
            }
            if per_round > 0.0 {
                ((log2(last) - log2(floor)) / per_round).clamp(1.0, MAX_ROUNDS_LEFT)
            } else {
                fallback
            }
        };
        self.rounds_left = Some(rounds);
        rounds
    }

    /// The fraction with `share` (0..=1) of this round done (below 1).
    pub(crate) fn within(&self, share: f64) -> f64 {
        let total = self.done + self.left;
        if total > 0.0 {
            ((self.done + self.round * share) / total).min(0.99)
        } else {
            0.0
        }
    }

    /// Ends a round after which `moving` detections still move; returns
    /// the fraction (1 when none moves).
    pub(crate) fn end_round(&mut self, moving: usize) -> f64 {
        let m = moving as f64;
        let r = if self.round > 0.0 {
            (m / self.round).min(0.9)
        } else {
            0.0
        };
        self.done += self.round;
        self.round = m;
        self.left = m / (1.0 - r);
        if moving == 0 {
            1.0
        } else {
            (self.done / (self.done + self.left)).min(0.99)
        }
    }
}

/// How propagation ended.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveStatus {
    /// Fixpoint reached, no empty domain.
    Consistent,
    /// A domain became empty; the reason names the constraint and variable.
    Infeasible(String),
    /// `max_rounds` or cancellation before the fixpoint (boxes still sound).
    Stopped,
}

/// A solved mission: domains and what was proved.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Consistent, infeasible or stopped.
    pub status: SolveStatus,
    /// Groups (size >= 2) of detections proved to be the same landmark.
    pub matching: Vec<Vec<usize>>,
    /// Propagation rounds.
    pub rounds: u32,
    /// Contractor calls and swept steps.
    pub contractions: u64,
    /// Final domains.
    pub model: Model,
    /// With `max_outliers` > 0 (and a consistent or stopped solve): what
    /// the solver proved of the false detections.
    pub outliers: Option<OutlierTally>,
}

/// What a robust solve (`max_outliers` = q > 0) proved of the false
/// detections: how many are proved false, and how many of the q drops
/// nothing accounts for. While `open` > 0, every detection is dropped by
/// some reading (monotonicity, docs/outliers.md), so `matching` is empty.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutlierTally {
    /// Detections proved false (no reading keeps them).
    pub proved_false: usize,
    /// Drops of q that neither the detections proved false nor the sets
    /// of which every reading drops one (conflicts, disjoint pairs and
    /// witnesses) account for.
    pub open: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixpoint approached linearly (the change per round halves, from
    /// 1 to the floor 2^-30 at round 30) at 100 detections of which 40
    /// move: once the fall is measured, the rounds left are the true ones
    /// (within one), so the fraction is the rounds' share done; it never
    /// says more than 0.99 before the end, and 1 at it.
    #[test]
    fn rounds_left_from_a_linear_convergence() {
        let (k, m) = (100, 40);
        let mut w = WorkEstimate::new(k);
        let floor = libm::ldexp(1.0, -30);
        let mut widths = 1e3;
        let mut last = 0.0;
        for round in 1..=30 {
            widths -= libm::ldexp(1.0, -round);
            let f = w.end_round_converging(k, m, widths, floor);
            assert!(f >= last || round < 4, "round {round}: {f} after {last}");
            assert!(f <= 0.99);
            last = f;
            if round >= 4 {
                let left = w.rounds_left.unwrap();
                let truth = f64::from(30 - round);
                assert!(
                    (left - truth).abs() <= 1.0 || (truth == 0.0 && left == 1.0),
                    "round {round}: {left} rounds left, truly {truth}"
                );
            }
        }
        // At the fixpoint: 1.
        assert_eq!(w.end_round_converging(k, 0, widths, floor), 1.0);
        // No fall (widths constant), none measured yet, a growing change:
        // the fallback, never a NaN or an infinity.
        let mut w = WorkEstimate::new(k);
        for widths in [5.0, 5.0, 5.0, 4.0, 4.5, f64::INFINITY, 0.0] {
            let f = w.end_round_converging(k, m, widths, 0.0);
            assert!((0.0..=0.99).contains(&f), "{f}");
        }
    }

    /// The job's names are the spec's, each parsed back, `exact` refused.
    #[test]
    fn association_names_are_the_parsed_ones() {
        let names = Association::names();
        assert_eq!(
            names,
            [
                "none",
                "nvalue",
                "projection",
                "independent",
                "shapes",
                "best"
            ]
        );
        for n in &names {
            assert_eq!(Association::parse(n).map(Association::name), Some(*n));
        }
        assert_eq!(Association::parse("exact"), None);
    }
}
