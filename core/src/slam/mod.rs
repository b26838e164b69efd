//! Set-membership SLAM: missions, the model, the physics-guided propagator,
//! simulation and scoring. OWNER: helper B. The signatures below are the API
//! the server and the web facade call.

pub mod bearing;
pub mod distance;
pub mod mission;
pub mod motion_chain;
pub mod propagator;
pub mod simulate;
