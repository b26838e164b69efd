//! Detection shapes (mode `shapes`, DESIGN.md "Detection shapes"): reasoning
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
//!   the matching);
//! - [`registration`]: the landmarks seen around one step, in its frame,
//!   placed on the n witness regions (the robot position where they fit);
//! - [`round`]: all of them, one SLAM round.

pub mod branch;
pub mod chain_sums;
pub mod distinct;
pub mod frames;
pub mod region;
pub mod registration;
pub mod relative;
pub mod round;
pub mod shape;
pub mod witnesses;

pub use region::Paving;
pub use round::{Chain, Domains, ShapesOptions, ShapesOutcome, ShapesState};
pub use shape::Shape;
