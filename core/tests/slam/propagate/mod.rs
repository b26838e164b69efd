//! The rounds and the fixpoint (core/src/slam/propagate).

mod planted;
mod progress;
mod same_fixpoint;
mod work_limit;
