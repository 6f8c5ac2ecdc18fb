//! `deep_drawing`: the paper's second example (Woo-like deep draw, forming.md defaults) with
//! the classical penalty (ε = 1e7), Eq. 28 on the contact rows' residual (`adaptive`,
//! δ = 1e-5 in), Eq. 28–29 as printed (`paper-literal`, a diagnostic) and the exact
//! `condensed` rule — the paper's Fig. 7.
//!
//! ```text
//! cargo run --release --bin deep_drawing -- --out figures/deep_drawing
//! cargo run --release --bin deep_drawing -- --json --steps 200 --elements 100
//! cargo run --release --bin deep_drawing -- --render-only --out figures/deep_drawing
//! ```
//!
//! `--out DIR` writes `deep_drawing.json` (provenance, config, every step and snapshot),
//! `steps_<run>.csv` and the figures (rendered from the saved JSON). Bad input exits with
//! status 2 and one line on stderr; a run outside the model's domain with status 3 (see
//! `--help`; `--allow-invalid` keeps it, marked `"valid": false`).

use penalty_lab::study::{self, deep_drawing::DeepDrawing};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<DeepDrawing>()
}
