//! The detection shapes (core/src/shapes) on planted solutions.

mod frames_planted;
mod props;
mod registration_props;
