//! The atmost_nvector contractors (core/src/nvector): worked examples
//! and properties.

mod examples;
mod props;
