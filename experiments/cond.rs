//! `cond`: the 2-norm condition number of a Matrix Market matrix, with proven bounds.
//!
//! ```text
//! cargo run --release --bin cond -- K.mtx --json
//! ```
//!
//! Prints a readable table, or with `--json` one JSON object (`cond2`, `cond2_lo`, `cond2_hi`,
//! `cond2_bounds_proven`, `cond2_within_contract`, `cond_route`, …); the study is
//! [`penalty_lab::study::cond`]. Bad input exits with status 2 and one line on stderr.

use penalty_lab::study::{self, cond::Cond};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<Cond>()
}
