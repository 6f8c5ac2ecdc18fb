//! `sweep`: ε and δ over randomized contact configurations — the harness's main job.
//!
//! ```text
//! cargo run --release --bin sweep                       # built-in default (< 1 min, 2 cores)
//! cargo run --release --bin sweep -- --families beam --count 50 --eps 1e0:1e10:21 --threads 2
//! cargo run --release --bin sweep -- --scenes-dir scenes/ --out results/files
//! cargo run --release --bin sweep -- --render-only --out results/sweep
//! cargo run --release --bin sweep -- merge results/all results/shard-1 results/shard-2
//! ```
//!
//! Writes `OUT/rows.csv`, `OUT/manifest.json` and `OUT/figures/*.{png,svg}`. Bad configuration
//! exits with status 2 and a message naming the problem and the valid choices.

use penalty_lab::study::{self, sweep::Sweep};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<Sweep>()
}
