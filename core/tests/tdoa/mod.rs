//! TDOA passive location (core/src/tdoa) on planted solutions.

mod planted;
mod shell;
