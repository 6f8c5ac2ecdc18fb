//! `deep_drawing`: the paper's second example (Woo-like deep draw, forming.md defaults) with
//! the classical penalty (ε = 1e7), the paper's Eq. 28–29 (`adaptive`, δ = 1e-5 in) and the
//! exact `condensed` rule — the paper's Fig. 7.
//!
//! ```text
//! cargo run --release --bin deep_drawing -- --out figures/deep_drawing
//! cargo run --release --bin deep_drawing -- --json --steps 200 --elements 100
//! ```
//!
//! `--out DIR` writes `deep_drawing.json` (provenance, config, every step and snapshot),
//! `steps_<run>.csv` and the figures (rendered from the saved JSON). Bad input exits with
//! status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::forming::experiment::{self, ExperimentConfig, Overrides};
use penalty_lab::forming::report;
use penalty_lab::forming::FormingConfig;
use penalty_lab::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "deep_drawing",
    about = "Woo-like hemispherical-punch deep draw: classical vs adaptive penalty (paper Fig. 7)",
    after_help = "Units: inch, ton-force, second. Exit status: 0 ok, 2 bad input or failed run."
)]
struct Args {
    /// Print the JSON document on stdout.
    #[arg(long)]
    json: bool,
    /// Write JSON, CSV step tables and figures into DIR.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Number of elements (default 50).
    #[arg(long)]
    elements: Option<usize>,
    /// Number of time steps (default 100).
    #[arg(long)]
    steps: Option<usize>,
    /// Punch travel in inches (default 1.0).
    #[arg(long, allow_negative_numbers = true)]
    travel: Option<f64>,
    /// Coulomb friction coefficient (default 0.2).
    #[arg(long, allow_negative_numbers = true)]
    friction: Option<f64>,
    /// Classical penalty ε in ton-force·s/in (default 1e7).
    #[arg(long, allow_negative_numbers = true)]
    penalty: Option<f64>,
    /// Allowed penetration δ in inches for the adaptive runs (default 1e-5).
    #[arg(long, allow_negative_numbers = true)]
    delta: Option<f64>,
    /// TOML file: `penalty`, `delta`, `condensed`, and a `[forming]` table; flags override it.
    #[arg(long, value_name = "FILE.toml")]
    config: Option<PathBuf>,
}

fn build(a: &Args, preset: FormingConfig) -> Result<ExperimentConfig, Error> {
    let c = match &a.config {
        Some(p) => ExperimentConfig::from_toml_file(p, preset)?,
        None => ExperimentConfig::paper_knobs(preset),
    };
    c.apply(&Overrides {
        elements: a.elements,
        steps: a.steps,
        travel: a.travel,
        friction: a.friction,
        penalty: a.penalty,
        delta: a.delta,
    })
}

fn run(a: &Args) -> Result<(), Error> {
    let cfg = build(a, FormingConfig::woo_deep_drawing())?;
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let doc = experiment::run("deep_drawing", &cfg, &command)?;
    if let Some(dir) = &a.out {
        let json = report::save(dir, "deep_drawing", &doc)?;
        let saved = report::load(&json)?;
        report::render_figures(dir, &saved, "Deep drawing", "fig7_condition_per_step")?;
    }
    if a.json {
        println!(
            "{}",
            serde_json::to_string(&doc)
                .map_err(|e| Error::Numerical(format!("cannot serialize: {e}")))?
        );
    } else {
        print!("{}", experiment::summary_table(&doc));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    std::panic::set_hook(Box::new(|_| {}));
    match std::panic::catch_unwind(|| run(&args)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(_) => {
            eprintln!("error: internal failure (panic); please report the command line");
            ExitCode::from(2)
        }
    }
}
