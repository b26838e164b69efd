//! Subcommands, one file each.

pub mod bench;
pub mod bench_real;
pub mod bench_service;
pub mod bench_slam;
pub mod calibrate;
pub mod check;
pub mod contract;
pub mod import;
pub mod measure;
pub mod plot;
pub mod run;
pub mod serve;
pub mod simulate;
pub mod tdoa;
pub mod worker;

pub(crate) use crate::service::formats::wrong_kind;

pub(crate) use crate::service::config::machine_threads;
