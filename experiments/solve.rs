//! `solve`: one scene file, one strategy, every metric.
//!
//! ```text
//! cargo run --release --bin solve -- scenes/paper_beam.scene.json --method paper --delta 0.1 --json
//! ```
//!
//! Prints a readable table, or with `--json` one JSON object (contract in
//! `shared/notes/methods.md`); the study is [`penalty_lab::study::solve`]. Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::provenance;
use penalty_lab::strategy::{registry, Knobs};
use penalty_lab::study::solve::{solve_scene, table};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "solve",
    version = penalty_lab::provenance::VERSION,
    about = "Solve one contact scene with one penalty strategy and report exact conditioning",
    after_help = "Methods: constant (--eps), scaled (--factor), spring|paper|condensed (--delta), \
                  lagrange, augmented (--eps, --tol; defaults: eps = max K[d,d] over the \
                  constrained DOFs, tol = 1e-9·max(1, max|û|); --adaptive for the per-constraint \
                  penalty update).\nExit status: 0 ok, 2 bad input or singular system."
)]
struct Args {
    /// Scene file (JSON; stiffness dense or Matrix Market).
    scene: PathBuf,
    /// Strategy.
    #[arg(long, value_parser = registry::method_parser())]
    method: String,
    /// Allowed penetration δ (units of u) for spring, paper, condensed.
    #[arg(long, allow_negative_numbers = true)]
    delta: Option<f64>,
    /// Penalty ε for constant and augmented.
    #[arg(long, allow_negative_numbers = true)]
    eps: Option<f64>,
    /// Factor f for scaled (ε_c = f times the diagonal entry of K at the DOF).
    #[arg(long, allow_negative_numbers = true)]
    factor: Option<f64>,
    /// Penetration tolerance for augmented.
    #[arg(long, allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Adaptive per-constraint penalty update (augmented).
    #[arg(long)]
    adaptive: bool,
    /// Skip cond₂ and log-det metrics (they cost O(N³) for dense systems).
    #[arg(long)]
    no_metrics: bool,
    /// Start constant, scaled and condensed from the exact contact set (a lagrange solve
    /// first), as every sweep row does: reproduces a sweep row's iteration counts.
    #[arg(long)]
    exact_start: bool,
    /// Relative accuracy asked of the cond₂ values, in (0, 1) (default: the accuracy
    /// contract, max(1e-12, 4·ε_mach·cond₂)); looser is faster, the bounds stay proven.
    #[arg(long, allow_negative_numbers = true)]
    cond_tol: Option<f64>,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| {
        let knobs = Knobs {
            eps: args.eps,
            factor: args.factor,
            delta: args.delta,
            tol: args.tol,
            adaptive: args.adaptive,
            ..Knobs::NONE
        };
        let v = solve_scene(
            &args.scene,
            &args.method,
            knobs,
            args.no_metrics,
            args.exact_start,
            args.cond_tol,
        )?;
        if args.json {
            println!("{}", provenance::json_text("solve result", &v)?);
        } else {
            print!("{}", table(&v));
        }
        Ok(())
    })
}
