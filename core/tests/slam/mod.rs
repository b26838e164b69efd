//! The SLAM engine (core/src/slam) end to end, one folder per stage of
//! the pipeline as in core/src/slam.

mod association;
mod contractors;
mod diagnose;
mod odometry_solve;
mod paper;
mod propagate;
mod properties;
mod robust;
mod unbounded_props;
