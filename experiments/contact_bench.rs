//! `contact_bench`: every contact rule against physics — Hertz contact (plane strain,
//! axisymmetric) and a rigid flat punch on graded Q4 meshes; the leaderboard of "how much
//! penalty is enough".
//!
//! ```text
//! cargo run --release --bin contact_bench                          # default suite
//! cargo run --release --bin contact_bench -- --cases hertz-axi --meshes 0.1,0.05
//! cargo run --release --bin contact_bench -- --render-only
//! cargo run --release --bin contact_bench -- --resume             # after an interruption
//! ```
//!
//! The study is [`penalty_lab::study::contact_bench`]. Writes `rows.csv`, `summary.json` (with
//! provenance, the convergence rates and the leaderboard), `domain.csv`, `kappa.csv` and the
//! figures into `--out` (default `results/contact_bench`). Each finished mesh is checkpointed
//! in `OUT/meshes/` (removed at the end); `--resume` reuses those of the same build and
//! options. Bad options exit with status 2 and one line.

use penalty_lab::study::{self, contact_bench::ContactBench};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<ContactBench>()
}
