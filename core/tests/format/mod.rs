//! The format layer (core/src/format).

mod paths;
