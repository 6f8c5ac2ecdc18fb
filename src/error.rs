//! One error type for the library. Binaries map every variant to exit status 2 with the
//! message on one line of stderr, except [`Error::OutsideModel`] (exit status 3).
//!
//! The variants that name a thing carry it as a field — which knob ([`Error::MissingKnob`],
//! [`Error::NotPositive`]), which name and the valid ones ([`Error::Unknown`]), which DOF
//! ([`Error::DofOutOfRange`]), which file and line ([`Error::Parse`]), which command-line
//! flag ([`Error::Flag`], added by the command-line layer only) — so that callers can match
//! on them; [`Error::Input`] holds the rest as text.

use thiserror::Error as ThisError;

/// Library error. Every message names the offending item and, where there is one, the valid
/// range or choices.
#[derive(Debug, ThisError)]
pub enum Error {
    /// Malformed or inconsistent user input not covered by a typed variant below.
    #[error("invalid input: {0}")]
    Input(String),
    /// A method built without a knob its strategy declares.
    #[error("invalid input: method {method} needs {knob}")]
    MissingKnob {
        /// The method.
        method: String,
        /// The knob, by its symbol (`ε`, `δ`, …).
        knob: &'static str,
    },
    /// A value that must be a finite number > 0.
    #[error("invalid input: {name} must be a finite number > 0 (got {value})")]
    NotPositive {
        /// What it is (`δ`, `eps_rel`, …).
        name: String,
        /// The value given.
        value: f64,
    },
    /// A name that is none of the valid ones.
    #[error("invalid input: unknown {what} '{name}' (valid: {valid})")]
    Unknown {
        /// What kind of name (`method`, `family`, `case`, `metric`).
        what: &'static str,
        /// The name given.
        name: String,
        /// The valid names, comma-separated (and what else is accepted).
        valid: String,
    },
    /// A constraint on a DOF the system does not have.
    #[error("invalid input: {context}: DOF {dof} is out of range (N = {n}, DOFs are 0-based)")]
    DofOutOfRange {
        /// Which item names the DOF (`constraint 3`).
        context: String,
        /// The DOF.
        dof: usize,
        /// The number of DOFs.
        n: usize,
    },
    /// A malformed line of a file.
    #[error("{path}: line {line}: {msg}")]
    Parse {
        /// The file.
        path: String,
        /// The line (1-based).
        line: usize,
        /// What is wrong with it.
        msg: String,
    },
    /// An error in the value of a command-line flag (the command-line layer names the flag;
    /// the library below it names the quantity).
    #[error("{flag}: {source}")]
    Flag {
        /// The flag (`--delta`).
        flag: &'static str,
        /// What is wrong.
        source: Box<Error>,
    },
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
    /// Shorthand for [`Error::Parse`].
    pub fn parse(path: impl std::fmt::Display, line: usize, msg: impl Into<String>) -> Self {
        Error::Parse {
            path: path.to_string(),
            line,
            msg: msg.into(),
        }
    }
    /// Shorthand for [`Error::Unknown`]: `valid` joined with `, ` and followed by `extra`.
    pub fn unknown(what: &'static str, name: &str, valid: &[&str], extra: &str) -> Self {
        Error::Unknown {
            what,
            name: name.to_string(),
            valid: valid.join(", ") + extra,
        }
    }
    /// `value` if it is a finite number > 0, else [`Error::NotPositive`] naming it.
    pub fn positive(name: impl std::fmt::Display, value: f64) -> Result<f64> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Error::NotPositive {
                name: name.to_string(),
                value,
            })
        }
    }
    /// This error as the value of command-line flag `flag` ([`Error::Flag`]).
    pub fn for_flag(self, flag: &'static str) -> Self {
        Error::Flag {
            flag,
            source: Box::new(self),
        }
    }
    /// Whether this is bad input: [`Error::Input`] or one of the typed input variants.
    pub fn is_input(&self) -> bool {
        matches!(
            self.root(),
            Error::Input(_)
                | Error::MissingKnob { .. }
                | Error::NotPositive { .. }
                | Error::Unknown { .. }
                | Error::DofOutOfRange { .. }
        )
    }
    /// The message without its `invalid input: ` prefix (for a caller that names the input
    /// itself, e.g. the file it came from).
    pub fn bare_message(&self) -> String {
        let text = self.to_string();
        match text.strip_prefix("invalid input: ") {
            Some(rest) => rest.to_string(),
            None => text,
        }
    }
    /// The error under any [`Error::Flag`] wrappers.
    pub fn root(&self) -> &Error {
        match self {
            Error::Flag { source, .. } => source.root(),
            e => e,
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
            let status = if matches!(e.root(), Error::OutsideModel(_)) {
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
