//! One error type for the library. Binaries map every variant to exit status 2 with the
//! message on one line of stderr, except [`Error::OutsideModel`] (exit status 3) and
//! [`Error::MethodFailed`] (exit status 4).
//!
//! The variants that name a thing carry it as a field — which knob ([`Error::MissingKnob`],
//! [`Error::NotPositive`]), which name and the valid ones ([`Error::Unknown`]), which DOF
//! ([`Error::DofOutOfRange`]), which file and line ([`Error::Parse`]), which command-line
//! flag ([`Error::Flag`], added by the command-line layer only), which value and its valid
//! range ([`Error::OutOfRange`], [`Error::NotFinite`]), which list and its lengths
//! ([`Error::LengthMismatch`], [`Error::NoneGiven`], [`Error::Duplicate`]), which constraint
//! row and what is wrong with it ([`Error::Constraint`], [`ConstraintProblem`]), which method
//! and what it needs ([`Error::Unsupported`]), which file is not what it must be
//! ([`Error::BadFile`]) — so that callers can match on them; [`Error::Input`] holds the few
//! that fit none of these as text.

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
    /// A value outside the range its quantity allows.
    #[error("invalid input: {name} must be {expected} (got {value})")]
    OutOfRange {
        /// What it is (`--levels`, `picard.relaxation`, `Poisson's ratio ν`, …).
        name: String,
        /// The value given, as written (a number, a pair, a list).
        value: String,
        /// What it must be (`in 2..=8`, `≥ 1`, `in (0, 1)`, `≤ punch.radius = 2`).
        expected: String,
    },
    /// A value that must be finite and is not (NaN or ±∞).
    #[error("invalid input: {what} is not finite")]
    NotFinite {
        /// Which value (`load entry 3`, `constraint 2's limit`).
        what: String,
    },
    /// A list or vector whose length does not match what it goes with.
    #[error("invalid input: {what} has {got} entries, expected {expected}")]
    LengthMismatch {
        /// Which list (`load vector q`, `surface weights`).
        what: String,
        /// Its length.
        got: usize,
        /// The length it must have (and why, in `what`).
        expected: usize,
    },
    /// A list given empty where at least one entry is needed.
    #[error("invalid input: {what}: none given{hint}")]
    NoneGiven {
        /// Which list (`--families`, `shard folders`).
        what: String,
        /// What may be given (`" (valid: beam, membrane)"`), or empty.
        hint: String,
    },
    /// An item given twice where each may appear once.
    #[error("invalid input: {what} {item} given twice")]
    Duplicate {
        /// What kind of item (`--delta-methods entry`, `shard`).
        what: String,
        /// The item (`'paper'`, `2/4`).
        item: String,
    },
    /// A constraint row that is malformed.
    #[error("invalid input: constraint {index}: {problem}")]
    Constraint {
        /// The row (0-based).
        index: usize,
        /// What is wrong with it.
        problem: ConstraintProblem,
    },
    /// A method or route asked for on a problem it does not handle.
    #[error("invalid input: {what} needs {needs}")]
    Unsupported {
        /// The method or route (`optimal`, `the elimination route`).
        what: String,
        /// What it needs that the problem lacks (`a sparse K`, `single-DOF constraints`).
        needs: String,
    },
    /// A file or folder that exists but is not what it must be (a folder that is not a sweep
    /// output, a manifest without its fields, a shard of another run).
    #[error("invalid input: {path}: {problem}")]
    BadFile {
        /// The file or folder.
        path: String,
        /// What is wrong with it.
        problem: String,
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
    #[error("{}", flag_text(flag, source))]
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
    /// A run finished and wrote its record, but a method failed on every scene it ran on
    /// (the message names it and its first error: the studies' per-method tally). Exit status 4.
    #[error("a method failed on every scene it ran on: {0}")]
    MethodFailed(String),
}

