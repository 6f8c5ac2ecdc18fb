//! `sweep`: ε and δ over randomized contact configurations — the harness's main job.
//!
//! ```text
//! cargo run --release --bin sweep                       # built-in default (< 1 min, 2 cores)
//! cargo run --release --bin sweep -- --families beam --count 50 --eps 1e0:1e10:21 --threads 2
//! cargo run --release --bin sweep -- --scenes-dir scenes/ --out results/files
//! cargo run --release --bin sweep -- --render-only --out results/sweep
//! cargo run --release --bin sweep -- merge results/all results/shard-1 results/shard-2
//! ```
//!
//! Writes `OUT/rows.csv`, `OUT/manifest.json` and `OUT/figures/*.{png,svg}`. Bad configuration
//! exits with status 2 and a message naming the problem and the valid choices.

use clap::Parser;
use penalty_lab::study::sweep::cli::ConfigArgs;
use penalty_lab::study::sweep::{self, figures, merge, RunOptions};
use penalty_lab::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "sweep",
    version = penalty_lab::provenance::VERSION,
    about = "Sweep penalty ε and allowed penetration δ over randomized contact scenes",
    after_help = "Without arguments: the built-in default (beam, membrane, spectrum, 8 scenes each, every \
                  method that handles bilateral ties) into results/sweep.\n`sweep merge OUT DIR...` merges the shard folders \
                  of one run (--shard K/N) into OUT.\nExit status: 0 ok, 2 bad configuration \
                  or input.",
    args_conflicts_with_subcommands = true
)]
struct Args {
    #[command(subcommand)]
    merge: Option<Merge>,
    #[command(flatten)]
    config: ConfigArgs,
    /// Output folder.
    #[arg(long, default_value = "results/sweep")]
    out: PathBuf,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Run shard K of N (contiguous blocks of scenes): K/N.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Continue an interrupted run in OUT (same config and shard).
    #[arg(long)]
    resume: bool,
    /// Only re-render the figures from OUT/rows.csv.
    #[arg(long)]
    render_only: bool,
    /// Also write every scene as a scene file (re-runnable with `solve`).
    #[arg(long, value_name = "DIR")]
    write_scenes: Option<PathBuf>,
    /// With --write-scenes: store every K as dense rows, whatever its structure (benchmarks).
    #[arg(long, requires = "write_scenes")]
    dense_scenes: bool,
    /// Skip the figures.
    #[arg(long)]
    no_figures: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

#[derive(clap::Subcommand, Debug)]
enum Merge {
    /// Merge the shard folders of one run into OUT (rows in scene order, one manifest); refuses
    /// missing, duplicated, incomplete or foreign shards.
    Merge {
        /// Output folder (not one of the shards).
        out: PathBuf,
        /// The shard folders, in any order.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Skip the figures.
        #[arg(long)]
        no_figures: bool,
    },
}

/// Renders the figures into `OUT/figures` from `OUT/rows.csv` and says how many it wrote.
fn render(out: &std::path::Path) -> Result<(), Error> {
    match figures::render_run(out)?.len() {
        0 => eprintln!(
            "no rows in {}: no figures rendered",
            out.join("rows.csv").display()
        ),
        k => eprintln!(
            "rendered {k} figure files into {}",
            out.join("figures").display()
        ),
    }
    Ok(())
}

fn run(a: &Args) -> Result<(), Error> {
    if let Some(Merge::Merge {
        out,
        dirs,
        no_figures,
    }) = &a.merge
    {
        let m = merge::merge(out, dirs)?;
        eprintln!(
            "sweep merge: {} shards, {} scenes, {} rows → {}",
            m.shards,
            m.scenes,
            m.rows,
            out.join("rows.csv").display()
        );
        return if *no_figures { Ok(()) } else { render(out) };
    }
    if a.render_only {
        return render(&a.out);
    }
    let cfg = a.config.config()?;
    let shard = a.shard.as_deref().map(sweep::parse_shard).transpose()?;
    if a.threads == Some(0) {
        return Err(Error::input("--threads must be ≥ 1"));
    }
    let opts = RunOptions {
        out: a.out.clone(),
        threads: a.threads,
        shard,
        resume: a.resume,
        write_scenes: a.write_scenes.clone(),
        dense_scenes: a.dense_scenes,
        progress: !a.quiet,
    };
    let s = sweep::run(&cfg, &opts)?;
    eprintln!(
        "sweep: {} scenes ({} resumed), {} rows in {:.2} s ({:.3e} rows/s) → {}",
        s.scenes,
        s.resumed_scenes,
        s.rows_written,
        s.wall_seconds,
        s.rows_per_second,
        a.out.join("rows.csv").display()
    );
    if !a.no_figures {
        render(&a.out)?;
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
