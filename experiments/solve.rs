//! `solve`: one scene file, one strategy, every metric.
//!
//! ```text
//! cargo run --release --bin solve -- scenes/paper_beam.scene.json --method paper --delta 0.1 --json
//! ```
//!
//! Prints a readable table, or with `--json` one JSON object (contract in
//! `shared/notes/methods.md`). Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::conditioning;
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::scene;
use penalty_lab::strategy::{self, Knobs, Method, MethodName};
use penalty_lab::Error;
use serde_json::{json, Value};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

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
    #[arg(long, value_enum)]
    method: MethodName,
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
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

fn finite_or_null(x: Option<f64>) -> Value {
    match x {
        Some(v) if v.is_finite() => json!(v),
        _ => Value::Null,
    }
}

fn run(args: &Args) -> Result<Value, Error> {
    let sc = scene::read_scene(&args.scene)?;
    let p = &sc.problem;
    let mut knobs = Knobs {
        eps: args.eps,
        factor: args.factor,
        delta: args.delta,
        tol: args.tol,
        adaptive: args.adaptive,
    };
    if args.method == MethodName::Augmented {
        if knobs.eps.is_none() {
            let e = p
                .constraints
                .iter()
                .map(|c| p.k.diag(c.dof).abs())
                .fold(0.0f64, f64::max);
            knobs.eps = Some(if e > 0.0 { e } else { 1.0 });
        }
        if knobs.tol.is_none() {
            let s = p
                .constraints
                .iter()
                .map(|c| c.limit.abs())
                .fold(1.0f64, f64::max);
            knobs.tol = Some(1e-9 * s);
        }
    }
    let method = Method::from_name(args.method.as_str(), knobs)?;
    let t0 = Instant::now();
    let sol = strategy::solve(p, method)?;
    let seconds = t0.elapsed().as_secs_f64();
    let set = if args.no_metrics {
        MetricSet::default()
    } else {
        MetricSet::ALL
    };
    let m = metrics::compute(p, &sol, set)?;
    let mut warnings = sol.warnings.clone();
    warnings.extend(metrics::precision_warnings(&m));
    if let Some(c) = m.cond2_system {
        if !c.cond2.is_finite() {
            warnings.push("the system matrix is singular (cond2 = ∞)".into());
        }
    }
    if sol.u.iter().any(|v| !v.is_finite()) {
        return Err(Error::Numerical(
            "the solution contains NaN/Inf (system singular to working precision)".into(),
        ));
    }
    Ok(json!({
        "scene": sc.name,
        "n": p.n(),
        "m": p.m(),
        "method": method.name(),
        "knob": method,
        "u": sol.u,
        "penalties": sol.penalties,
        "gaps": sol.gaps,
        "forces": sol.forces,
        "max_penetration": sol.max_penetration,
        "cond2_K": finite_or_null(m.cond2_k.map(|c| c.cond2)),
        "cond2_system": finite_or_null(m.cond2_system.map(|c| c.cond2)),
        "cond_route_K": m.cond2_k.map(|c| c.route.name()),
        "cond_route_system": m.cond2_system.map(|c| c.route.name()),
        "cond2_K_bounds": bounds(m.cond2_k),
        "cond2_system_bounds": bounds(m.cond2_system),
        "log10_det_K": finite_or_null(m.log10_det_k),
        "log10_det_system": finite_or_null(m.log10_det_system),
        "log10_det_ratio": finite_or_null(m.log10_det_ratio),
        "linear_solves": sol.stats.linear_solves,
        "factorizations": sol.stats.factorizations,
        "iterations": sol.stats.iterations,
        "converged": sol.stats.converged,
        "refinements": sol.stats.refinements,
        "cg_iterations": sol.stats.cg_iterations,
        "active_set_sizes": sol.stats.active_set_sizes,
        "clipped": sol.stats.clipped,
        "system": sol.system,
        "seconds": seconds,
        "warnings": warnings,
    }))
}

/// The certified bracket `[lo, hi]` of a sparse-route cond₂ (null where not certified or
/// unbounded).
fn bounds(c: Option<conditioning::CondReport>) -> Value {
    match c.and_then(|c| c.certificate) {
        Some(cert) => {
            let (lo, hi) = cert.cond2_bounds();
            json!([finite_or_null(Some(lo)), finite_or_null(Some(hi))])
        }
        None => Value::Null,
    }
}

fn fmt_vec(v: &Value) -> String {
    match v.as_array() {
        Some(a) if a.len() <= 12 => a
            .iter()
            .map(|x| x.as_f64().map_or("null".into(), |f| format!("{f:.6}")))
            .collect::<Vec<_>>()
            .join("  "),
        Some(a) => format!("[{} values]", a.len()),
        None => v.to_string(),
    }
}

fn print_table(v: &Value) {
    println!("scene {}  (N = {}, m = {})", v["scene"], v["n"], v["m"]);
    println!("method {}  {}", v["method"], v["knob"]);
    if v["converged"] == Value::Bool(false) {
        println!("NOT CONVERGED (see the warnings below)");
    }
    for key in ["penalties", "gaps", "forces", "u"] {
        println!("{key:>18}: {}", fmt_vec(&v[key]));
    }
    for key in [
        "max_penetration",
        "cond2_K",
        "cond2_system",
        "cond_route_system",
        "cond2_system_bounds",
        "log10_det_K",
        "log10_det_system",
        "log10_det_ratio",
        "linear_solves",
        "factorizations",
        "iterations",
        "converged",
        "seconds",
    ] {
        let s = match &v[key] {
            Value::Number(n) if n.is_f64() => format!("{:.6e}", n.as_f64().unwrap_or(f64::NAN)),
            other => other.to_string(),
        };
        println!("{key:>18}: {s}");
    }
    match v["warnings"].as_array() {
        Some(w) if !w.is_empty() => {
            for x in w {
                println!("warning: {}", x.as_str().unwrap_or_default());
            }
        }
        _ => println!("warnings: none"),
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| {
        let v = run(&args)?;
        if args.json {
            println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
        } else {
            print_table(&v);
        }
        Ok(())
    })
}
