//! One error type for the library. Binaries map every variant to exit status 2 with the
//! message on one line of stderr.

use thiserror::Error as ThisError;

/// Library error. Every message names the offending item and, where there is one, the valid
/// range or choices.
#[derive(Debug, ThisError)]
pub enum Error {
    /// Malformed or inconsistent user input (sizes, NaN/Inf, DOF out of range, δ ≤ 0, …).
    #[error("invalid input: {0}")]
    Input(String),
    /// A matrix that must be factorized is singular (or not positive definite) to working
    /// precision.
    #[error("singular matrix: {0}")]
    Singular(String),
    /// A file could not be read or written.
    #[error("{path}: {msg}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        msg: String,
    },
    /// A numerical routine failed (e.g. an eigenvalue iteration did not converge).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl Error {
    /// Shorthand for [`Error::Input`].
    pub fn input(msg: impl Into<String>) -> Self {
        Error::Input(msg.into())
    }
    /// Shorthand for [`Error::Singular`].
    pub fn singular(msg: impl Into<String>) -> Self {
        Error::Singular(msg.into())
    }
    /// Shorthand for [`Error::Io`].
    pub fn io(path: impl std::fmt::Display, msg: impl std::fmt::Display) -> Self {
        Error::Io {
            path: path.to_string(),
            msg: msg.to_string(),
        }
    }
}

/// Library result.
pub type Result<T> = std::result::Result<T, Error>;
