//! The one error type of core: invalid input, with the JSON path of the bad
//! value. An empty box is a result, never an error.

use std::fmt;

/// Invalid input: what is wrong and where (a JSON path such as
/// `detections[12].range`, empty for the whole document).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct InputError {
    /// JSON path of the offending value (`""` for the document itself).
    pub path: String,
    /// What is wrong, in words a user can act on.
    pub message: String,
}

impl InputError {
    /// An error at `path`.
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> InputError {
        InputError {
            path: path.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.path.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.path, self.message)
        }
    }
}
