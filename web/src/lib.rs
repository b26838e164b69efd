//! Browser facade over nvector-core.
