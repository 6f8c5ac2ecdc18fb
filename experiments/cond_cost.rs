//! `cond_cost`: what an exact cond₂ costs, by route, against one Cholesky of the same matrix.
//!
//! ```text
//! cargo run --release --bin cond_cost                       # default sizes, table on stdout
//! cargo run --release --bin cond_cost -- --sides 20,40,80 --repeats 3 --json
//! cargo run --release --bin cond_cost -- --render-only      # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::cond_cost`]. Writes `cond_cost.csv`, `cond_cost.json` (with
//! provenance) and the figure `cond_cost` (time vs n, log–log, with least-squares slopes in
//! the legend) into `--out` (default `results/cond_cost`; the committed figures are `figures/cond_cost`, written by `figures/regenerate.sh`).

use penalty_lab::study::{self, cond_cost::CondCost};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<CondCost>()
}
