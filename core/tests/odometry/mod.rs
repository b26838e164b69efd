//! The odometry2d pieces (core/src/odometry) on planted solutions: the
//! drift windows, the scan pose, the woods scenario against them.

mod drift;
mod exempt;
mod props;
mod scan_pose;
mod woods;
