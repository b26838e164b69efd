//! The nvector global constraint atmost_nvector(n, {d(1)..d(k)}) and its
//! contractors (Chabert, Jaulin, Lorca, CP 2009).
//!
//! OWNER: helper A. This file fixes the API that the rest of the code calls.

use crate::error::InputError;
use crate::ibox::IntervalBox;

pub mod contract;

/// Which contractor enforces atmost_nvector.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// atmost_nvalue on each axis projection independently (paper, section 5).
    Nvalue,
    /// `Nvalue` plus whole-box intersection of groups, to a fixpoint.
    Projection,
    /// `Projection` plus pairwise-disjoint witnesses in full dimension.
    Independent,
    /// Exact bound consistency (exponential, k <= 40).
    Exact,
    /// The strongest polynomial contractor.
    Best,
}

impl Mode {
    /// Parses the spec's name (`"nvalue"`, `"projection"`, ...).
    pub fn parse(s: &str) -> Option<Mode> {
        Some(match s {
            "nvalue" => Mode::Nvalue,
            "projection" => Mode::Projection,
            "independent" => Mode::Independent,
            "exact" => Mode::Exact,
            "best" => Mode::Best,
            _ => return None,
        })
    }

    /// The spec's name.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Nvalue => "nvalue",
            Mode::Projection => "projection",
            Mode::Independent => "independent",
            Mode::Exact => "exact",
            Mode::Best => "best",
        }
    }
}

/// What a contraction proved.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Some box shrank.
    Contracted,
    /// Nothing could be removed.
    Unchanged,
    /// The constraint has no solution in the boxes (they are all emptied).
    Infeasible {
        /// Why, e.g. "axis 0 needs at least 3 distinct values, n = 2".
        reason: String,
    },
}

/// Result of one atmost_nvector contraction.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Contracted, unchanged or infeasible.
    pub status: Status,
    /// Partition of the box indices into sets proved equal (singletons
    /// included), each sorted, listed by smallest index.
    pub groups: Vec<Vec<usize>>,
    /// Proved lower bound on the minimum number of distinct vectors.
    pub min_distinct_lower: usize,
    /// Size of a hitting set found (an upper bound of that minimum).
    pub min_distinct_upper: usize,
    /// Passes over the axes / fixpoint rounds.
    pub rounds: u32,
}

/// Contracts `boxes` (all of one dimension) under atmost_nvector(n, boxes).
/// Never removes a vector tuple satisfying the constraint.
pub fn atmost_nvector(
    n: usize,
    boxes: &mut [IntervalBox],
    mode: Mode,
) -> Result<Outcome, InputError> {
    let _ = (n, mode);
    let k = boxes.len();
    Ok(Outcome {
        status: Status::Unchanged,
        groups: (0..k).map(|i| vec![i]).collect(),
        min_distinct_lower: usize::from(k > 0),
        min_distinct_upper: k,
        rounds: 0,
    })
}
