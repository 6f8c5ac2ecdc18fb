//! What an exact cond₂ costs, by route, against one Cholesky of the same matrix (the
//! `cond_cost` experiment).
//!
//! Matrices: the membrane stiffness (5-point Laplacian on `side × side` interior nodes, the
//! sweep's `membrane` family) and a sparse-assembled cantilever of `elements` Euler–Bernoulli
//! frame elements (the `beam` family). For each: the time of one sparse Cholesky (symbolic +
//! numeric — the floor any exact method pays), of the sparse exact route (Lanczos + inertia
//! certificate), and, up to `dense_max` unknowns, of the dense symmetric eigenvalue and SVD
//! routes. Times are medians of `repeats` runs, single-threaded.

mod figures;
mod report;

pub use figures::figures;
pub use report::table;

use crate::conditioning::{self, cond2_dense, cond2_sparse_spd};
use crate::error::{Error, Result};
use crate::linalg::Factorization;
use crate::model::beam::{Frame, Section};
use crate::model::membrane;
use crate::progress::Progress;
use crate::provenance;
use crate::stats::median_time;
use crate::system::Stiffness;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Smallest n used for the least-squares slopes of the figure's legend.
pub const SLOPE_MIN_N: f64 = 300.0;

/// What to measure.
#[derive(Clone, Debug, Serialize)]
pub struct CostConfig {
    /// Membrane grid sides (n = side²), each in 2..=2000.
    pub sides: Vec<usize>,
    /// Cantilever element counts (n = 3·elements), each in 1..=300 000.
    pub elements: Vec<usize>,
    /// Repeats per measurement (≥ 1; the median is reported).
    pub repeats: usize,
    /// Largest n for the dense routes.
    pub dense_max: usize,
}

impl CostConfig {
    /// Checks the repeats and the sizes; errors name the value and its range.
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--sides", &self.sides)?;
        Error::distinct("--elements", &self.elements)?;
        if self.repeats == 0 {
            return Err(Error::out_of_range("--repeats", self.repeats, "≥ 1"));
        }
        if let Some(s) = self.sides.iter().find(|&&s| !(2..=2000).contains(&s)) {
            return Err(Error::out_of_range("--sides entry", s, "in 2..=2000"));
        }
        if let Some(e) = self.elements.iter().find(|&&e| !(1..=300_000).contains(&e)) {
            return Err(Error::out_of_range("--elements entry", e, "in 1..=300000"));
        }
        Ok(())
    }
}

/// Measures every matrix of `cfg` ([`CostConfig::validate`]d first), one progress step per
/// matrix.
pub fn run(cfg: &CostConfig, progress: &Progress) -> Result<Vec<Row>> {
    cfg.validate()?;
    progress.set_total(cfg.sides.len() + cfg.elements.len());
    let mut rows = Vec::new();
    for &side in &cfg.sides {
        progress.message(format!("membrane {side}×{side}"));
        rows.push(measure(
            "membrane",
            &membrane::stiffness(side, 1.0)?,
            cfg.repeats,
            cfg.dense_max,
        )?);
        progress.step(&format!("cond_cost: membrane {side}×{side}"));
    }
    for &el in &cfg.elements {
        progress.message(format!("cantilever, {el} elements"));
        let frame = Frame::cantilever(el, 30.0, Section::rectangle(2100.0, 1.0, 1.0))?;
        rows.push(measure(
            "beam",
            &frame.assemble(true)?,
            cfg.repeats,
            cfg.dense_max,
        )?);
        progress.step(&format!("cond_cost: cantilever with {el} elements"));
    }
    progress.finish();
    Ok(rows)
}

