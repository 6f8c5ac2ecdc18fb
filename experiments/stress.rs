//! `stress`: absurd penalties and near-singular systems — forward error against an
//! extended-precision reference, what iterative refinement and equilibration buy, and every
//! strategy at extreme knobs (no NaN/Inf, no panic, warnings where digits are lost).
//!
//! ```text
//! cargo run --release --bin stress -- --out figures/stress
//! cargo run --release --bin stress -- --families spectrum --count 4 --eps 1e-3:1e20:24 --json
//! ```
//!
//! Writes `OUT/eps_study.csv`, `OUT/strategies.csv` (for spreadsheets), `OUT/eps_study.json`
//! (every field of the ε study, exact), `OUT/strategies.json`, `OUT/stress.json` (git commit, config, seed, summary)
//! and `OUT/figures/*.{png,svg}`, rendered from `eps_study.json` once it is written
//! (`--render-only --out DIR` re-renders from it without running). Library:
//! [`penalty_lab::study::stress`] ([`penalty_lab::study::stress::record`] runs it). Bad input exits with status 2 and one line on stderr.

use penalty_lab::study::{self, stress::Stress};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<Stress>()
}
