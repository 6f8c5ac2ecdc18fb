//! cond₂ of a bare Matrix Market matrix with its certificate: the `cond` binary's study
//! ([`Cond`], a one-shot study: no record in `--out`, no figures) and its table
//! ([`report::table`]).
//!
//! cond₂(A) = σ_max(A) / σ_min(A), by [`crate::conditioning::cond2_warm`] — the same engine,
//! routes and accuracy contract as `solve`'s cond₂ values:
//!
//! - a symmetric positive definite matrix takes the certified inertia route (sparse Cholesky
//!   of shifted matrices; any size), with proven bounds;
//! - a symmetric indefinite one (e.g. a saddle point) falls back to dense eigenvalues
//!   (densified up to [`crate::conditioning::DENSIFY_LIMIT`] unknowns, with Kahan-type bounds);
//! - a near-symmetric one (rounding-level asymmetry) is certified through its symmetric part,
//!   the bracket widened by the skew part's norm;
//! - an unsymmetric one takes the dense SVD (densified up to the same limit); above it the run
//!   is refused with the size named.
//!
//! Use it on a matrix assembled elsewhere (`cond K.mtx --json`): the JSON carries `cond2`,
//! `cond2_lo`, `cond2_hi`, `cond2_bounds_proven`, `cond2_within_contract` and `cond_route`
//! (names of `solve --json`), and `warnings` says out loud when the value is not proven within
//! the contract or σ_min could not be bounded away from 0.

pub mod report;

pub use report::table;

use crate::conditioning::{cond2_warm, CondReport, Reuse};
use crate::error::{Error, Result};
use crate::metrics::MetricSet;
use crate::scene::matrix_market::read_matrix_market;
use crate::study::shape::{Drawing, RunContext, Study};
use crate::system::{Stiffness, Symmetry};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The `cond` binary's study (module doc).
pub struct Cond;

/// `cond`'s flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// The matrix: a Matrix Market file (`coordinate` or `array`, `real`/`integer`,
    /// `general` or `symmetric` storage), square.
    pub matrix: PathBuf,
    /// Relative accuracy asked of cond₂, in (0, 1) (default: the contract,
    /// max(1e-12, 4·ε_mach·cond₂)). A looser tolerance stops the Lanczos runs earlier; the
    /// bounds stay proven where the route proves them.
    #[arg(long, value_name = "REL")]
    pub cond_tol: Option<f64>,
}

/// `cond`'s validated configuration.
#[derive(Clone, Debug, Serialize)]
pub struct CondConfig {
    /// The Matrix Market file.
    pub matrix: PathBuf,
    /// Relative accuracy asked (`None`: the contract).
    pub cond_tol: Option<f64>,
}

/// The certified cond₂ of one matrix (what `cond --json` prints).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CondRecord {
    /// The file, as given.
    pub matrix: String,
    /// Dimension N of the N×N matrix.
    pub n: usize,
    /// Stored entries after expanding symmetric storage and summing duplicates.
    pub nnz: usize,
    /// `exact`, `near` (rounding-level asymmetry) or `unsymmetric`.
    pub symmetry: String,
    /// The largest |a_ij − a_ji| (0 for an exactly symmetric matrix).
    pub asymmetry_max_abs: f64,
    /// σ_max/σ_min, the best estimate (`null`: +∞, σ_min = 0 to working precision).
    pub cond2: Option<f64>,
    /// Lower bound of cond₂.
    pub cond2_lo: Option<f64>,
    /// Upper bound of cond₂ (`null`: +∞, σ_min not bounded away from 0).
    pub cond2_hi: Option<f64>,
    /// Whether `[cond2_lo, cond2_hi]` is proven, every rounding included.
    pub cond2_bounds_proven: bool,
    /// Whether `cond2` is proven within max(1e-12, 4·ε_mach·cond₂) of the exact value.
    pub cond2_within_contract: bool,
    /// The largest relative error of `cond2` its bounds allow (`null`: unbounded).
    pub cond2_error_bound: Option<f64>,
    /// The route taken ([`crate::conditioning::CondRoute::name`]).
    pub cond_route: String,
    /// Largest singular value (estimate).
    pub sigma_max: f64,
    /// Smallest singular value (estimate).
    pub sigma_min: f64,
    /// log10|det A| where the route factorized A itself (the SPD route), else `null`.
    pub log10_det: Option<f64>,
    /// The relative accuracy asked (`null`: the contract).
    pub cond_tol: Option<f64>,
    /// Wall-clock seconds of the cond₂ (reading the file excluded).
    pub seconds: f64,
    /// What the numbers do not say by themselves.
    pub warnings: Vec<String>,
}

/// Reads `path` and certifies its cond₂ (module doc). Errors on an unreadable or malformed
/// file, a `cond_tol` outside (0, 1), and an unsymmetric or indefinite sparse matrix above the
/// densify limit.
pub fn cond_of_file(path: &Path, cond_tol: Option<f64>) -> Result<CondRecord> {
    MetricSet::check_cond_tol(cond_tol).map_err(|e| e.for_flag("--cond-tol"))?;
    let a = read_matrix_market(path)?;
    let nnz = a.nnz();
    // The storage its structure prefers, as scenes are read: the same routes as `solve`.
    let a = a.in_preferred_storage();
    let mut r = cond_of_matrix(&a, path.display().to_string(), cond_tol)?;
    r.nnz = nnz;
    Ok(r)
}

