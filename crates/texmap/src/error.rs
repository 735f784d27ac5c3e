//! One error type for the whole library, grouped by who is at fault.

use std::path::{Path, PathBuf};

/// The result type of every fallible texmap call.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong, grouped by who is at fault.
///
/// Errors about a file carry its path, so the command line can print one line that names it.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A file's contents are corrupt or not in a format we read.
    #[error("{}: {message}", path.display())]
    Decode { path: PathBuf, message: String },
    /// The input asks for more than the configured limits allow.
    #[error("{}: {message}", path.display())]
    Limits { path: PathBuf, message: String },
    /// A parameter given by the caller is out of range or malformed.
    #[error("{0}")]
    Parameter(String),
    /// A valid request texmap does not support.
    #[error("{0}")]
    Unsupported(String),
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().to_path_buf(),
            source,
        }
    }

    /// A decoding error on `path`.
    pub fn decode(path: impl AsRef<Path>, message: impl Into<String>) -> Self {
        Error::Decode {
            path: path.as_ref().to_path_buf(),
            message: message.into(),
        }
    }

    /// A limit exceeded by `path`.
    pub fn limits(path: impl AsRef<Path>, message: impl Into<String>) -> Self {
        Error::Limits {
            path: path.as_ref().to_path_buf(),
            message: message.into(),
        }
    }

    /// A bad parameter.
    pub fn parameter(message: impl Into<String>) -> Self {
        Error::Parameter(message.into())
    }
}
