//! Set-membership SLAM as a one-way pipeline (ARCHITECTURE.md; each layer
//! imports only the layers below it, which core/tests/layers.rs checks):
//!
//! 1. [`mission`]: the typed, validated input;
//! 2. [`model`]: the domains (positions, displacements, detection boxes);
//! 3. [`types`]: what the layers above share (options, progress, solution);
//! 4. propagation: [`association`] (the shapes part of the association
//!    step), [`rounds`] (the physics-guided rounds), [`kept`] and
//!    [`outliers`] (the robust propagation), [`fixpoint`] (which of the two);
//! 5. [`diagnose`]: a minimal set of detections to check when infeasible;
//! 6. [`result`]: `nvector-result/1` and the score;
//! 7. [`solve`]: the entry points.
//!
//! [`simulate`] and [`woods`] write missions (they sit beside the
//! pipeline, on `mission`). The basic contractors (distance, bearing, motion chain) are
//! in [`crate::contractors`], below this module and [`crate::shapes`].

pub mod association;
pub mod check;
pub mod codec;
pub mod diagnose;
pub mod fixpoint;
pub mod kept;
pub mod mission;
pub mod model;
pub mod outliers;
pub mod plant;
pub mod result;
pub mod robust_cliques;
pub mod robust_conflicts;
pub mod robust_heading;
pub mod robust_hitting;
pub mod robust_regions;
pub mod robust_subsets;
pub mod robust_tracks;
pub mod rounds;
pub mod simulate;
#[cfg(feature = "openapi")]
mod simulate_schema;
pub mod solve;
pub mod types;
pub mod woods;
