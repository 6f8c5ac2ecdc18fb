//! Run time against error for cond₂ itself, route by route (the `cond_accuracy` experiment).
//!
//! Matrices: `K + ε_c·e_d e_dᵀ` on every constraint DOF d of a scene, `ε_c = f·K_dd` with f from
//! 0 (K alone) to 1e12, for generated `beam`, `membrane` and `spectrum` scenes and the outside
//! elasticity scenes given as files. Reference: [`reference::extreme_eigenvalues_dd`]
//! (bisection with double-double inertia counts, ≈ 1e-25 relative), independent of every route.
//!
//! Routes, each timed (median of `repeats`, one thread):
//! * `dense_svd`, `dense_eigen` — faer's singular values / symmetric eigenvalues of the
//!   densified matrix;
//! * `certified` — [`conditioning::cond2`], the default (value + proven bounds);
//! * `lanczos_estimate` — the same converged Lanczos runs without the certificate
//!   ([`sparse::estimate_extremes`]): what the bounds cost;
//! * `condest_1norm` — Hager's 1-norm estimate `‖A‖₁·est‖A⁻¹‖₁` with one Cholesky factor
//!   (Hager 1984; Higham, *Accuracy and Stability*, Alg. 15.1): the cheap anchor, an estimate
//!   of κ₁, not κ₂ (`n^{-1}κ₁ ≤ κ₂ ≤ n·κ₁`), so its "error" says how far a 1-norm condition
//!   estimate is from cond₂.

mod figures;
mod report;

pub use figures::{figures, ERROR_FLOOR};
pub use report::table;

use crate::conditioning::{self, reference, sparse};
use crate::error::{Error, Result};
use crate::generate::{generate, Family, GeneratorConfig};
use crate::linalg::Factorization;
use crate::stats::median_time;
use crate::system::{Problem, Stiffness};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What to measure.
#[derive(Clone, Debug, Serialize)]
pub struct Config {
    /// Generated scenes per family (beam, membrane, spectrum).
    pub per_family: usize,
    /// Seed of the generated scenes.
    pub seed: u64,
    /// Penalty factors f (ε_c = f·K_dd; 0 = K alone).
    pub factors: Vec<f64>,
    /// Scene files measured besides the generated ones (e.g. the elasticity scenes).
    pub scene_files: Vec<PathBuf>,
    /// Repeats per timing (the median is reported), ≥ 1.
    pub repeats: usize,
}

/// One matrix, one route.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Row {
    /// Scene family or file stem.
    pub family: String,
    /// Scene name.
    pub scene: String,
    /// Unknowns.
    pub n: usize,
    /// Penalty factor f.
    pub factor: f64,
    /// Reference cond₂ (double-double bisection).
    pub cond2_ref: f64,
    /// Route (`dense_svd`, `dense_eigen`, `certified`, `lanczos_estimate`, `condest_1norm`).
    pub route: String,
    /// The value the route reports.
    pub value: f64,
    /// |value / cond2_ref − 1|.
    pub rel_error: f64,
    /// The contract `max(1e-12, 4·ε_mach·cond2_ref)`.
    pub contract: f64,
    /// Relative width of the route's bounds (`certified` only).
    pub bounds_width: Option<f64>,
    /// cond₂ of the equilibrated `Ŝ⁻¹AŜ⁻¹` (unit diagonal; double-double bisection).
    pub cond2_equilibrated: f64,
    /// The width target of the bounds, `max(1e-12, min(8·ε_mach·cond2_equilibrated,
    /// 3.5·ε_mach·cond2_ref))` ([`sparse::width_target`]).
    pub width_target: f64,
    /// Median wall time (s).
    pub seconds: f64,
}

/// The route names, in figure order.
pub const ROUTES: [&str; 5] = [
    "dense_svd",
    "dense_eigen",
    "certified",
    "lanczos_estimate",
    "condest_1norm",
];

/// Hager's estimate of `‖A⁻¹‖₁` for a symmetric A with factor `f` (at most 5 iterations).
fn inverse_one_norm(f: &Factorization, n: usize) -> f64 {
    let mut x = vec![1.0 / n as f64; n];
    let mut est = 0.0;
    for it in 0..5 {
        let y = f.solve(&x);
        est = y.iter().map(|v| v.abs()).sum::<f64>();
        let xi: Vec<f64> = y
            .iter()
            .map(|v| if *v >= 0.0 { 1.0 } else { -1.0 })
            .collect();
        let z = f.solve(&xi);
        let (j, zj) =
            z.iter().enumerate().fold(
                (0, 0.0f64),
                |b, (i, v)| if v.abs() > b.1 { (i, v.abs()) } else { b },
            );
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if it > 0 && zj <= ztx {
            break;
        }
        x = vec![0.0; n];
        x[j] = 1.0;
    }
    est
}

