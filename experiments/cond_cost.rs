//! `cond_cost`: what an exact cond₂ costs, by route, against one Cholesky of the same matrix.
//!
//! ```text
//! cargo run --release --bin cond_cost                       # default sizes, table on stdout
//! cargo run --release --bin cond_cost -- --sides 20,40,80 --repeats 3 --json
//! cargo run --release --bin cond_cost -- --render-only      # re-render from saved data
//! ```
//!
//! Matrices: the membrane stiffness (5-point Laplacian on `side × side` interior nodes, the
//! sweep's `membrane` family) and a sparse-assembled cantilever of `elements` Euler–Bernoulli
//! frame elements (the `beam` family). For each: the time of one sparse Cholesky (symbolic +
//! numeric — the floor any exact method pays), of the sparse exact route (Lanczos + inertia
//! certificate), and, up to `--dense-max` unknowns, of the dense symmetric eigenvalue and SVD
//! routes. Times are medians of `--repeats` runs, single-threaded. Writes `cond_cost.csv`,
//! `cond_cost.json` (with provenance) and the figure `cond_cost` (time vs n, log–log, with
//! least-squares slopes in the legend) into `--out` (default `figures/cond_cost`).

use clap::Parser;
use penalty_lab::conditioning::{self, cond2_dense, cond2_sparse_spd};
use penalty_lab::linalg::Factorization;
use penalty_lab::model::beam::{Frame, Section};
use penalty_lab::model::membrane;
use penalty_lab::plot::{render, Figure, Mark, Series};
use penalty_lab::provenance;
use penalty_lab::system::Stiffness;
use penalty_lab::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser, Debug, Serialize)]
#[command(
    name = "cond_cost",
    version = penalty_lab::provenance::VERSION,
    about = "Time of an exact cond2 by route (sparse inertia, dense eigen, dense SVD) against one Cholesky"
)]
struct Args {
    /// Membrane grid sides (n = side²).
    #[arg(long, value_delimiter = ',', default_values_t = [20usize, 45, 100, 224, 316])]
    sides: Vec<usize>,
    /// Cantilever element counts (n = 3·elements).
    #[arg(long, value_delimiter = ',', default_values_t = [150usize, 700, 3300, 33000])]
    elements: Vec<usize>,
    /// Repeats per measurement (the median is reported).
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Largest n for the dense routes.
    #[arg(long, default_value_t = 2100)]
    dense_max: usize,
    /// Output directory.
    #[arg(long, default_value = "figures/cond_cost")]
    out: PathBuf,
    /// Print the rows as JSON on stdout instead of the table.
    #[arg(long)]
    json: bool,
    /// Re-render the figure from `OUT/cond_cost.json` without measuring.
    #[arg(long)]
    render_only: bool,
}

/// One matrix, all routes.
#[derive(Serialize, Deserialize, Debug, Clone)]
struct Row {
    family: String,
    n: usize,
    nnz: usize,
    cond2: f64,
    /// Relative width of the certified cond₂ bracket.
    cond2_bracket: f64,
    lanczos_steps: usize,
    factorizations: usize,
    cholesky_s: f64,
    sparse_exact_s: f64,
    dense_eigen_s: Option<f64>,
    dense_svd_s: Option<f64>,
    /// Relative difference sparse route vs dense SVD (where the SVD ran).
    rel_diff_vs_svd: Option<f64>,
}

#[derive(Serialize, Deserialize)]
struct Document {
    provenance: serde_json::Value,
    rows: Vec<Row>,
}

fn time<T>(repeats: usize, mut f: impl FnMut() -> Result<T>) -> Result<(f64, T)> {
    let mut times = Vec::with_capacity(repeats);
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        let r = f()?;
        times.push(t0.elapsed().as_secs_f64());
        last = Some(r);
    }
    let med = penalty_lab::stats::median(&times).expect("at least one repeat");
    Ok((med, last.expect("at least one repeat")))
}

fn measure(family: &str, a: &Stiffness, args: &Args) -> Result<Row> {
    let Stiffness::Sparse(m) = a else {
        return Err(Error::input("cond_cost measures sparse matrices"));
    };
    let n = a.n();
    let (cholesky_s, _) = time(args.repeats, || Factorization::new(a, true))?;
    let (sparse_exact_s, r) = time(args.repeats, || cond2_sparse_spd(m))?;
    let c = r.certificate.expect("sparse route has a certificate");
    let (lo, hi) = c.cond2_bounds();
    let (mut dense_eigen_s, mut dense_svd_s, mut rel_diff) = (None, None, None);
    if n <= args.dense_max {
        let d = a.to_dense();
        let (t, _) = time(args.repeats, || cond2_dense(d.as_ref(), true))?;
        dense_eigen_s = Some(t);
        let (t, s) = time(args.repeats, || cond2_dense(d.as_ref(), false))?;
        dense_svd_s = Some(t);
        rel_diff = Some((r.cond2 - s.cond2).abs() / s.cond2);
    }
    Ok(Row {
        family: family.into(),
        n,
        nnz: a.nnz(),
        cond2: r.cond2,
        cond2_bracket: hi / lo - 1.0,
        lanczos_steps: c.lanczos_steps,
        factorizations: c.factorizations,
        cholesky_s,
        sparse_exact_s,
        dense_eigen_s,
        dense_svd_s,
        rel_diff_vs_svd: rel_diff,
    })
}