/// The certified cond₂ of `a` as a [`CondRecord`] named `name` (`nnz`: the entries `a` stores,
/// N² for dense storage).
pub fn cond_of_matrix(a: &Stiffness, name: String, cond_tol: Option<f64>) -> Result<CondRecord> {
    let symmetry = a.symmetry();
    let t0 = Instant::now();
    let (r, _) = cond2_warm(
        a,
        Reuse {
            tol: cond_tol,
            ..Reuse::default()
        },
    )?;
    let seconds = t0.elapsed().as_secs_f64();
    let (sym_name, asym) = match symmetry {
        Symmetry::Exact => ("exact", 0.0),
        Symmetry::Near(s) => ("near", s.max_abs),
        Symmetry::Unsymmetric(s) => ("unsymmetric", s.max_abs),
    };
    let within = r.within_contract();
    Ok(CondRecord {
        matrix: name,
        n: a.n(),
        nnz: a.nnz(),
        symmetry: sym_name.into(),
        asymmetry_max_abs: asym,
        cond2: finite(r.cond2),
        cond2_lo: finite(r.cond2_lo),
        cond2_hi: finite(r.cond2_hi),
        cond2_bounds_proven: r.bounds_proven,
        cond2_within_contract: within,
        cond2_error_bound: finite(r.error_bound()),
        cond_route: r.route.name().into(),
        sigma_max: r.sigma_max,
        sigma_min: r.sigma_min,
        log10_det: r.log10_det.and_then(finite),
        cond_tol,
        seconds,
        warnings: warnings(&r, within, cond_tol),
    })
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// What a report's numbers do not say by themselves: singular to working precision, bounds
/// not proven, or a value not proven within the contract (with the route and the width).
fn warnings(r: &CondReport, within: bool, cond_tol: Option<f64>) -> Vec<String> {
    let mut w = Vec::new();
    let route = r.route.name();
    if !r.cond2.is_finite() || r.sigma_min <= 0.0 {
        w.push(format!(
            "the matrix is singular to working precision (σ_min = {:e}): cond2 = ∞",
            r.sigma_min
        ));
    } else {
        w.extend(r.singular_caveat("the matrix"));
    }
    w.extend(r.unproven_caveat("the matrix"));
    if r.cond2.is_finite() && r.cond2_hi.is_finite() && !within {
        let tol = cond_tol.unwrap_or_else(|| CondReport::contract_tol(r.cond2_lo));
        let bound = r.error_bound();
        if cond_tol.is_none() || bound > tol {
            w.push(format!(
                "cond2 is not proven within the accuracy contract: route {route}, bounds \
                 [{:.6e}, {:.6e}] allow a relative error of {bound:.1e} (contract {:.1e}{})",
                r.cond2_lo,
                r.cond2_hi,
                CondReport::contract_tol(r.cond2_lo),
                cond_tol.map_or(String::new(), |t| format!(", asked {t:.1e}")),
            ));
        }
    }
    w
}

impl Study for Cond {
    const NAME: &'static str = "cond";
    const ABOUT: &'static str =
        "The 2-norm condition number of a Matrix Market matrix, with proven bounds";
    const PROGRESS: &'static str = "cond";
    const DEFAULT_OUT: &'static str = "";
    const SAVES: bool = false;
    type Flags = Flags;
    type Config = CondConfig;
    type Record = CondRecord;

    fn after_help() -> String {
        format!(
            "cond2 = σ_max/σ_min. Routes: symmetric positive definite → certified inertia \
             route (any size); symmetric indefinite, near-symmetric and unsymmetric → dense \
             eigenvalues/SVD, densified up to {} unknowns (refused above). \
             Exit status: 0 ok, 2 bad input.",
            crate::conditioning::DENSIFY_LIMIT
        )
    }

    fn config(f: &Flags) -> Result<CondConfig> {
        MetricSet::check_cond_tol(f.cond_tol).map_err(|e| e.for_flag("--cond-tol"))?;
        Ok(CondConfig {
            matrix: f.matrix.clone(),
            cond_tol: f.cond_tol,
        })
    }

    fn run(c: &CondConfig, _: &RunContext) -> Result<CondRecord> {
        cond_of_file(&c.matrix, c.cond_tol)
    }

    fn save(
        _: &Path,
        _: &CondConfig,
        _: &CondRecord,
        _: &crate::provenance::Provenance,
    ) -> Result<()> {
        Ok(())
    }

    fn load(_: &Path) -> Result<CondRecord> {
        Err(Error::unsupported(
            "--render-only",
            "a study that keeps a record (cond keeps no record)",
        ))
    }

    fn figures(_: &CondRecord) -> Result<Vec<Drawing>> {
        Ok(Vec::new())
    }

    fn report(r: &CondRecord) -> String {
        table(r)
    }
}
