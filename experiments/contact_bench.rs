//! `contact_bench`: every contact rule against physics — Hertz contact (plane strain,
//! axisymmetric) and the contact patch test on graded Q4 meshes; the leaderboard of "how much
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
//! provenance, the convergence rates and the leaderboard) and the figures into `--out`
//! (default `results/contact_bench`). Each finished mesh is checkpointed in `OUT/meshes/`
//! (removed at the end); `--resume` reuses those of the same build and options. Bad options
//! exit with status 2 and one line.

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::strategy::registry;
use penalty_lab::study::contact_bench::{self, analytic::Case, figures, BenchConfig, Checkpoints};
use penalty_lab::{provenance, Error, Result};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "contact_bench",
    version = penalty_lab::provenance::VERSION,
    about = "Contact rules against Hertz and the patch test: pressure errors, cond2, leaderboard"
)]
struct Args {
    /// Cases: hertz-plane, hertz-axi, patch (default: all).
    #[arg(long, value_delimiter = ',')]
    cases: Option<Vec<String>>,
    /// Element sizes at the contact over a (Hertz) or over the block half-width (patch).
    #[arg(long, value_delimiter = ',')]
    meshes: Option<Vec<f64>>,
    /// Methods (default: every registered one).
    #[arg(long, value_parser = registry::method_parser(), value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// `constant`: ε grid over E*/a (E* = E/(1 − ν²)): ε per unit contact length/area.
    #[arg(long, value_delimiter = ',')]
    eps_rel: Option<Vec<f64>>,
    /// `scaled`: factors f of ε_c = f·K_dd (d the constraint's DOF).
    #[arg(long, value_delimiter = ',')]
    factors: Option<Vec<f64>>,
    /// δ-rules, barrier d̂ and augmented tolerances over a.
    #[arg(long, value_delimiter = ',')]
    deltas_rel: Option<Vec<f64>>,
    /// `optimal` runs on meshes of at most this many DOFs (default 100, at most 20000; one
    /// δ took 60–132 s at 2 211 DOFs, 8–64 min at 5 253 on 2 cores: see `--resume`).
    #[arg(long)]
    optimal_max_n: Option<usize>,
    /// Relative accuracy asked of cond₂.
    #[arg(long)]
    cond_tol: Option<f64>,
    /// Hertz block size over a (default 16; the domain study's blocks are fixed).
    #[arg(long)]
    block_over_a: Option<f64>,
    /// Output directory.
    #[arg(long, default_value = "results/contact_bench")]
    out: PathBuf,
    /// Print the summary (leaderboard, rates, rows) as JSON on stdout instead of the tables.
    #[arg(long)]
    json: bool,
    /// Re-render the figures from `OUT/summary.json` without solving.
    #[arg(long)]
    render_only: bool,
    /// Reuse the meshes an interrupted run of the same build and options checkpointed in
    /// `OUT/meshes/`.
    #[arg(long)]
    resume: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

fn config(a: &Args) -> Result<BenchConfig> {
    let mut cfg = BenchConfig::default();
    if let Some(cs) = &a.cases {
        cfg.cases = cs
            .iter()
            .map(|c| {
                Case::from_name(c).ok_or_else(|| {
                    Error::input(format!(
                        "--cases: unknown case {c} (hertz-plane, hertz-axi, flat-punch)"
                    ))
                })
            })
            .collect::<Result<_>>()?;
    }
    if let Some(m) = &a.meshes {
        cfg.meshes = m.clone();
    }
    if let Some(m) = &a.methods {
        cfg.methods = m.clone();
    }
    for (flag, v) in [
        (&mut cfg.eps_rel, &a.eps_rel),
        (&mut cfg.factors, &a.factors),
        (&mut cfg.deltas_rel, &a.deltas_rel),
    ] {
        if let Some(v) = v {
            *flag = v.clone();
        }
    }
    if let Some(n) = a.optimal_max_n {
        cfg.optimal_max_n = n;
    }
    if let Some(t) = a.cond_tol {
        cfg.cond_tol = t;
    }
    if let Some(b) = a.block_over_a {
        cfg.block_over_a = b;
    }
    cfg.validate()?;
    Ok(cfg)
}

fn run(a: &Args) -> Result<()> {
    let summary = if a.render_only {
        contact_bench::load(&a.out)?
    } else {
        let cfg = config(a)?;
        let checkpoints = Checkpoints::in_out(&a.out, a.resume);
        let progress = Progress::new("contact_bench (meshes)", a.quiet);
        let run = contact_bench::run(&cfg, &progress, Some(&checkpoints))?;
        let summary = contact_bench::save(&a.out, &cfg, &run)?;
        checkpoints.remove()?;
        summary
    };
    let files = figures::render(&a.out, &summary)?;
    if a.json {
        println!(
            "{}",
            provenance::json_text("contact_bench summary", &summary)?
        );
    } else {
        print!("{}", figures::tables(&summary));
        println!("{} figure files in {}", files.len(), a.out.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
