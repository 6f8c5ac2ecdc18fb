//! `runtime_vs_error`: time to solution against error for every strategy as its knob varies,
//! on beam and membrane scenes from 10² to 10⁶ DOFs. Library: [`penalty_lab::perf`].
//!
//! ```text
//! cargo run --release --bin runtime_vs_error -- --smoke --json       # seconds
//! cargo run --release --bin runtime_vs_error                         # 10²…10⁶ DOFs, 3 repeats
//! cargo run --release --bin runtime_vs_error -- --sizes 100,10000 --repeats 5 --out results/rve
//! cargo run --release --bin runtime_vs_error -- --render-only --out figures/runtime_vs_error
//! ```
//!
//! Writes `OUT/rows.csv` (for spreadsheets), `OUT/rows.json` (every field, exact),
//! `OUT/manifest.json` (git commit, config, crate versions, wall time) and
//! `OUT/figures/*.{png,svg}`, rendered from `rows.json` once it is written (`--render-only`
//! re-renders from it without measuring); progress goes to stderr. A strategy that errors or would
//! exceed the per-solve budget at some size is recorded as a row with the reason; the run goes
//! on. Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::perf::{self, Knobs, PerfConfig, PerfRow};
use penalty_lab::plot;
use penalty_lab::progress::Progress;
use penalty_lab::provenance;
use penalty_lab::strategy::{MethodName, METHOD_NAMES};
use penalty_lab::Error;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "runtime_vs_error",
    version = penalty_lab::provenance::VERSION,
    about = "Time to solution against error for every contact strategy, as its knob varies, at increasing size",
    after_help = "Knobs: ε for constant (relative to max K[d,d]), factor for scaled, δ for \
                  spring/paper/condensed and the tolerance for augmented (relative to the \
                  displacement scale).\nExit status: 0 ok, 2 bad input."
)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = "results/runtime_vs_error")]
    out: PathBuf,
    /// Small and quick: sizes 100 and 1000, 1 repeat, 3 knob values per strategy.
    #[arg(long)]
    smoke: bool,
    /// Print the rows and manifest as one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
    /// Requested DOF counts, comma-separated (default 100,1000,10000,100000,1000000; smoke
    /// 100,1000).
    #[arg(long, value_delimiter = ',')]
    sizes: Option<Vec<usize>>,
    /// Families, comma-separated: beam, membrane.
    #[arg(long, value_delimiter = ',', default_value = "beam,membrane")]
    families: Vec<String>,
    /// Methods, comma-separated (default: all seven).
    #[arg(long, value_enum, value_delimiter = ',')]
    methods: Option<Vec<MethodName>>,
    /// Timed repeats per point; the median is reported (default 3; smoke 1).
    #[arg(long)]
    repeats: Option<usize>,
    /// Per-solve time budget in seconds: a method predicted to exceed it at a size is skipped.
    #[arg(long, default_value_t = 30.0)]
    budget: f64,
    /// Maximum contact constraints per scene.
    #[arg(long, default_value_t = 400)]
    max_constraints: usize,
    /// Memory limit for condensed's N×m block, in GB.
    #[arg(long, default_value_t = 4.0)]
    memory_gb: f64,
    /// Skip the figures.
    #[arg(long)]
    no_figures: bool,
    /// Re-render the figures from `OUT/rows.json` without measuring.
    #[arg(long, conflicts_with_all = ["smoke", "json", "no_figures"])]
    render_only: bool,
}

fn opt<T: std::fmt::LowerExp>(v: Option<T>) -> String {
    v.map_or(String::new(), |x| format!("{x:e}"))
}

