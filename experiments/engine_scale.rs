//! `engine_scale`: the contact solve engine on full-contact membranes from 10⁴ to 10⁶ DOFs —
//! iterations, factorizations, CG iterations, wall time, peak memory, certified cond₂ per
//! method ([`penalty_lab::study::engine_scale`]).
//!
//! ```text
//! cargo run --release --bin engine_scale                             # 10⁴, 10⁵
//! cargo run --release --bin engine_scale -- --sizes 1000000 --methods condensed
//! ```
//!
//! Writes `rows.csv`, `rows.json` and `manifest.json` (provenance) and the figure
//! `engine_scale` into `--out` (default `results/engine_scale`; the committed figures are `figures/engine_scale`, written by `figures/regenerate.sh`); prints a table.

use penalty_lab::study::{self, engine_scale::EngineScale};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<EngineScale>()
}
