//! `engine_scale`: the contact solve engine on full-contact membranes from 10⁴ to 10⁶ DOFs —
//! iterations, factorizations, CG iterations, wall time, peak memory, certified cond₂ per
//! method ([`penalty_lab::study::engine_scale`]).
//!
//! ```text
//! cargo run --release --bin engine_scale                             # 10⁴, 10⁵
//! cargo run --release --bin engine_scale -- --sizes 1000000 --methods condensed
//! ```
//!
//! Writes `rows.csv`, `rows.json` and `manifest.json` (provenance) and the figure
//! `engine_scale` into `--out` (default `figures/engine_scale`); prints a table.

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::strategy::registry;
use penalty_lab::study::engine_scale::{self, ScaleConfig};
use penalty_lab::{plot, provenance, Error, Result};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "engine_scale",
    version = penalty_lab::provenance::VERSION,
    about = "The contact solve engine at 1e4-1e6 DOFs"
)]
struct Args {
    /// Requested DOF counts (membrane side = round(√size)).
    #[arg(long, value_delimiter = ',', default_values_t = [10_000usize, 100_000])]
    sizes: Vec<usize>,
    /// Methods (default: constant, scaled, condensed, lagrange).
    #[arg(long, value_parser = registry::method_parser(), value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Skip the cond₂ metrics.
    #[arg(long)]
    no_cond: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
    /// Output directory.
    #[arg(long, default_value = "figures/engine_scale")]
    out: PathBuf,
    /// Re-render the figure from `OUT/rows.json` without solving.
    #[arg(long)]
    render_only: bool,
}

fn run(a: Args) -> Result<()> {
    let rows = if a.render_only {
        provenance::read_json(&a.out.join("rows.json"))?
    } else {
        measure(a.sizes, a.methods, a.no_cond, a.quiet, &a.out)?
    };
    let figs = engine_scale::figures(&rows);
    plot::render_panels(&figs, 2, &a.out.join("engine_scale"), (1120, 460))?;
    print_table(&rows);
    Ok(())
}

/// Solves and records `OUT/rows.{csv,json}` and `OUT/manifest.json`.
fn measure(
    sizes: Vec<usize>,
    methods: Option<Vec<String>>,
    no_cond: bool,
    quiet: bool,
    out: &std::path::Path,
) -> Result<Vec<engine_scale::ScaleRow>> {
    let cfg = ScaleConfig {
        sizes,
        methods: methods.unwrap_or_else(|| {
            engine_scale::scale_method_names()
                .iter()
                .map(|s| s.to_string())
                .collect()
        }),
        cond: !no_cond,
        ..Default::default()
    };
    let rows = engine_scale::run(&cfg, &Progress::new("engine_scale (solves)", quiet))?;
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    provenance::write_csv(&out.join("rows.csv"), &rows)?;
    provenance::write_json(&out.join("rows.json"), &rows)?;
    let manifest = provenance::Provenance::new("engine_scale").record(serde_json::json!({
        "config": cfg,
        "threads": 1,
        "timing": "wall time (std::time::Instant) of one strategy::solve, release build",
    }));
    provenance::write_json(&out.join("manifest.json"), &manifest)?;
    Ok(rows)
}

fn print_table(rows: &[engine_scale::ScaleRow]) {
    println!(
        "{:>8} {:<10} {:>5} {:>5} {:>5} {:>9} {:>9} {:>9} {:>11} {:>11}",
        "N", "method", "its", "fact", "CG", "solve s", "cond s", "peak MB", "cond2 K", "cond2 sys"
    );
    let e = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.4e}"));
    let f = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.2}"));
    for r in rows {
        println!(
            "{:>8} {:<10} {:>5} {:>5} {:>5} {:>9.2} {:>9} {:>9} {:>11} {:>11}{}",
            r.n,
            r.method,
            r.iterations,
            r.factorizations,
            r.cg_iterations,
            r.seconds_solve,
            f(r.seconds_cond_system),
            f(r.peak_rss_mb),
            e(r.cond2_k),
            e(r.cond2_system),
            if r.converged { "" } else { "  NOT CONVERGED" }
        );
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(args))
}
