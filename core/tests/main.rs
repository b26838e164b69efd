//! core's integration tests in one test executable (`cargo test -p
//! nvector-core --test integration [FILTER]`, e.g. `odometry::drift::` for
//! one file's tests): one file per subject, in folders along core/src's
//! layout (`slam::robust::conflicts` tests core/src/slam/robust/conflicts.rs),
//! each folder a module here. One executable instead of one per file: one link and one
//! compilation of what they share, in the test build, in clippy's and in
//! CI's time. `interval_props.rs` stays a test of its own (`--test
//! interval_props`): scripts/inari.sh builds it alone with AVX2 and FMA.
//!
//! The shared helpers (`common`, `propagation_reference`) are declared
//! once here; the files name them `crate::common`.

mod common;
mod propagation_reference;

mod check_planted;
mod format;
mod layers;
mod nvector;
mod odometry;
mod one_message;
mod shapes;
mod slam;
mod tdoa;
