//! The former path of the entry points and shared types, kept so that the
//! server, the wasm facade and the Python module compile unchanged:
//! re-exports only, at the top of the pipeline. New code imports from
//! [`super::solve`], [`super::fixpoint`] and [`super::types`].

pub use super::fixpoint::propagate;
pub use super::solve::{solve, solve_model};
pub use super::types::{Association, Progress, SolveOptions};
