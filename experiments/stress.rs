//! `stress`: absurd penalties and near-singular systems — forward error against an
//! extended-precision reference, what iterative refinement and equilibration buy, and every
//! strategy at extreme knobs (no NaN/Inf, no panic, warnings where digits are lost).
//!
//! ```text
//! cargo run --release --bin stress -- --out figures/stress
//! cargo run --release --bin stress -- --families spectrum --count 4 --eps 1e-3:1e20:24 --json
//! ```
//!
//! Writes `OUT/eps_study.csv`, `OUT/strategies.csv` (for spreadsheets), `OUT/eps_study.json`
//! (every field of the ε study, exact), `OUT/stress.json` (git commit, config, seed, summary)
//! and `OUT/figures/*.{png,svg}`, rendered from `eps_study.json` once it is written
//! (`--render-only --out DIR` re-renders from it without running). Library:
//! [`penalty_lab::stability`]. Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::plot::{self, Figure};
use penalty_lab::provenance;
use penalty_lab::stability::{self, EpsRow, StrategyRow, StressConfig, StressScene};
use penalty_lab::stats::median;
use penalty_lab::sweep::generate::FAMILY_NAMES;
use penalty_lab::sweep::LogGrid;
use penalty_lab::Error;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "stress",
    version = penalty_lab::provenance::VERSION,
    about = "Stability stress: forward error vs ε and cond, refinement and scaling, strategies at extreme knobs",
    after_help = "Scenes: the paper's beam (bilateral and upper) plus COUNT generated scenes per \
                  family, small enough for the double-double reference.\nExit status: 0 ok, 2 bad \
                  input."
)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = "results/stress")]
    out: PathBuf,
    /// Print all results as one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Master seed of the generated scenes.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Generated scenes per family.
    #[arg(long, default_value_t = 2)]
    count: usize,
    /// Families of generated scenes, comma-separated (beam, membrane, spectrum); "none" for
    /// the paper's beam only.
    #[arg(long, value_delimiter = ',', default_value = "beam,membrane,spectrum")]
    families: Vec<String>,
    /// Uniform-ε grid LO:HI:N (log-spaced, inclusive).
    #[arg(long, value_name = "LO:HI:N", default_value = "1e-3:1e20:47")]
    eps: String,
    /// Maximum iterative-refinement steps.
    #[arg(long, default_value_t = 10)]
    max_steps: usize,
    /// Skip the figures.
    #[arg(long)]
    no_figures: bool,
    /// Re-render the figures from `OUT/eps_study.json` without running.
    #[arg(long, conflicts_with_all = ["json", "no_figures"])]
    render_only: bool,
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:e}"))
}

