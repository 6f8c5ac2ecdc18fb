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

use clap::Parser;
use penalty_lab::study::deep_drawing;
use penalty_lab::study::forming_runs::{self, Cli};
use penalty_lab::Error;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "deep_drawing",
    version = penalty_lab::provenance::VERSION,
    about = "Woo-like hemispherical-punch deep draw: classical vs adaptive penalty (paper Fig. 7)",
    after_help = format!(
        "Default travel 1.0 in. Units: inch, ton-force, second. {}",
        forming_runs::EXIT_STATUSES
    )
)]
struct Args {
    #[command(flatten)]
    cli: Cli,
}

fn run(a: &Args) -> Result<(), Error> {
    let doc = a.cli.execute(deep_drawing::EXPERIMENT)?;
    if a.cli.json {
        println!(
            "{}",
            serde_json::to_string(&doc)
                .map_err(|e| Error::Numerical(format!("cannot serialize: {e}")))?
        );
    } else {
        print!("{}", forming_runs::summary_table(&doc));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