/// `‖A‖₁` (max absolute column sum).
fn one_norm(a: &Stiffness) -> f64 {
    let mut cols = vec![0.0f64; a.n()];
    a.for_each_entry(|_, j, v| cols[j] += v.abs());
    cols.into_iter().fold(0.0, f64::max)
}

/// Every route on `a` against its reference.
fn measure(
    family: &str,
    scene: &str,
    factor: f64,
    a: &Stiffness,
    repeats: usize,
) -> Result<Vec<Row>> {
    let n = a.n();
    let (lmax, lmin) = reference::extreme_eigenvalues_dd(a);
    let cond2_ref = lmax / lmin;
    let s_hat: Vec<f64> = (0..n).map(|i| 1.0 / a.diag(i).sqrt()).collect();
    let (hmax, hmin) = reference::extreme_eigenvalues_dd(&a.scaled(&s_hat));
    let cond2_equilibrated = hmax / hmin;
    let dense = a.to_dense();
    let sparse_a = a.to_sparse();
    let mut out = Vec::new();
    let mut push = |route: &str, seconds: f64, value: f64, bounds_width: Option<f64>| {
        out.push(Row {
            family: family.into(),
            scene: scene.into(),
            n,
            factor,
            cond2_ref,
            route: route.into(),
            value,
            rel_error: (value / cond2_ref - 1.0).abs(),
            contract: crate::conditioning::CondReport::contract_tol(cond2_ref),
            bounds_width,
            cond2_equilibrated,
            width_target: sparse::width_target(None, cond2_equilibrated, cond2_ref),
            seconds,
        })
    };
    let ratio = |v: &[f64]| {
        let mx = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mn = v.iter().fold(f64::INFINITY, |m, x| m.min(x.abs()));
        mx / mn
    };
    let (t, sv) = median_time(repeats, || {
        dense
            .singular_values()
            .map_err(|e| Error::Numerical(format!("SVD: {e:?}")))
    })?;
    push("dense_svd", t, ratio(&sv), None);
    let (t, ev) = median_time(repeats, || {
        dense
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .map_err(|e| Error::Numerical(format!("eigen: {e:?}")))
    })?;
    push("dense_eigen", t, ratio(&ev), None);
    let (t, r) = median_time(repeats, || conditioning::cond2(a))?;
    push("certified", t, r.cond2, Some(r.relative_width()));
    let (t, (mx, mn)) = median_time(repeats, || sparse::estimate_extremes(&sparse_a))?;
    push("lanczos_estimate", t, mx / mn, None);
    let (t, k1) = median_time(repeats, || {
        let f = Factorization::new(a, true)?;
        Ok(one_norm(a) * inverse_one_norm(&f, n))
    })?;
    push("condest_1norm", t, k1, None);
    Ok(out)
}

/// `K + Σ_c f·(d_cᵀKd_c) d_c d_cᵀ` over the constraints of `p` (`f·K_dd e_d e_dᵀ` for
/// single-DOF ones).
fn penalized(p: &Problem, factor: f64) -> Stiffness {
    if factor == 0.0 {
        return p.k.clone();
    }
    let adds: Vec<(usize, usize, f64)> = p
        .constraints
        .iter()
        .flat_map(|c| c.outer(factor * c.stiffness(&p.k)))
        .collect();
    p.k.with_entries_added(&adds)
}

impl Config {
    /// Checks the repeats and the penalty factors; errors name the value and its range.
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--factors", &self.factors)?;
        Error::distinct(
            "--scenes",
            self.scene_files.iter().map(|p| p.display().to_string()),
        )?;
        if self.per_family == 0 && self.scene_files.is_empty() {
            return Err(Error::none_given(
                "matrices to measure",
                " (--per-family 0 and no --scenes)",
            ));
        }
        if self.repeats == 0 {
            return Err(Error::out_of_range("--repeats", self.repeats, "≥ 1"));
        }
        if let Some(f) = self.factors.iter().find(|f| !(f.is_finite() && **f >= 0.0)) {
            return Err(Error::out_of_range(
                "penalty factor",
                f,
                "a finite number ≥ 0",
            ));
        }
        Ok(())
    }
}

