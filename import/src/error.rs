//! The error of every importer: what is wrong and where, the file, the
//! line and the column when the fault is in a file, the option when it is
//! in the settings. The messages are the ones `nvector import` prints.

use nvector_core::InputError;
use std::path::PathBuf;

/// Why an import failed.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// A file could not be read.
    #[error("reading {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The system's reason.
        #[source]
        source: std::io::Error,
    },
    /// A cell of a CSV file is not a finite number.
    #[error("{}:{line}: column {column} ({name}): '{text}' is not a finite number", path.display())]
    Cell {
        /// The file.
        path: PathBuf,
        /// The line (1-based, as an editor counts).
        line: usize,
        /// The column (1-based).
        column: usize,
        /// The column's name in the header (empty without a header).
        name: String,
        /// The cell as written.
        text: String,
    },
    /// A line of a file is wrong.
    #[error("{}:{line}: {message}", path.display())]
    Line {
        /// The file.
        path: PathBuf,
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A file is wrong as a whole (a missing column, too few rows, ...).
    #[error("{}: {message}", path.display())]
    File {
        /// The file (as the data set names it, or the path given).
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A setting is wrong; the message names it as `nvector import`'s
    /// flag does.
    #[error("{message}")]
    Setting {
        /// The setting's name (`heading_error`, `initial`, ...).
        option: &'static str,
        /// What is wrong, naming the flag.
        message: String,
    },
    /// What was built is not a valid mission (core's validation).
    #[error("the imported mission is invalid: {0}")]
    InvalidMission(InputError),
    /// What was built is not a valid TDOA problem (core's validation).
    #[error("the imported TDOA problem is invalid: {0}")]
    InvalidTdoa(InputError),
}

impl ImportError {
    /// An error at a line of a file.
    pub(crate) fn line(path: impl Into<PathBuf>, line: usize, message: impl Into<String>) -> Self {
        ImportError::Line {
            path: path.into(),
            line,
            message: message.into(),
        }
    }

    /// An error of a whole file.
    pub(crate) fn file(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        ImportError::File {
            path: path.into(),
            message: message.into(),
        }
    }

    /// An error of a setting.
    pub(crate) fn setting(option: &'static str, message: impl Into<String>) -> Self {
        ImportError::Setting {
            option,
            message: message.into(),
        }
    }

    /// A file that could not be read.
    pub(crate) fn read(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ImportError::Read {
            path: path.into(),
            source,
        }
    }
}
