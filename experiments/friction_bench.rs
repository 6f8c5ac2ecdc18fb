//! `friction_bench`: Coulomb friction — every tangential penalty rule against the exact law.
//!
//! ```text
//! cargo run --release --bin friction_bench                       # sliding block, μ = 0.1, 0.2, 0.3
//! cargo run --release --bin friction_bench -- --mu 0.2 --law tresca --json
//! ```
//!
//! The study is [`penalty_lab::study::friction_bench`]. Writes `friction_bench.csv`,
//! `friction_bench.json` (with provenance) and the figure `friction_eps_t` into `--out`
//! (default `results/friction_bench`). Bad input exits with status 2 and one line on stderr.

use penalty_lab::study::{self, friction_bench::FrictionBench};
use std::process::ExitCode;

fn main() -> ExitCode {
    study::main::<FrictionBench>()
}