/// Least-squares slope of log t against log n.
fn slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Reads one route's wall time (s) off a row; `None` where the route was skipped.
type RouteTime = fn(&Row) -> Option<f64>;

fn render_figure(rows: &[Row], out: &Path) -> Result<Vec<PathBuf>> {
    let mut fig = Figure::new(
        "Exact cond₂: cost by route vs one sparse Cholesky (median, 1 thread)",
        "unknowns n",
        "wall time (s)",
    )
    .log_log()
    .with_size(1000, 650);
    let routes: [(&str, RouteTime); 4] = [
        ("one sparse Cholesky", |r| Some(r.cholesky_s)),
        ("sparse exact (Lanczos + inertia)", |r| {
            Some(r.sparse_exact_s)
        }),
        ("dense symmetric eigenvalues", |r| r.dense_eigen_s),
        ("dense SVD", |r| r.dense_svd_s),
    ];
    let mut color = 0;
    for family in ["membrane", "beam"] {
        for (name, get) in routes.iter() {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.family == family)
                .filter_map(|r| get(r).map(|t| (r.n as f64, t)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
            let label = match slope(&x, &y) {
                Some(s) => format!("{family}: {name} (slope {s:.2})"),
                None => format!("{family}: {name}"),
            };
            let mark = if family == "membrane" {
                Mark::LinePoints
            } else {
                Mark::Dashed
            };
            fig = fig.with_series(Series::new(label, x, y, mark).color(color % 8));
            color += 1;
        }
        color = 0;
    }
    render(&fig, &out.join("cond_cost"))
}

fn print_table(rows: &[Row]) {
    println!(
        "| family | n | cond₂ | bracket | Cholesky (s) | sparse exact (s) | ratio | dense eigen (s) | dense SVD (s) | vs SVD |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let f = |v: Option<f64>| v.map_or("—".to_string(), |t| format!("{t:.3e}"));
    for r in rows {
        println!(
            "| {} | {} | {:.4e} | {:.0e} | {:.3e} | {:.3e} | {:.1} | {} | {} | {} |",
            r.family,
            r.n,
            r.cond2,
            r.cond2_bracket,
            r.cholesky_s,
            r.sparse_exact_s,
            r.sparse_exact_s / r.cholesky_s,
            f(r.dense_eigen_s),
            f(r.dense_svd_s),
            r.rel_diff_vs_svd.map_or("—".into(), |d| format!("{d:.0e}")),
        );
    }
}

fn run(args: &Args) -> Result<()> {
    let json_path = args.out.join("cond_cost.json");
    let rows = if args.render_only {
        let text =
            std::fs::read_to_string(&json_path).map_err(|e| Error::io(json_path.display(), e))?;
        let doc: Document = serde_json::from_str(&text)
            .map_err(|e| Error::input(format!("{}: {e}", json_path.display())))?;
        doc.rows
    } else {
        if args.repeats == 0 {
            return Err(Error::input("--repeats must be ≥ 1"));
        }
        if let Some(s) = args.sides.iter().find(|&&s| !(2..=2000).contains(&s)) {
            return Err(Error::input(format!("--sides: {s} outside 2..=2000")));
        }
        if let Some(e) = args.elements.iter().find(|&&e| !(1..=300_000).contains(&e)) {
            return Err(Error::input(format!("--elements: {e} outside 1..=300000")));
        }
        let mut rows = Vec::new();
        for &side in &args.sides {
            eprintln!("cond_cost: membrane {side}×{side}");
            rows.push(measure("membrane", &membrane::stiffness(side, 1.0)?, args)?);
        }
        for &el in &args.elements {
            eprintln!("cond_cost: cantilever with {el} elements");
            let frame = Frame::cantilever(el, 30.0, Section::rectangle(2100.0, 1.0, 1.0))?;
            rows.push(measure("beam", &frame.assemble(true)?, args)?);
        }
        std::fs::create_dir_all(&args.out).map_err(|e| Error::io(args.out.display(), e))?;
        let doc = Document {
            provenance: serde_json::json!({
                "git_commit": provenance::git_commit(),
                "crate_versions": provenance::crate_versions(),
                "config": args,
                "threads": 1,
                "bracket_tol": conditioning::sparse::BRACKET_TOL,
                "command": std::env::args().collect::<Vec<_>>().join(" "),
            }),
            rows: rows.clone(),
        };
        let text = serde_json::to_string_pretty(&doc).expect("serializable");
        provenance::write_atomic(&json_path, text.as_bytes())?;
        provenance::write_csv(&args.out.join("cond_cost.csv"), &rows)?;
        rows
    };
    render_figure(&rows, &args.out)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&rows).expect("serializable")
        );
    } else {
        print_table(&rows);
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
