//! TDOA passive location (docs/formats.md, "TDOA passive location"; the
//! paper's second application): receivers at uncertain places time-stamp
//! pulses from emitters at unknown places; atmost_nvector over the pulses'
//! positions deinterleaves them (docs/tdoa.md).
//!
//! One contractor per file: [`arrival`] (the arrival constraint with the
//! emission time as a variable), [`cuts`] (altitude and region), [`pulse`]
//! (the per-pulse fixpoint and paving), [`readings`] (`max_outliers` over
//! arrivals), [`shell`] (a pulse's hyperbolic shells as a detection shape),
//! [`solve`] (rounds with the operator's matching, atmost_nvector and the
//! shells); [`problem`] is the validated input, [`result`] the
//! output, [`simulate`] the radar scenario.

pub mod arrival;
pub mod cuts;
pub mod problem;
pub mod pulse;
pub mod readings;
pub mod result;
pub mod shell;
pub mod shell_step;
pub mod simulate;
pub mod solve;

pub use problem::TdoaProblem;
pub use result::tdoa_result_json;
pub use solve::{solve_tdoa, solve_tdoa_with, TdoaOptions, TdoaSolution};
