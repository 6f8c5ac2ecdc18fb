//! `solver_cost`: what each penalty rule costs a direct and an iterative solver at equal
//! accuracy (penalty error = discretization error; penetration = δ), over mesh levels with h
//! halving: digits lost, CG iterations with Jacobi and IC(0), MINRES for Lagrange, raw and
//! Jacobi-scaled cond₂, and the slopes against h.
//!
//! ```text
//! cargo run --release --bin solver_cost                      # default: 9 families, 5 levels
//! cargo run --release --bin solver_cost -- --families membrane --levels 3 --json
//! cargo run --release --bin solver_cost -- --render-only      # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::solver_cost`]. Writes `solver_cost.csv`,
//! `solver_cost.json` (with provenance), `summary.json` (slopes) and the figures into `--out`
//! (default `results/solver_cost`; the committed figures are `figures/solver_cost`, written by `figures/regenerate.sh`).

use penalty_lab::study::{self, solver_cost::SolverCost};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<SolverCost>()
}
