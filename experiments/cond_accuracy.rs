//! `cond_accuracy`: run time against error of cond₂ itself, route by route.
//!
//! ```text
//! cargo run --release --bin cond_accuracy                  # default panel, table on stdout
//! cargo run --release --bin cond_accuracy -- --render-only # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::cond_accuracy`]. Writes `cond_accuracy.csv`,
//! `cond_accuracy.json` (with provenance) and the figure `cond_accuracy` (error against time,
//! log–log, one colour per route) into `--out` (default `results/cond_accuracy`; the committed figures are `figures/cond_accuracy`, written by `figures/regenerate.sh`).

use penalty_lab::study::{self, cond_accuracy::CondAccuracy};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<CondAccuracy>()
}
