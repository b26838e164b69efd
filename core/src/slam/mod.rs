//! Set-membership SLAM: missions, the model, the physics-guided propagator,
//! simulation and scoring.

pub mod bearing;
pub mod diagnose;
pub mod distance;
pub mod kept;
pub mod mission;
pub mod model;
pub mod motion_chain;
pub mod outliers;
pub mod propagator;
pub mod result;
pub mod simulate;
