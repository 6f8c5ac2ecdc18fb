//! `penalty_scaling`: how a penalty's error and cond₂ (raw and Jacobi-scaled) scale with the
//! mesh size h when contact rows couple DOFs — the two-body patch test with mortar and
//! node-to-segment rows, `constant` at a fixed ε and at ε ∝ E/h, and the δ-rules.
//!
//! ```text
//! cargo run --release --bin penalty_scaling                     # default: 3 discretizations, 5 levels
//! cargo run --release --bin penalty_scaling -- --discretizations mortar --levels 3 --json
//! cargo run --release --bin penalty_scaling -- --render-only    # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::penalty_scaling`]. Writes `penalty_scaling.csv`,
//! `penalty_scaling.json` (with provenance), `summary.json` (slopes) and the figure into
//! `--out` (default `results/penalty_scaling`; the committed figures are `figures/penalty_scaling`, written by `figures/regenerate.sh`).

use penalty_lab::study::{self, penalty_scaling::PenaltyScaling};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<PenaltyScaling>()
}
