//! The odometry2d steps of the association: the evidence a robot without
//! a heading sensor has that two detections see one landmark (or distinct
//! ones), used by the rounds inside and after their passes
//! ([`crate::slam::propagate`]).
//!
//! - [`separation`]: groups whose boxes fit in a set narrower than the
//!   minimum separation are one landmark (after the passes);
//! - [`sequential`]: the same rule inside the passes, a sequential filter
//!   over the groups' boxes so far;
//! - [`scan_map`]: a scan's detections registered against the closed-world
//!   map of pairwise distinct groups;
//! - [`scan_pose_step`]: a step's detections contract p(step), th(step) and
//!   their landmark boxes together (over pieces of the heading);
//! - [`tracks`]: detections at nearby steps proved to see one landmark
//!   from the relative poses and the minimum separation.

pub mod scan_map;
pub mod scan_pose_step;
pub mod separation;
pub mod sequential;
pub mod tracks;
