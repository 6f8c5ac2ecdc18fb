//! `paper_beam`: the paper's beam example (Sec. 4.2, Eq. 30–37) number by number.
//!
//! ```text
//! cargo run --release --bin paper_beam                      # compute, write data, render, print
//! cargo run --release --bin paper_beam -- --json            # the comparison as JSON on stdout
//! cargo run --release --bin paper_beam -- --render-only     # re-render figures from saved data
//! ```
//!
//! Writes into `--out` (default `results/paper_beam`; the committed figures are `figures/paper_beam`, written by `figures/regenerate.sh`) `paper_beam.json` (every number the paper
//! prints next to ours, the `condensed` comparison, one line per strategy, the notes and the
//! computations behind them, provenance), `deflection.csv`, `cond_vs_eps.csv` and the figures
//! `fig3_deflection_free`, `fig4_deflection_contact`, `cond_vs_eps` (PNG + SVG), rendered from
//! the saved files only. The study is `penalty_lab::study::paper_beam`.

use penalty_lab::study::{self, paper_beam::PaperBeam};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<PaperBeam>()
}