fn csv(rows: &[PerfRow]) -> String {
    let mut t = String::from(
        "family,size,n,m,method,knob,value,value_rel,status,seconds,seconds_all,\
         max_penetration,penetration_rel,error_vs_ref,reference,iterations,factorizations,\
         linear_solves,converged,n_warnings,reason\n",
    );
    for r in rows {
        let cells = [
            r.family.clone(),
            r.size.to_string(),
            r.n.to_string(),
            r.m.to_string(),
            r.method.clone(),
            r.knob.clone(),
            format!("{:e}", r.value),
            format!("{:e}", r.value_rel),
            r.status.clone(),
            opt(r.seconds),
            r.seconds_all
                .iter()
                .map(|s| format!("{s:e}"))
                .collect::<Vec<_>>()
                .join(" "),
            opt(r.max_penetration),
            opt(r.penetration_rel),
            opt(r.error_vs_ref),
            r.reference.clone(),
            r.iterations.map_or(String::new(), |v| v.to_string()),
            r.factorizations.map_or(String::new(), |v| v.to_string()),
            r.linear_solves.map_or(String::new(), |v| v.to_string()),
            r.converged.map_or(String::new(), |v| v.to_string()),
            r.warnings.len().to_string(),
            r.reason.clone(),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

fn config(a: &Args) -> Result<PerfConfig, Error> {
    let sizes = a.sizes.clone().unwrap_or_else(|| {
        if a.smoke {
            vec![100, 1000]
        } else {
            vec![100, 1_000, 10_000, 100_000, 1_000_000]
        }
    });
    let cfg = PerfConfig {
        families: a.families.iter().map(|s| s.trim().to_string()).collect(),
        sizes,
        methods: a.methods.clone().map_or_else(
            || METHOD_NAMES.iter().map(|s| s.to_string()).collect(),
            |v| v.iter().map(|m| m.as_str().to_string()).collect(),
        ),
        repeats: a.repeats.unwrap_or(if a.smoke { 1 } else { 3 }),
        budget_seconds: a.budget,
        max_constraints: a.max_constraints,
        memory_limit_bytes: a.memory_gb * 1e9,
        knobs: if a.smoke {
            Knobs::smoke()
        } else {
            Knobs::full()
        },
    };
    if !(a.memory_gb.is_finite() && a.memory_gb > 0.0) {
        return Err(Error::input(format!(
            "--memory-gb {}: need a finite number > 0",
            a.memory_gb
        )));
    }
    cfg.validate()?;
    Ok(cfg)
}

/// Renders every figure into `OUT/figures` from `OUT/rows.json`.
fn render(out: &Path) -> Result<(), Error> {
    let path = out.join("rows.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(path.display(), e))?;
    let rows: Vec<PerfRow> = serde_json::from_str(&text)
        .map_err(|e| Error::input(format!("{}: {e}", path.display())))?;
    let dir = out.join("figures");
    let mut files = 0;
    for (name, panels) in perf::figures(&rows) {
        let cols = panels.len().min(3);
        let nrows = panels.len().div_ceil(cols) as u32;
        files += plot::render_panels(
            &panels,
            cols,
            &dir.join(&name),
            (560 * cols as u32, 460 * nrows),
        )?
        .len();
    }
    eprintln!("rendered {files} figure files into {}", dir.display());
    Ok(())
}

fn run(a: &Args) -> Result<(), Error> {
    if a.render_only {
        return render(&a.out);
    }
    let cfg = config(a)?;
    let t0 = Instant::now();
    let progress = Progress::new("runtime_vs_error (points)", a.quiet);
    let rows = perf::run(&cfg, &progress)?;
    progress.finish();
    let wall = t0.elapsed().as_secs_f64();
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(a.out.display(), e))?;
    provenance::write_atomic(&a.out.join("rows.csv"), csv(&rows).as_bytes())?;
    provenance::write_atomic(
        &a.out.join("rows.json"),
        serde_json::to_string(&rows).expect("JSON value").as_bytes(),
    )?;
    let count = |s: &str| rows.iter().filter(|r| r.status == s).count();
    let manifest = json!({
        "experiment": "runtime_vs_error",
        "git_commit": provenance::git_commit(),
        "command": std::env::args().collect::<Vec<_>>().join(" "),
        "smoke": a.smoke,
        "config": cfg,
        "crate_versions": provenance::crate_versions(),
        "threads": 1,
        "timing": "wall time (std::time::Instant) of complete strategy::solve calls, release build, median of the repeats",
        "rows": rows.len(),
        "ok": count("ok"),
        "errors": count("error"),
        "skipped": count("skipped"),
        "wall_seconds": wall,
    });
    provenance::write_atomic(
        &a.out.join("manifest.json"),
        serde_json::to_string_pretty(&manifest)
            .expect("JSON value")
            .as_bytes(),
    )?;
    if !a.no_figures {
        render(&a.out)?;
    }
    eprintln!(
        "runtime_vs_error: {} rows ({} ok, {} errors, {} skipped) in {wall:.1} s → {}",
        rows.len(),
        count("ok"),
        count("error"),
        count("skipped"),
        a.out.display()
    );
    if a.json {
        let all = json!({"manifest": manifest, "rows": rows});
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