/// What is wrong with a constraint row ([`Error::Constraint`]).
#[derive(Debug, Clone, PartialEq)]
pub enum ConstraintProblem {
    /// The row has no terms (zero coefficients are dropped when a row is built, so an
    /// all-zero row arrives here too).
    NoTerms,
    /// Every coefficient of the row is zero.
    AllZero,
    /// A coefficient that is NaN or ±∞.
    NonFiniteCoefficient {
        /// The DOF it multiplies.
        dof: usize,
    },
    /// A DOF listed twice in one row.
    RepeatedDof {
        /// The DOF.
        dof: usize,
    },
    /// The limit is NaN or ±∞.
    NonFiniteLimit,
    /// A single-DOF row on a DOF an earlier single-DOF row already constrains.
    ConstrainedTwice {
        /// The DOF.
        dof: usize,
    },
}

impl std::fmt::Display for ConstraintProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ConstraintProblem::NoTerms => {
                write!(f, "the row has no terms, or every coefficient is zero")
            }
            ConstraintProblem::AllZero => write!(f, "every coefficient is zero"),
            ConstraintProblem::NonFiniteCoefficient { dof } => {
                write!(f, "the coefficient of DOF {dof} is not finite")
            }
            ConstraintProblem::RepeatedDof { dof } => {
                write!(f, "DOF {dof} appears twice in the row")
            }
            ConstraintProblem::NonFiniteLimit => write!(f, "limit is not finite"),
            ConstraintProblem::ConstrainedTwice { dof } => {
                write!(f, "DOF {dof} is constrained twice")
            }
        }
    }
}

