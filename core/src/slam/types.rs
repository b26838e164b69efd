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
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            association: Association::NVector(Contractor::Best),
            max_rounds: 10_000,
            tolerance: 1e-9,
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
    /// fixpoint: the work done over the work done and left, a round's work
    /// counted as the detections whose change it carries (all in the first
    /// round, then those still moving), the work left extrapolated from
    /// the fall of that count (a geometric series).
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
#[derive(Debug, Clone)]
pub(crate) struct WorkEstimate {
    /// Done in the finished rounds.
    done: f64,
    /// To do in this round.
    round: f64,
    /// Left from the start of this round.
    left: f64,
}

impl WorkEstimate {
    /// Before the first round of k detections: as pessimistic as later
    /// rounds can be.
    pub(crate) fn new(k: usize) -> WorkEstimate {
        WorkEstimate {
            done: 0.0,
            round: k as f64,
            left: 10.0 * k as f64,
        }
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
