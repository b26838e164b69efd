//! The importers' numbers as the leaves of core's document types
//! (`nvector_core::format::leaf`): a mission is built as a `MissionDoc`
//! and written by `nvector_core::format::to_value`, as the simulators
//! write theirs.

use nvector_core::format::leaf::{BoxIn, Integer, IntervalIn, PointsIn};
use nvector_core::Interval;

/// `[lo, hi]` as a document's interval (`lo <= hi`, checked by the
/// caller: an interval that holds no number is written `"empty"`).
pub(crate) fn interval([lo, hi]: [f64; 2]) -> IntervalIn {
    IntervalIn(Interval::new(lo, hi))
}

/// `[[lo, hi], ...]` as a document's box.
pub(crate) fn boxed(axes: &[[f64; 2]]) -> BoxIn {
    BoxIn(axes.iter().map(|&[lo, hi]| Interval::new(lo, hi)).collect())
}

/// A count or an index as a document's integer.
pub(crate) fn int(n: usize) -> Integer {
    Integer::Value(n as u64)
}

/// Points of the plane, `null` where unknown.
pub(crate) fn points(ps: impl IntoIterator<Item = Option<[f64; 2]>>) -> PointsIn {
    let mut out = PointsIn {
        width: 2,
        ..PointsIn::default()
    };
    for p in ps {
        match p {
            Some(p) => out.flat.extend_from_slice(&p),
            None => out.nulls.push(out.count),
        }
        out.count += 1;
    }
    out
}

/// Whether `[lo, hi]` is a setting's interval: finite bounds, `lo <= hi`.
pub(crate) fn finite_interval([lo, hi]: [f64; 2]) -> bool {
    lo.is_finite() && hi.is_finite() && lo <= hi
}
