//! `runtime_vs_error`: time to solution against error for every strategy as its knob varies,
//! on beam and membrane scenes from 10² to 10⁶ DOFs. Library: [`penalty_lab::study::runtime_vs_error`].
//!
//! ```text
//! cargo run --release --bin runtime_vs_error -- --smoke --json       # seconds
//! cargo run --release --bin runtime_vs_error                         # 10²…10⁶ DOFs, 3 repeats
//! cargo run --release --bin runtime_vs_error -- --sizes 100,10000 --repeats 5 --out results/rve
//! cargo run --release --bin runtime_vs_error -- --render-only --out figures/runtime_vs_error
//! ```
//!
//! Writes `OUT/rows.csv` (for spreadsheets), `OUT/rows.json` (every field, exact),
//! `OUT/manifest.json` (git commit, config, crate versions, wall time) and
//! `OUT/figures/*.{png,svg}`, rendered from `rows.json` once it is written (`--render-only`
//! re-renders from it without measuring); progress goes to stderr. A strategy that errors or would
//! exceed the per-solve budget at some size is recorded as a row with the reason; the run goes
//! on. Bad input exits with status 2 and one line on stderr.

use penalty_lab::study::{self, runtime_vs_error::RuntimeVsError};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<RuntimeVsError>()
}
