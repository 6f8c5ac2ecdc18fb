//! One error type for the library. Binaries map every variant to exit status 2 with the
//! message on one line of stderr, except [`Error::OutsideModel`] (exit status 3).

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
    /// A simulation ran but left the domain of its model (e.g. a forming run whose blank was
    /// drawn off the holder); the message lists the reasons. Exit status 3.
    #[error("run outside the model: {0}")]
    OutsideModel(String),
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

/// The `main` of every binary: runs `f`; an error becomes its message on one line of stderr
/// and exit status 2 (3 for [`Error::OutsideModel`]), a panic (a bug, never expected) one line asking for a report and exit
/// status 2 — never a backtrace or a half-written line. Standard output closed by its reader
/// (`| head`) ends the binary quietly with status 0.
pub fn run_main(f: impl FnOnce() -> Result<()> + std::panic::UnwindSafe) -> std::process::ExitCode {
    std::panic::set_hook(Box::new(|_| {}));
    match std::panic::catch_unwind(f) {
        Ok(Ok(())) => std::process::ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("error: {e}");
            let status = if matches!(e, Error::OutsideModel(_)) {
                3
            } else {
                2
            };
            std::process::ExitCode::from(status)
        }
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown".into());
            if msg.starts_with("failed printing to stdout") && msg.contains("Broken pipe") {
                // The reader went away (`| head`): not a failure of the run.
                return std::process::ExitCode::SUCCESS;
            }
            eprintln!(
                "error: internal failure ({}); please report the command line",
                msg.replace('\n', " ")
            );
            std::process::ExitCode::from(2)
        }
    }
}