/// One matrix, all routes.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Row {
    /// Matrix family (`membrane`, `beam`).
    pub family: String,
    /// Unknowns.
    pub n: usize,
    /// Stored nonzeros.
    pub nnz: usize,
    /// cond₂ by the sparse route.
    pub cond2: f64,
    /// Relative width of the certified cond₂ bracket (∞ where the bracket is unbounded,
    /// past cond₂ ≈ 1/ε_mach; JSON `null`).
    #[serde(deserialize_with = "null_is_infinite")]
    pub cond2_bracket: f64,
    /// Lanczos steps of the sparse route.
    pub lanczos_steps: usize,
    /// Cholesky factorizations of the sparse route.
    pub factorizations: usize,
    /// One sparse Cholesky, symbolic + numeric (s).
    pub cholesky_s: f64,
    /// The sparse exact route (s).
    pub sparse_exact_s: f64,
    /// Dense symmetric eigenvalues (s), up to `dense_max`.
    pub dense_eigen_s: Option<f64>,
    /// Dense SVD (s), up to `dense_max`.
    pub dense_svd_s: Option<f64>,
    /// Relative difference sparse route vs dense SVD (where the SVD ran).
    pub rel_diff_vs_svd: Option<f64>,
}

/// serde_json writes a non-finite f64 as `null`; read it back as +∞.
fn null_is_infinite<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// Times every route on the sparse matrix `a`: `repeats` runs each (median), the dense
/// routes only up to `dense_max` unknowns.
pub fn measure(family: &str, a: &Stiffness, repeats: usize, dense_max: usize) -> Result<Row> {
    let Stiffness::Sparse(m) = a else {
        return Err(Error::unsupported("cond_cost", "a sparse matrix"));
    };
    let n = a.n();
    let (cholesky_s, _) = median_time(repeats, || Factorization::new(a, true))?;
    let (sparse_exact_s, r) = median_time(repeats, || cond2_sparse_spd(m))?;
    let c = r.certificate.expect("sparse route has a certificate");
    let (lo, hi) = c.cond2_bounds();
    let (mut dense_eigen_s, mut dense_svd_s, mut rel_diff) = (None, None, None);
    if n <= dense_max {
        let d = a.to_dense();
        let (t, _) = median_time(repeats, || cond2_dense(d.as_ref(), true))?;
        dense_eigen_s = Some(t);
        let (t, s) = median_time(repeats, || cond2_dense(d.as_ref(), false))?;
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

/// The `cond_cost` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Membrane grid sides (n = side²).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "4,6,10,14,20,45,100,224,316"
    )]
    sides: Vec<usize>,
    /// Cantilever element counts (n = 3·elements).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "4,12,40,112,150,700,3300,33000"
    )]
    elements: Vec<usize>,
    /// Repeats per measurement (the median is reported).
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Largest n for the dense routes.
    #[arg(long, default_value_t = 2100)]
    dense_max: usize,
}

/// The study as the shared entry runs it ([`crate::study::shape::main`]).
pub struct CondCost;

impl crate::study::shape::Study for CondCost {
    const NAME: &'static str = "cond_cost";
    const ABOUT: &'static str =
        "Time of an exact cond2 by route (sparse inertia, dense eigen, dense SVD) against one Cholesky";
    const PROGRESS: &'static str = "cond_cost (matrices)";
    const DEFAULT_OUT: &'static str = "results/cond_cost";
    const FIGURES_DIR: &'static str = "";
    type Flags = Flags;
    type Config = CostConfig;
    type Record = Vec<Row>;

    fn config(a: &Flags) -> Result<CostConfig> {
        let cfg = CostConfig {
            sides: a.sides.clone(),
            elements: a.elements.clone(),
            repeats: a.repeats,
            dense_max: a.dense_max,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    fn run(cfg: &CostConfig, ctx: &crate::study::shape::RunContext) -> Result<Vec<Row>> {
        run(cfg, ctx.progress)
    }

    fn save(
        out: &Path,
        cfg: &CostConfig,
        rows: &Vec<Row>,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        crate::study::shape::save_rows(
            out,
            provenance,
            serde_json::json!({
                "config": cfg,
                "threads": 1,
                "bracket_tol": conditioning::sparse::BRACKET_TOL,
            }),
            rows,
        )
    }

    fn load(out: &Path) -> Result<Vec<Row>> {
        crate::study::shape::load_rows(out, Self::NAME)
    }

    fn figures(rows: &Vec<Row>) -> Result<Vec<crate::study::shape::Drawing>> {
        Ok(figures(rows))
    }

    fn report(rows: &Vec<Row>) -> String {
        table(rows)
    }

    fn json(rows: &Vec<Row>) -> Result<String> {
        provenance::json_text("cond_cost rows", rows)
    }
}
