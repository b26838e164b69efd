//! core's integration tests in one test executable (`cargo test -p
//! nvector-core --test integration [FILTER]`, e.g. `woods_drift::` for one
//! file's tests): one file per subject beside this one, each a module
//! here. One executable instead of one per file: one link and one
//! compilation of what they share, in the test build, in clippy's and in
//! CI's time. `interval_props.rs` stays a test of its own (`--test
//! interval_props`): scripts/inari.sh builds it alone with AVX2 and FMA.
//!
//! The shared helpers (`common`, `propagation_reference`) are declared
//! once here; the files name them `crate::common`.

mod common;
mod propagation_reference;

mod check_planted;
mod diagnose;
mod format_paths;
mod frames_planted;
mod layers;
mod nvector_examples;
mod nvector_props;
mod odometry_props;
mod odometry_solve;
mod odometry_woods;
mod one_message;
mod outliers;
mod outliers_boundary;
mod propagation_planted;
mod propagation_progress;
mod propagation_same_fixpoint;
mod propagation_work_limit;
mod registration_props;
mod robust_cliques;
mod robust_conflicts;
mod robust_heading;
mod robust_hitting;
mod robust_regions;
mod robust_subsets;
mod robust_tracks;
mod shapes_props;
mod shapes_schedule;
mod shapes_slam;
mod slam_contractors;
mod slam_paper;
mod slam_properties;
mod tdoa_planted;
mod tdoa_shell;
mod unbounded_props;
mod woods_bridges;
mod woods_drift;
mod woods_exempt;
mod woods_false;
mod woods_scan_map;
mod woods_scan_pose;
mod woods_sequential;
