//! `stretch_test`: the paper's first example (classical ε = 1e7: cond 2.705e5, modified
//! δ = 1e-5 in: cond 3.721e2; its geometry figure is lost), rebuilt as the clamped
//! hemispherical-punch stretching test with published geometry (Ghosh–Hecker, forming.md),
//! converted to inches: clamp radius 2.330 in, punch radius 2.0 in, die profile radius
//! 0.25 in, the paper's sheet t = 0.035 in, μ = 0.2, 50 elements, 100 steps to 0.8 in.
//!
//! ```text
//! cargo run --release --bin stretch_test -- --json
//! cargo run --release --bin stretch_test -- --out figures/stretch_test
//! cargo run --release --bin stretch_test -- --render-only --out figures/stretch_test
//! ```
//!
//! `--json` prints `cond2_classical`, `cond2_adaptive` (Eq. 28 on the residual) and
//! `cond2_condensed` at
//! the **representative step = the last step (full punch travel)**, their medians over all
//! steps, and the per-step series of every run. Bad input exits with status 2; a run outside the
//! model's domain with status 3 (`--allow-invalid` keeps it, marked `"valid": false`).

use penalty_lab::study::{self, stretch_test::StretchTest};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<StretchTest>()
}
