//! `solve`: one scene file, one strategy, every metric.
//!
//! ```text
//! cargo run --release --bin solve -- scenes/paper_beam.scene.json --method paper --delta 0.1 --json
//! ```
//!
//! Prints a readable table, or with `--json` one JSON object (contract in
//! `shared/notes/methods.md`); the study is [`penalty_lab::study::solve`]. Bad input exits with status 2 and one line on stderr.

use penalty_lab::study::{self, solve::Solve};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<Solve>()
}
