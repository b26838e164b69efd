//! The association step (core/src/slam/association): the shapes
//! through the engine and their schedule; the odometry2d steps.

mod odometry2d;
mod shapes_schedule;
mod shapes_slam;
mod threads;
