//! `nvector-import`: from sensor logs to missions.
//!
//! The data science between a robot's files and an `nvector-mission/1`:
//! reading CSV logs, converting the bundled data sets, fitting sensor
//! models on a run with truth and applying them to runs without it. It
//! reads files but holds no HTTP, no storage and no clock: the CLI and the
//! Python package call it.
