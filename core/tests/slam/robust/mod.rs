//! The robust propagation for false detections (core/src/slam/robust,
//! docs/outliers.md) on planted solutions.

mod boundary;
mod cliques;
mod conflicts;
mod heading;
mod hitting;
mod planted;
mod regions;
mod subsets;
mod track_groups;
mod woods_false;