impl Error {
    /// Shorthand for [`Error::OutOfRange`]: `name` must be `expected` but is `value`.
    pub fn out_of_range(
        name: impl std::fmt::Display,
        value: impl std::fmt::Display,
        expected: impl std::fmt::Display,
    ) -> Self {
        Error::OutOfRange {
            name: name.to_string(),
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
    /// Shorthand for [`Error::NotFinite`].
    pub fn not_finite(what: impl std::fmt::Display) -> Self {
        Error::NotFinite {
            what: what.to_string(),
        }
    }
    /// Shorthand for [`Error::LengthMismatch`].
    pub fn length_mismatch(what: impl std::fmt::Display, got: usize, expected: usize) -> Self {
        Error::LengthMismatch {
            what: what.to_string(),
            got,
            expected,
        }
    }
    /// Shorthand for [`Error::NoneGiven`].
    pub fn none_given(what: impl std::fmt::Display, hint: impl std::fmt::Display) -> Self {
        Error::NoneGiven {
            what: what.to_string(),
            hint: hint.to_string(),
        }
    }
    /// Shorthand for [`Error::Duplicate`].
    pub fn duplicate(what: impl std::fmt::Display, item: impl std::fmt::Display) -> Self {
        Error::Duplicate {
            what: what.to_string(),
            item: item.to_string(),
        }
    }
    /// Shorthand for [`Error::Unsupported`].
    pub fn unsupported(what: impl std::fmt::Display, needs: impl std::fmt::Display) -> Self {
        Error::Unsupported {
            what: what.to_string(),
            needs: needs.to_string(),
        }
    }
    /// Shorthand for [`Error::BadFile`].
    pub fn bad_file(path: impl std::fmt::Display, problem: impl std::fmt::Display) -> Self {
        Error::BadFile {
            path: path.to_string(),
            problem: problem.to_string(),
        }
    }
    /// A JSON file that does not parse as what it must hold: [`Error::Parse`] with serde's
    /// line, its column and message (`path: line L: column C: message`).
    pub fn json(path: impl std::fmt::Display, e: &serde_json::Error) -> Self {
        let text = e.to_string();
        let suffix = format!(" at line {} column {}", e.line(), e.column());
        let msg = text.strip_suffix(&suffix).unwrap_or(&text);
        Error::parse(path, e.line(), format!("column {}: {msg}", e.column()))
    }
    /// A TOML file that does not parse as what it must hold: [`Error::Parse`] at the line of
    /// the error's span in `text` (the file's contents), or [`Error::BadFile`] where the error
    /// has no span (or no text is given: a value decoded after merging); the message on one
    /// line.
    pub fn toml(path: impl std::fmt::Display, text: Option<&str>, e: &toml::de::Error) -> Self {
        let msg = e.message().replace('\n', " ");
        match (text, e.span()) {
            (Some(text), Some(span)) => {
                let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                Error::parse(path, line, msg)
            }
            _ => Error::bad_file(path, msg),
        }
    }
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
    /// `value` if it lies in the open interval (0, 1) (a relative tolerance), else
    /// [`Error::OutOfRange`] naming it.
    pub fn fraction(name: impl std::fmt::Display, value: f64) -> Result<f64> {
        if value.is_finite() && value > 0.0 && value < 1.0 {
            Ok(value)
        } else {
            Err(Error::out_of_range(name, value, "in (0, 1)"))
        }
    }
    /// Ok where no two of `items` are equal, else [`Error::Duplicate`] naming the first
    /// repeated one as an entry of `what` (a list flag or field: a repeated entry would run
    /// the same rows twice).
    pub fn distinct<T: PartialEq + std::fmt::Display>(
        what: impl std::fmt::Display,
        items: impl IntoIterator<Item = T>,
    ) -> Result<()> {
        let items: Vec<T> = items.into_iter().collect();
        for (i, x) in items.iter().enumerate() {
            if items[..i].contains(x) {
                return Err(Error::duplicate(format!("{what} entry"), format!("'{x}'")));
            }
        }
        Ok(())
    }
    /// This error as the value of command-line flag `flag` ([`Error::Flag`]).
    pub fn for_flag(self, flag: &'static str) -> Self {
        Error::Flag {
            flag,
            source: Box::new(self),
        }
    }
    /// Whether this is bad input: every variant but a singular matrix, an I/O failure, a
    /// numerical failure and a run outside its model (so [`Error::Input`], each typed input
    /// variant and a malformed file's [`Error::Parse`]; a new input variant counts without
    /// being listed).
    pub fn is_input(&self) -> bool {
        !matches!(
            self.root(),
            Error::Singular(_)
                | Error::Io { .. }
                | Error::Numerical(_)
                | Error::OutsideModel(_)
                | Error::MethodFailed(_)
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
    /// The quantity a range error names (`steps`, `punch.radius`, `penalty ε`), under any
    /// [`Error::Flag`] wrappers: for a caller that places the value in its source.
    pub fn quantity(&self) -> Option<&str> {
        match self.root() {
            Error::NotPositive { name, .. } | Error::OutOfRange { name, .. } => Some(name),
            _ => None,
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
/// and exit status 2 (3 for [`Error::OutsideModel`], 4 for [`Error::MethodFailed`]), a panic (a bug, never expected) one line asking for a report and exit
/// status 2 — never a backtrace or a half-written line. Standard output closed by its reader
/// (`| head`) ends the binary quietly with status 0.
pub fn run_main(f: impl FnOnce() -> Result<()> + std::panic::UnwindSafe) -> std::process::ExitCode {
    std::panic::set_hook(Box::new(|_| {}));
    match std::panic::catch_unwind(f) {
        Ok(Ok(())) => std::process::ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("error: {e}");
            let status = match e.root() {
                Error::OutsideModel(_) => 3,
                Error::MethodFailed(_) => 4,
                _ => 2,
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

/// [`Error::Flag`]'s message: `invalid input: --flag: what is wrong` for bad input (the prefix
/// once, in front), `--flag: message` otherwise.
fn flag_text(flag: &str, source: &Error) -> String {
    if source.is_input() {
        format!("invalid input: {flag}: {}", source.bare_message())
    } else {
        format!("{flag}: {source}")
    }
}
