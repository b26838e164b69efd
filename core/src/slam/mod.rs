//! Set-membership SLAM as a one-way pipeline (ARCHITECTURE.md; each layer
//! imports only the layers below it, which core/tests/layers.rs checks),
//! one folder per stage:
//!
//! 1. [`mission`]: the typed, validated input (types, validation, writer);
//! 2. [`model`]: the domains (positions, displacements, detection boxes);
//! 3. [`types`]: what the layers above share (options, progress, solution);
//! 4. [`association`]: the association step (the shapes steps; the
//!    odometry2d steps in [`association::odometry2d`]);
//! 5. [`propagate`]: the physics-guided rounds (passes along the chain,
//!    the detections contracted inside the passes) and [`propagate::fixpoint`]
//!    (the rounds or the robust propagation);
//! 6. [`robust`]: the robust propagation for false detections
//!    (`max_outliers`, docs/outliers.md) and what it proves;
//! 7. [`diagnose`]: a minimal set of detections to check when infeasible;
//! 8. [`result`]: `nvector-result/1` and the score;
//! 9. [`solve`]: the entry points.
//!
//! [`simulate`] writes missions (the scenarios, beside the pipeline, on
//! `mission`) and [`plant`] plants false ranges into one; [`check`] lists
//! the constraints a mission's truth breaks; [`codec`] is the validated mission in binary. The basic
//! contractors (distance, bearing, motion chain) are in
//! [`crate::contractors`], below this module and [`crate::shapes`].

pub mod association;
pub mod check;
pub mod codec;
pub mod diagnose;
pub mod mission;
pub mod model;
pub mod plant;
pub mod propagate;
pub mod result;
pub mod robust;
pub mod simulate;
pub mod solve;
pub mod types;
