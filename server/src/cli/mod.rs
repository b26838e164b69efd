//! Subcommands, one file each.

pub mod bench;
pub mod bench_service;
pub mod bench_slam;
pub mod contract;
pub mod csv;
pub mod import;
pub mod import_locards;
pub mod import_woods;
pub mod measure;
pub mod plot;
mod result_check;
pub mod run;
pub mod serve;
pub mod simulate;
pub mod tdoa;
pub mod worker;

pub(crate) use crate::service::formats::wrong_kind;
