//! `cond_accuracy`: run time against error of cond₂ itself, route by route.
//!
//! ```text
//! cargo run --release --bin cond_accuracy                  # default panel, table on stdout
//! cargo run --release --bin cond_accuracy -- --render-only # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::cond_accuracy`]. Writes `cond_accuracy.csv`,
//! `cond_accuracy.json` (with provenance) and the figure `cond_accuracy` (error against time,
//! log–log, one colour per route) into `--out` (default `figures/cond_accuracy`).

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::study::cond_accuracy::{self, Config};
use penalty_lab::Result;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "cond_accuracy",
    version = penalty_lab::provenance::VERSION,
    about = "Error of cond2 against a double-double reference vs run time, for every route"
)]
struct Args {
    /// Generated scenes per family (beam, membrane, spectrum).
    #[arg(long, default_value_t = 2)]
    per_family: usize,
    /// Seed of the generated scenes.
    #[arg(long, default_value_t = 2024)]
    seed: u64,
    /// Penalty factors f (ε_c = f·K_dd on every constraint DOF; 0 = K alone).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, default_values_t = [0.0, 1.0, 1e3, 1e6, 1e9, 1e12])]
    factors: Vec<f64>,
    /// Scene files measured besides the generated ones ("" for none).
    #[arg(long, value_delimiter = ',', default_values_t = [
        "tests/data/elasticity/elasticity-quad-block.scene.json".to_string(),
        "tests/data/elasticity/elasticity-tet-brick.scene.json".to_string(),
    ])]
    scenes: Vec<String>,
    /// Repeats per timing (the median is reported).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Output directory.
    #[arg(long, default_value = "figures/cond_accuracy")]
    out: PathBuf,
    /// Re-render the figure from `OUT/cond_accuracy.json` without measuring.
    #[arg(long)]
    render_only: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

fn run(a: &Args) -> Result<()> {
    let rows = if a.render_only {
        cond_accuracy::load(&a.out)?
    } else {
        let cfg = Config {
            per_family: a.per_family,
            seed: a.seed,
            factors: a.factors.clone(),
            scene_files: a
                .scenes
                .iter()
                .filter(|s| !s.is_empty())
                .map(PathBuf::from)
                .collect(),
            repeats: a.repeats,
        };
        let progress = Progress::new("cond_accuracy (matrices)", a.quiet);
        progress.set_total((3 * cfg.per_family + cfg.scene_files.len()) * cfg.factors.len());
        let rows = cond_accuracy::run(&cfg, |what| progress.step(what))?;
        progress.finish();
        cond_accuracy::save(&a.out, &cfg, &rows)?;
        rows
    };
    cond_accuracy::render_figure(&rows, &a.out)?;
    print!("{}", cond_accuracy::table(&rows));
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
