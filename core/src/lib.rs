//! nvector-core: sound interval arithmetic, contractors and the nvector
//! global constraint (Chabert, Jaulin, Lorca, CP 2009) for set-membership
//! localization and mapping.
//!
//! The crate is pure: no I/O, no clock, no platform maths (`libm` only),
//! so native and wasm32 builds give the same bits; threads only in
//! [`par`], behind the `threads` feature, natively, with results merged
//! in a fixed order (the same bits for any thread count).
#![warn(missing_docs)]

pub mod contractors;
pub mod error;
pub mod figure;
pub mod format;
pub mod ibox;
pub mod interval;
pub mod json;
pub mod nvector;
pub mod odometry;
pub mod outline;
pub mod par;
pub mod radix;
pub mod rng;
pub mod shapes;
pub mod slam;
pub mod sort;
pub mod tdoa;
#[cfg(test)]
mod test_rng;
pub mod union_find;

pub use error::InputError;
pub use ibox::IntervalBox;
pub use interval::Interval;