fn eps_csv(rows: &[EpsRow]) -> String {
    let mut t = String::from(
        "scene,family,n,m_active,eps,cond2,cond2_f64,cond_eps_mach,cond2_scaled,precision_warning,reference_correction,\
         err_plain,err_refined_working,err_refined_extended,err_equilibrated,\
         err_equilibrated_refined_extended,steps_extended,penalty_error,total_error_plain,\
         total_error_refined,variant_errors,strategy_status,strategy_max_penetration,\
         strategy_warnings,strategy_message\n",
    );
    for r in rows {
        let f = &r.forward;
        let cells = [
            r.scene.clone(),
            r.family.clone(),
            r.n.to_string(),
            r.m_active.to_string(),
            format!("{:e}", r.eps),
            opt(r.cond2),
            opt(r.cond2_f64),
            opt(r.cond_eps_mach),
            opt(r.cond2_scaled),
            r.precision_warning.to_string(),
            opt(r.reference_correction),
            opt(f.plain),
            opt(f.refined_working),
            opt(f.refined_extended),
            opt(f.equilibrated),
            opt(f.equilibrated_refined_extended),
            r.steps_extended.map_or(String::new(), |s| s.to_string()),
            opt(r.penalty_error),
            opt(r.total_error_plain),
            opt(r.total_error_refined),
            r.variant_errors.join(" | "),
            r.strategy_status.clone(),
            opt(r.strategy_max_penetration),
            r.strategy_warnings.to_string(),
            r.strategy_message.clone(),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

fn strategy_csv(rows: &[StrategyRow]) -> String {
    let mut t = String::from(
        "scene,family,n,m,method,knob,value,value2,adaptive,status,max_penetration,max_penalty,\
         cond2_system,precision_expected,n_warnings,forward_error,error_vs_lagrange,message,\
         warnings\n",
    );
    for r in rows {
        let cells = [
            r.scene.clone(),
            r.family.clone(),
            r.n.to_string(),
            r.m.to_string(),
            r.method.clone(),
            r.knob.clone(),
            format!("{:e}", r.value),
            opt(r.value2),
            r.adaptive.to_string(),
            r.status.clone(),
            opt(r.max_penetration),
            opt(r.max_penalty),
            opt(r.cond2_system),
            r.precision_expected.to_string(),
            r.warnings.len().to_string(),
            opt(r.forward_error),
            opt(r.error_vs_lagrange),
            r.message.clone(),
            r.warnings.join(" | "),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

/// What the run found, in numbers (also the `summary` of the JSON outputs).
fn summary(eps_rows: &[EpsRow], strat: &[StrategyRow]) -> Value {
    let count = |s: &str| strat.iter().filter(|r| r.status == s).count();
    let unwarned: Vec<Value> = strat
        .iter()
        .filter(|r| r.precision_expected && r.warnings.is_empty())
        .map(|r| json!({"scene": r.scene, "method": r.method, "value": r.value}))
        .collect();
    let bad: Vec<Value> = strat
        .iter()
        .filter(|r| r.status == "panic" || r.status == "non_finite")
        .map(|r| {
            json!({"scene": r.scene, "method": r.method, "knob": r.knob, "value": r.value,
                   "value2": r.value2, "adaptive": r.adaptive, "status": r.status,
                   "message": r.message})
        })
        .collect();
    // Refinement in the regime where theory says it converges (cond·ε_mach < 1e-2).
    let regime: Vec<&EpsRow> = eps_rows
        .iter()
        .filter(|r| r.cond_eps_mach.is_some_and(|c| c < 1e-2))
        .collect();
    let med = |f: &dyn Fn(&EpsRow) -> Option<f64>, rows: &[&EpsRow]| {
        median(&rows.iter().filter_map(|r| f(r)).collect::<Vec<_>>())
    };
    let beyond: Vec<&EpsRow> = eps_rows
        .iter()
        .filter(|r| r.cond_eps_mach.is_none_or(|c| c >= 1e-2))
        .collect();
    let plain_failed_equil_ok = eps_rows
        .iter()
        .filter(|r| r.forward.plain.is_none() && r.forward.equilibrated.is_some())
        .count();
    let max_cond = eps_rows
        .iter()
        .filter_map(|r| r.cond2)
        .chain(strat.iter().filter_map(|r| r.cond2_system))
        .fold(0.0f64, f64::max);
    json!({
        "strategy_runs": strat.len(),
        "ok": count("ok"),
        "clean_errors": count("error"),
        "non_finite": count("non_finite"),
        "panics": count("panic"),
        "panics_or_non_finite": bad,
        "precision_expected_but_unwarned": unwarned,
        "eps_points": eps_rows.len(),
        "max_cond2_seen": max_cond,
        "refinement_regime_cond_eps_below_1e-2": {
            "points": regime.len(),
            "median_err_plain": med(&|r| r.forward.plain, &regime),
            "median_err_refined_working": med(&|r| r.forward.refined_working, &regime),
            "median_err_refined_extended": med(&|r| r.forward.refined_extended, &regime),
            "median_err_equilibrated": med(&|r| r.forward.equilibrated, &regime),
        },
        "beyond_cond_eps_1e-2": {
            "points": beyond.len(),
            "plain_solved": beyond.iter().filter(|r| r.forward.plain.is_some()).count(),
            "equilibrated_solved": beyond.iter().filter(|r| r.forward.equilibrated.is_some()).count(),
            "median_err_plain": med(&|r| r.forward.plain, &beyond),
            "median_err_refined_extended": med(&|r| r.forward.refined_extended, &beyond),
            "median_err_equilibrated_refined_extended":
                med(&|r| r.forward.equilibrated_refined_extended, &beyond),
        },
        "points_where_plain_is_refused_but_equilibrated_solves": plain_failed_equil_ok,
    })
}

/// Renders the figures into `OUT/figures` from `OUT/eps_study.json` and says how many it wrote.
fn render(out: &Path) -> Result<(), Error> {
    let path = out.join("eps_study.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(path.display(), e))?;
    let eps_rows: Vec<EpsRow> = serde_json::from_str(&text)
        .map_err(|e| Error::input(format!("{}: {e}", path.display())))?;
    let dir = out.join("figures");
    let figs = stability::figures(&eps_rows);
    let mut n = 0;
    let panel = |prefix: &str| -> Vec<Figure> {
        figs.iter()
            .filter(|(name, _)| name.starts_with(prefix))
            .map(|(_, f)| f.clone())
            .collect()
    };
    for prefix in ["forward_error_vs_eps_", "error_vs_lagrange_"] {
        let fs = panel(prefix);
        if fs.is_empty() {
            continue;
        }
        let cols = 2;
        let rows = fs.len().div_ceil(cols) as u32;
        let stem = dir.join(prefix.trim_end_matches('_'));
        n += plot::render_panels(&fs, cols, &stem, (1500, 520 * rows))?.len();
    }
    for (name, fig) in &figs {
        if name.starts_with("forward_error_vs_") && !name.starts_with("forward_error_vs_eps_")
            || name.ends_with("_paper-beam")
        {
            n += plot::render(fig, &dir.join(name))?.len();
        }
    }
    eprintln!("rendered {n} figure files into {}", dir.display());
    Ok(())
}

fn run(a: &Args) -> Result<(), Error> {
    if a.render_only {
        return render(&a.out);
    }
    let grid = LogGrid::parse(&a.eps)?;
    let families: Vec<String> = a
        .families
        .iter()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty() && s != "none")
        .collect();
    for f in &families {
        if !FAMILY_NAMES.contains(&f.as_str()) {
            return Err(Error::input(format!(
                "unknown family '{f}' (valid: {}, or none)",
                FAMILY_NAMES.join(", ")
            )));
        }
    }
    if a.count > 50 {
        return Err(Error::input(format!(
            "--count {} is too large for the dense double-double reference (max 50)",
            a.count
        )));
    }
    let cfg = StressConfig {
        eps: grid.values(),
        max_steps: a.max_steps,
        ..StressConfig::default()
    };
    let t0 = Instant::now();
    let scenes: Vec<StressScene> = stability::stress_scenes(a.seed, a.count, &families)?;
    let mut eps_rows = Vec::new();
    let mut strat_rows = Vec::new();
    for (i, sc) in scenes.iter().enumerate() {
        let t = Instant::now();
        eps_rows.extend(stability::eps_study(sc, &cfg)?);
        strat_rows.extend(stability::strategy_study(sc, &cfg)?);
        eprintln!(
            "[{}/{}] {} (N = {}, m = {}): {:.2} s",
            i + 1,
            scenes.len(),
            sc.name,
            sc.problem.n(),
            sc.problem.m(),
            t.elapsed().as_secs_f64()
        );
    }
    let wall = t0.elapsed().as_secs_f64();
    let summary = summary(&eps_rows, &strat_rows);
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(a.out.display(), e))?;
    let write =
        |name: &str, text: &str| provenance::write_atomic(&a.out.join(name), text.as_bytes());
    write("eps_study.csv", &eps_csv(&eps_rows))?;
    write(
        "eps_study.json",
        &serde_json::to_string(&eps_rows).expect("JSON value"),
    )?;
    write("strategies.csv", &strategy_csv(&strat_rows))?;
    let manifest = json!({
        "experiment": "stress",
        "git_commit": provenance::git_commit(),
        "crate_versions": provenance::crate_versions(),
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "seed": a.seed,
        "count": a.count,
        "families": families,
        "config": cfg,
        "scenes": scenes.iter().map(|s| json!({"name": s.name, "family": s.family,
            "n": s.problem.n(), "m": s.problem.m()})).collect::<Vec<_>>(),
        "reference": "double-double Gaussian elimination with partial pivoting + 2 refinement steps (stability::PenalizedSystem::reference)",
        "plot_floor": stability::PLOT_FLOOR,
        "wall_seconds": wall,
        "summary": summary,
    });
    let text = serde_json::to_string_pretty(&manifest).expect("JSON value");
    write("stress.json", &text)?;
    if !a.no_figures && !eps_rows.is_empty() {
        render(&a.out)?;
    }
    eprintln!(
        "stress: {} scenes, {} ε points, {} strategy runs ({} ok, {} clean errors, {} non-finite, {} panics) in {:.1} s → {}",
        scenes.len(),
        eps_rows.len(),
        strat_rows.len(),
        manifest["summary"]["ok"],
        manifest["summary"]["clean_errors"],
        manifest["summary"]["non_finite"],
        manifest["summary"]["panics"],
        wall,
        a.out.display()
    );
    if a.json {
        let all = json!({
            "manifest": manifest,
            "eps_study": eps_rows,
            "strategies": strat_rows,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&all).expect("JSON value")
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
