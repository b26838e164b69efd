//! The odometry2d steps of the association on planted woods worlds.

mod bridges;
mod scan_map;
mod sequential;
