//! The `odometry2d` model's pieces: a ground robot whose heading
//! is not measured but integrated from its odometry.
//!
//! - [`angle`]: sound angle arithmetic on the real line (the direction arc
//!   of a box, and the contraction of a heading to the copies `arc + 2πk`
//!   of an arc);
//! - [`chain`]: the odometry2d motion chain (state x, y, heading per step),
//!   forward and backward;
//! - [`drift`]: the heading drift bound over windows of k steps
//!   (`heading_drift`), from prefix sums of the turn inputs;
//! - [`motion_drift`]: the position drift bound over windows of k steps
//!   (`motion_drift`), read by the relative evidence;
//! - [`sensor`]: a range (and bearing) detection measured from a point fixed
//!   in the body frame (`sensor_offset`) under an uncertain heading;
//! - [`sector`]: the detection's landmark set with an uncertain heading (an
//!   annulus sector whose direction is uncertain), its outer box, a sound
//!   `meets(box)`, a sound disjointness test between two of them, and the
//!   heading contraction from "the landmark is in box B".
//!
//! The `woods` scenario (an odometry2d robot among identical landmarks,
//! with scans and a stated minimum separation) is `crate::slam::simulate::odometry_scenario`: it
//! writes missions, beside the pipeline, and `slam` imports this module.
//!
//! Headings are real numbers, never wrapped into [-π, π]: every angle
//! contraction here works with all the copies `α + 2πk` of an arc.

pub mod angle;
pub mod chain;
pub mod drift;
pub mod motion_drift;
pub mod pair_heading;
pub mod relative;
pub mod scan_pose;
pub mod sector;
pub mod sensor;