/// Measures every matrix of `cfg` ([`Config::validate`]d first), calling `step` after each
/// (progress).
pub fn run(cfg: &Config, mut step: impl FnMut(&str)) -> Result<Vec<Row>> {
    cfg.validate()?;
    let mut scenes: Vec<(String, String, Problem)> = Vec::new();
    let gen = GeneratorConfig::default();
    for family in [Family::Beam, Family::Membrane, Family::Spectrum] {
        for i in 0..cfg.per_family {
            let s = generate(family, i, cfg.seed, &gen)?;
            scenes.push((family.name().into(), s.name.clone(), s.problem));
        }
    }
    for path in &cfg.scene_files {
        let s = crate::scene::read_scene(path)?;
        scenes.push(("elasticity".into(), s.name.clone(), s.problem));
    }
    let mut rows = Vec::new();
    for (family, name, p) in &scenes {
        for &f in &cfg.factors {
            rows.extend(measure(family, name, f, &penalized(p, f), cfg.repeats)?);
            step(&format!("{name}, f = {f:e}"));
        }
    }
    Ok(rows)
}

/// One route's summary ([`summary`]).
pub struct RouteSummary {
    /// Route name.
    pub route: String,
    /// Median wall time (s).
    pub median_seconds: f64,
    /// Median relative error.
    pub median_error: f64,
    /// Largest relative error.
    pub max_error: f64,
    /// Values within the contract.
    pub within: usize,
    /// Bounds no wider than their target (routes with bounds), and how many have bounds.
    pub tight: Option<(usize, usize)>,
    /// Rows.
    pub total: usize,
}

/// Per route: median time, median and largest error, how many values meet the contract and
/// how many bounds meet their width target.
pub fn summary(rows: &[Row]) -> Vec<RouteSummary> {
    ROUTES
        .iter()
        .map(|&route| {
            let r: Vec<&Row> = rows.iter().filter(|x| x.route == route).collect();
            let t: Vec<f64> = r.iter().map(|x| x.seconds).collect();
            let e: Vec<f64> = r.iter().map(|x| x.rel_error).collect();
            let widths: Vec<(f64, f64)> = r
                .iter()
                .filter_map(|x| x.bounds_width.map(|w| (w, x.width_target)))
                .collect();
            RouteSummary {
                route: route.to_string(),
                median_seconds: crate::stats::median(&t).unwrap_or(f64::NAN),
                median_error: crate::stats::median(&e).unwrap_or(f64::NAN),
                max_error: e.iter().copied().fold(0.0, f64::max),
                within: r.iter().filter(|x| x.rel_error <= x.contract).count(),
                tight: (!widths.is_empty())
                    .then(|| (widths.iter().filter(|(w, t)| w <= t).count(), widths.len())),
                total: r.len(),
            }
        })
        .collect()
}

/// The `cond_accuracy` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Generated scenes per family (beam, membrane, spectrum).
    #[arg(long, default_value_t = 2)]
    per_family: usize,
    /// Seed of the generated scenes.
    #[arg(long, default_value_t = 2024)]
    seed: u64,
    /// Penalty factors f (ε_c = f·K_dd on every constraint DOF; 0 = K alone).
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        default_value = "0,1,1e3,1e6,1e9,1e12"
    )]
    factors: Vec<f64>,
    /// Scene files measured besides the generated ones ("" for none).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "tests/data/elasticity/elasticity-quad-block.scene.json,tests/data/elasticity/elasticity-tet-brick.scene.json"
    )]
    scenes: Vec<String>,
    /// Repeats per timing (the median is reported).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
}

/// The study as the shared entry runs it ([`crate::study::shape::main`]).
pub struct CondAccuracy;

impl crate::study::shape::Study for CondAccuracy {
    const NAME: &'static str = "cond_accuracy";
    const ABOUT: &'static str =
        "Error of cond2 against a double-double reference vs run time, for every route";
    const PROGRESS: &'static str = "cond_accuracy (matrices)";
    const DEFAULT_OUT: &'static str = "results/cond_accuracy";
    const FIGURES_DIR: &'static str = "";
    type Flags = Flags;
    type Config = Config;
    type Record = Vec<Row>;

    fn config(a: &Flags) -> Result<Config> {
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
        cfg.validate()?;
        Ok(cfg)
    }

    fn run(cfg: &Config, ctx: &crate::study::shape::RunContext) -> Result<Vec<Row>> {
        let progress = ctx.progress;
        progress.set_total((3 * cfg.per_family + cfg.scene_files.len()) * cfg.factors.len());
        run(cfg, |what| progress.step(what))
    }

    fn save(
        out: &std::path::Path,
        cfg: &Config,
        rows: &Vec<Row>,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        crate::study::shape::save_rows(
            out,
            provenance,
            serde_json::json!({ "config": cfg, "threads": 1 }),
            rows,
        )
    }

    fn load(out: &std::path::Path) -> Result<Vec<Row>> {
        crate::study::shape::load_rows(out, Self::NAME)
    }

    fn figures(rows: &Vec<Row>) -> Result<Vec<crate::study::shape::Drawing>> {
        Ok(figures(rows))
    }

    fn report(rows: &Vec<Row>) -> String {
        table(rows)
    }
}
