//! Detection shapes (mode `shapes`, docs/design.md "Detection shapes"): reasoning
//! on the true set of landmark positions each detection allows — an annulus
//! around an uncertain robot position, an annular sector with a bearing —
//! rather than on its hull box, which for a range overlaps every other.
//!
//! - [`shape`]: the shapes and their sound tests (disjoint, meets a box);
//! - [`witnesses`]: pairwise-disjoint shapes or regions prove distinct
//!   landmarks (more than n: infeasible);
//! - [`region`]: a proved group's landmark region, the intersection of its
//!   members' shapes, as a paving;
//! - [`branch`]: a detection whose landmark is one of n regions, contracted
//!   once per region (the hull of the survivors kept; one survivor proves
//!   the matching); [`branch_memo`] (natively) reuses each region's part
//!   of a detection's last branch while the shape and that region stay
//!   the same;
//! - [`registration`]: the landmarks seen around one step, in its frame,
//!   placed on the n witness regions (the robot position where they fit);
//! - [`chain_sums`], [`frames`], [`relative_pairs`]: displacements summed along
//!   the chain, local frames, distinct pairs in the frame of a step;
//! - [`distinct`]: the union-find and the distinct pairs.
//!
//! This module is pure geometry: it never sees a mission (a detection
//! reaches it as a [`shape::Sighting`]) nor anything of [`crate::slam`].
//! The SLAM association step that runs all of them over a round's domains
//! is [`crate::slam::association`].

pub mod branch;
#[cfg(not(target_arch = "wasm32"))]
pub mod branch_memo;
pub mod chain_sums;
pub mod distinct;
pub mod frames;
pub mod region;
pub mod registration;
pub mod relative_pairs;
pub mod shape;
pub mod witnesses;

pub use region::Paving;
pub use shape::{Shape, Sighting};
