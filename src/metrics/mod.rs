//! Metrics of a solve, computed only when asked for: exact cond₂ of K and of the final system
//! matrix, `log10|det|` of both and their difference (the paper's "ratio of main
//! determinants"), plus the precision warning.
//!
//! The final system matrix is `K + D E Dᵀ` for the penalty strategies and the saddle-point
//! matrix `[K D_A; D_Aᵀ 0]` for `lagrange`.

use crate::conditioning::{self, sparse::RitzStarts, CondReport, Reuse};
use crate::error::{Error, Result};
use crate::strategy::{lagrange, penalized_matrix, Solution, SystemKind};
use crate::system::{Problem, Stiffness};
use serde::Serialize;

pub mod solver;

/// Which metrics to compute.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MetricSet {
    /// Exact cond₂ of K and of the system matrix.
    pub cond: bool,
    /// log10|det| of K and of the system matrix, and their ratio.
    pub det: bool,
    /// Relative accuracy asked of the cond₂ values (`--cond-tol`; `None`: the contract,
    /// `max(1e-12, 4·ε_mach·cond₂)`). A looser tolerance stops the Lanczos runs earlier; the
    /// bounds are proven either way.
    pub cond_tol: Option<f64>,
}

impl MetricSet {
    /// Checks a relative accuracy asked of cond₂: finite, in (0, 1).
    pub fn check_cond_tol(tol: Option<f64>) -> Result<()> {
        tol.map_or(Ok(()), |t| {
            Error::fraction("relative cond₂ accuracy", t).map(|_| ())
        })
    }

    /// Everything.
    pub const ALL: MetricSet = MetricSet {
        cond: true,
        det: true,
        cond_tol: None,
    };
}

/// Computed metrics (`None` = not requested).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Metrics {
    /// cond₂(K).
    pub cond2_k: Option<CondReport>,
    /// cond₂ of the final system matrix.
    pub cond2_system: Option<CondReport>,
    /// log10|det K| (−∞ if singular).
    pub log10_det_k: Option<f64>,
    /// log10|det| of the final system matrix.
    pub log10_det_system: Option<f64>,
    /// `log10|det(system)| − log10|det K|`.
    pub log10_det_ratio: Option<f64>,
    /// Requested metrics that have no exact route for this matrix (e.g. cond₂ of a sparse
    /// indefinite saddle-point matrix above the densify limit), with the reason.
    pub unavailable: Vec<String>,
    /// Wall time of the cond₂ analyses (s; not serialized).
    #[serde(skip)]
    pub seconds_cond: f64,
    /// Wall time of the determinants (s; near zero where the cond₂ route's factorization gave
    /// them; not serialized).
    #[serde(skip)]
    pub seconds_det: f64,
}

/// cond₂ of the system matrix, or `None` with a note when no exact route exists for it.
/// `starts`: K's Ritz vectors; `free_bottom`: K_ℱℱ's bottom Ritz vector at the exact contact
/// set ([`contact_bottom`]), where known.
fn system_cond(
    problem: &Problem,
    sol: &Solution,
    sys: &Stiffness,
    starts: Option<&RitzStarts>,
    free_bottom: Option<&[f64]>,
    tol: Option<f64>,
    unavailable: &mut Vec<String>,
) -> Result<Option<CondReport>> {
    let penalty = starts.and_then(|s| penalty_starts(problem, sol, sys, s, free_bottom));
    let reuse = Reuse {
        starts: penalty.as_ref().or(starts),
        factor: sol.factor.as_deref(),
        tol,
        // The solution's own matrix is attached only where it is symmetric bit for bit.
        exactly_symmetric: sol.matrix.as_deref().is_some_and(|m| std::ptr::eq(m, sys)),
        ..Reuse::default()
    };
    cond_of_system(problem, &sol.system, sys, reuse, unavailable)
}

/// The starts of a penalized system's cond₂ ([`conditioning::starts`]), K's Ritz vectors
/// where nothing better is at hand: the top one replaced by
/// [`conditioning::starts::penalty_top_start`] where the constraints are single-DOF and every
/// active penalty exceeds K's diagonal entry at its DOF (the regime where A's top eigenvector
/// leaves K's for the active block) and the padded vector is the better start; the bottom
/// one by `free_bottom` (K_ℱℱ's at the exact contact set) where its Rayleigh quotient on A is
/// the smaller ([`conditioning::starts::penalty_bottom_start`]). None where neither is
/// replaced or the system is not penalized. A function of the problem, the solution, K's
/// vectors and `free_bottom` alone: `solve` and a sweep row start alike.
fn penalty_starts(
    problem: &Problem,
    sol: &Solution,
    sys: &Stiffness,
    k_starts: &RitzStarts,
    free_bottom: Option<&[f64]>,
) -> Option<RitzStarts> {
    if !matches!(sol.system, SystemKind::Penalized) {
        return None;
    }
    let active = dominant_active_dofs(problem, sol);
    if active.is_none() && free_bottom.is_none() {
        return None;
    }
    let a = sys.as_sparse();
    let top = active
        .and_then(|active| conditioning::starts::penalty_top_start(&a, &k_starts.top, &active));
    let bottom = free_bottom
        .and_then(|f| conditioning::starts::penalty_bottom_start(&a, &k_starts.bottom, f));
    if top.is_none() && bottom.is_none() {
        return None;
    }
    Some(RitzStarts {
        top: top.unwrap_or_else(|| k_starts.top.clone()),
        bottom: bottom.unwrap_or_else(|| k_starts.bottom.clone()),
    })
}

/// The sorted, distinct DOFs of the active constraints of a penalized solution where every
/// constraint with a penalty is single-DOF and its penalty exceeds K's diagonal entry at its
/// DOF; None otherwise.
fn dominant_active_dofs(problem: &Problem, sol: &Solution) -> Option<Vec<usize>> {
    let mut active = Vec::new();
    for (c, &e) in sol.penalties.iter().enumerate() {
        if e > 0.0 {
            let d = problem.constraints.get(c)?.single_dof()?;
            if e <= problem.k.diag(d) {
                return None;
            }
            active.push(d);
        }
    }
    active.sort_unstable();
    active.dedup();
    Some(active)
}

/// K_ℱℱ's bottom Ritz vector at a contact set (`contact[c]`: constraint c in contact, the
/// exact solution's set from `lagrange`), padded with zeros on the contact DOFs ℬ
/// ([`conditioning::starts::free_block_bottom`], started from K's bottom Ritz vector): the
/// bottom start of every penalized row of the scene where it is the better one. None where
/// a constraint in contact couples DOFs, no constraint or every DOF is in contact, K_ℱℱ is
/// not positive definite, or the run fails. A sweep computes it once per scene after its
/// lagrange row; `solve --exact-start` the same way.
pub fn contact_bottom(
    problem: &Problem,
    contact: &[bool],
    k_starts: &RitzStarts,
) -> Option<Vec<f64>> {
    let mut dofs = contact
        .iter()
        .enumerate()
        .filter(|&(_, &on)| on)
        .map(|(c, _)| problem.constraints.get(c)?.single_dof())
        .collect::<Option<Vec<usize>>>()?;
    dofs.sort_unstable();
    dofs.dedup();
    let k = problem.k.as_sparse();
    conditioning::starts::free_block_bottom(&k, &dofs, &k_starts.bottom)
}

/// cond₂ of `sys`, the system matrix of `kind` on `problem` (for a saddle point, `problem.k`
/// is its K block), or `None` with a note when no exact route exists for it. `factor`: a
/// factorization of `sys` itself, if one is at hand.
pub(crate) fn cond_of_system(
    problem: &Problem,
    kind: &SystemKind,
    sys: &Stiffness,
    reuse: Reuse<'_>,
    unavailable: &mut Vec<String>,
) -> Result<Option<CondReport>> {
    // A saddle point with symmetric K: the block-structure route, never densified (a dense K
    // in compressed columns), for a Boolean D and for rows that couple DOFs
    // (`cond2_saddle_rows`); where it does not apply, the generic route.
    let boolean_dofs = |active: &[usize]| -> Option<Vec<usize>> {
        active
            .iter()
            .map(|&c| problem.constraints[c].single_dof())
            .collect()
    };
    if let SystemKind::SaddlePoint { active } = kind {
        if crate::route::saddle_route(problem.k.is_symmetric()) {
            let k = problem.k.as_sparse();
            let schur = conditioning::saddle::SCHUR_TEST_MAX;
            let report = match boolean_dofs(active) {
                Some(dofs) => {
                    conditioning::saddle::cond2_saddle_warm(&k, &dofs, schur, reuse.starts)
                }
                // Rows that couple DOFs: the same route on the pattern of K + DDᵀ.
                None => {
                    let rows: Vec<conditioning::saddle::Row> = active
                        .iter()
                        .map(|&c| problem.constraints[c].terms.clone())
                        .collect();
                    conditioning::saddle::cond2_saddle_rows(&k, &rows, schur, reuse.starts)
                }
            };
            // Where it fails — not its structure (repeated DOFs, no active constraint,
            // dependent rows, sizes past its limits), K_FF / K + ρDDᵀ not positive definite,
            // or a numerical failure of its Lanczos runs — the generic route decides below
            // (dense up to its size limit), never a refusal of a valid matrix.
            if let Ok(r) = report {
                return Ok(Some(r));
            }
        }
    }
    match conditioning::cond2_warm(sys, reuse) {
        Ok((r, _)) => Ok(Some(r)),
        // No route for it (e.g. indefinite above the densify limit) or a route's numerical
        // failure: the metric is missing with its reason, the solve stands.
        Err(e) => {
            let msg = e.bare_message();
            unavailable.push(format!("cond2 of the system matrix not computed: {msg}"));
            Ok(None)
        }
    }
}

/// `log10|det A|` of the system matrix: read off the cond₂ route's own factorization when it
/// has one; for a saddle point `det K_FF` ([`conditioning::log10_abs_det_saddle`]); else from a
/// factorization of A.
fn log10_det(
    problem: &Problem,
    sol: &Solution,
    cond: Option<&CondReport>,
    a: &Stiffness,
) -> Result<f64> {
    let dofs = match &sol.system {
        SystemKind::SaddlePoint { active } if cond.and_then(|c| c.log10_det).is_none() => active
            .iter()
            .map(|&c| problem.constraints[c].single_dof())
            .collect::<Option<Vec<usize>>>(),
        _ => None,
    };
    match dofs {
        Some(dofs) => conditioning::log10_abs_det_saddle(&problem.k, &dofs),
        None => conditioning::log10_abs_det_after(a, cond),
    }
}

/// Threshold on `cond₂ · ε_mach` above which fewer than ~10 digits are reliable.
pub const DIGITS_LOST_THRESHOLD: f64 = 1e-6;

/// A JSON number where `x` is finite, else `null` (what a reader can parse for ±∞ or NaN).
pub fn finite_or_null(x: Option<f64>) -> serde_json::Value {
    match x {
        Some(v) if v.is_finite() => serde_json::json!(v),
        _ => serde_json::Value::Null,
    }
}

/// The final system matrix of a solution.
pub fn system_matrix(problem: &Problem, sol: &Solution) -> Stiffness {
    match &sol.system {
        SystemKind::Penalized => penalized_matrix(problem, &sol.penalties),
        SystemKind::SaddlePoint { active } => lagrange::saddle_matrix(problem, active),
    }
}

/// [`system_matrix`], borrowed where the solve kept the matrix it factored
/// ([`Solution::matrix`], the same entries bit for bit).
fn system_matrix_of<'a>(problem: &Problem, sol: &'a Solution) -> std::borrow::Cow<'a, Stiffness> {
    match (&sol.system, &sol.matrix) {
        (SystemKind::Penalized, Some(a)) => std::borrow::Cow::Borrowed(a),
        _ => std::borrow::Cow::Owned(system_matrix(problem, sol)),
    }
}

/// Computes the requested metrics.
pub fn compute(problem: &Problem, sol: &Solution, set: MetricSet) -> Result<Metrics> {
    compute_at_contact_set(problem, sol, set, None)
}

/// [`compute`] where the exact contact set is known (`contact[c]`: constraint c in contact,
/// from a lagrange solve of the same problem, as `solve --exact-start` and every sweep row
/// have it): a penalized system's bottom Lanczos run may then start from K_ℱℱ's bottom Ritz
/// vector at that set ([`contact_bottom`]), as a sweep's rows do — the same rows bit for bit.
pub fn compute_at_contact_set(
    problem: &Problem,
    sol: &Solution,
    set: MetricSet,
    contact: Option<&[bool]>,
) -> Result<Metrics> {
    let mut out = Metrics::default();
    if !(set.cond || set.det) {
        return Ok(out);
    }
    let sys = system_matrix_of(problem, sol);
    if set.cond {
        // Where K's Ritz vectors are kept (n ≤ RITZ_VECTOR_MAX_N) the system's cond₂ starts
        // from them, after K's, exactly as a sweep does (`compute_with_k`): the same rows bit
        // for bit, given the exact contact set for a penalized system (a sweep's rows have
        // it: `contact_bottom`; without it the bottom run starts from K's vector). Above, the
        // two analyses one after the other, the system's from the generic start: K's and a penalized system's each run their two ends side by side where a
        // second factor fits the memory (`conditioning::sparse::SIDE_BY_SIDE_ENDS_MIN_N`),
        // which uses the two threads a side-by-side pair of analyses would, at the memory of
        // one (10⁶ membrane: docs/performance.md); a saddle point's analysis (lagrange) runs
        // on one thread, after K's. Each end is sequential inside: the same results for any
        // number of threads. Where K's analysis fails (a singular K above the densify limit,
        // a floating body held only by its rows), cond₂(K) is missing with its reason in
        // `unavailable` and the system's analysis runs from the generic start: a metric of K
        // never ends a solve.
        let mut unavailable = Vec::new();
        let tol = set.cond_tol;
        let (k, system) = match k_analysis(&problem.k, tol) {
            Ok((k, ritz)) => {
                let starts = ritz.as_ref();
                let free = contact
                    .zip(starts)
                    .filter(|_| matches!(sol.system, SystemKind::Penalized))
                    .and_then(|(c, r)| contact_bottom(problem, c, r));
                let system = system_cond(
                    problem,
                    sol,
                    &sys,
                    starts,
                    free.as_deref(),
                    tol,
                    &mut unavailable,
                );
                (Some(k), system)
            }
            Err(e) => {
                unavailable.push(format!("cond2 of K not computed: {}", e.bare_message()));
                let system = system_cond(problem, sol, &sys, None, None, tol, &mut unavailable);
                (None, system)
            }
        };
        out.cond2_k = k;
        out.cond2_system = system?;
        out.unavailable = unavailable;
    }
    if set.det {
        // As cond₂(K): a determinant that cannot be formed is missing with its reason.
        let dk = conditioning::log10_abs_det_after(&problem.k, out.cond2_k.as_ref());
        let ds = log10_det(problem, sol, out.cond2_system.as_ref(), &sys);
        let mut missing = |what: &str, e: Error| {
            out.unavailable
                .push(format!("{what} not computed: {}", e.bare_message()));
            None
        };
        let dk = dk.map_or_else(|e| missing("log10|det K|", e), Some);
        let ds = ds.map_or_else(|e| missing("log10|det| of the system matrix", e), Some);
        out.log10_det_k = dk;
        out.log10_det_system = ds;
        out.log10_det_ratio = dk.zip(ds).map(|(k, s)| s - k);
    }
    Ok(out)
}

/// K's cond₂ as [`compute`] takes it, to relative accuracy `tol` (`None`: the accuracy
/// contract), with its Ritz vectors where they are kept (n ≤
/// [`conditioning::sparse::RITZ_VECTOR_MAX_N`]): the starts of the system's analysis in
/// [`compute_with_k`]. A caller that analyses K once for many solves (`solver_cost`'s levels)
/// calls this, so its rows are [`compute`]'s bit for bit.
pub fn k_analysis(k: &Stiffness, tol: Option<f64>) -> Result<(CondReport, Option<RitzStarts>)> {
    let reuse = Reuse {
        tol,
        keep_ritz: k.n() <= conditioning::sparse::RITZ_VECTOR_MAX_N,
        ..Reuse::default()
    };
    conditioning::cond2_warm(k, reuse)
}

/// Like [`compute`], but only the system matrix is analysed: `cond2_k` is left `None` and
/// `log10|det K|` is taken from `log10_det_k` when given (a sweep computes K's metrics once per
/// scene). `starts`: K's Ritz vectors ([`conditioning::cond2_warm`]), from which the system's
/// cond₂ starts its Lanczos runs (penalty systems `K + D E Dᵀ` only, the top run from the
/// active block's vector where the penalties dominate K's diagonal, `penalty_starts`: fewer
/// steps, the value inside the same certified bracket), the bottom run from `free_bottom`
/// (K_ℱℱ's bottom Ritz vector at the exact contact set, [`contact_bottom`]) where it is the
/// better start.
pub fn compute_with_k(
    problem: &Problem,
    sol: &Solution,
    set: MetricSet,
    log10_det_k: Option<f64>,
    starts: Option<&RitzStarts>,
    free_bottom: Option<&[f64]>,
) -> Result<Metrics> {
    let mut out = Metrics::default();
    if !(set.cond || set.det) {
        return Ok(out);
    }
    let sys = system_matrix_of(problem, sol);
    if set.cond {
        let t = std::time::Instant::now();
        out.cond2_system = system_cond(
            problem,
            sol,
            &sys,
            starts,
            free_bottom,
            set.cond_tol,
            &mut out.unavailable,
        )?;
        out.seconds_cond = t.elapsed().as_secs_f64();
    }
    if set.det {
        let t = std::time::Instant::now();
        let dk = match log10_det_k {
            Some(v) => v,
            None => conditioning::log10_abs_det(&problem.k)?,
        };
        let ds = log10_det(problem, sol, out.cond2_system.as_ref(), &sys)?;
        out.log10_det_k = Some(dk);
        out.log10_det_system = Some(ds);
        out.log10_det_ratio = Some(ds - dk);
        out.seconds_det = t.elapsed().as_secs_f64();
    }
    Ok(out)
}

/// A solution's warnings followed by [`precision_warnings`], without saying twice that K is
/// not positive definite (the strategy and cond₂(K) may both find it).
pub fn warnings(sol: &Solution, m: &Metrics) -> Vec<String> {
    let mut w = sol.warnings.clone();
    let said = |w: &[String]| {
        w.iter()
            .any(|x| x.starts_with(crate::strategy::NOT_SPD_WARNING))
    };
    for x in precision_warnings(m) {
        if !(x.starts_with(crate::strategy::NOT_SPD_WARNING) && said(&w)) {
            w.push(x);
        }
    }
    w
}

/// Warnings derived from metrics: digits lost when `cond₂(system) · ε_mach > 1e-6`, a cond₂
/// whose bracket is not proven (route and bracket named), a K that may be singular, and the
/// metrics that could not be computed.
pub fn precision_warnings(m: &Metrics) -> Vec<String> {
    let mut w = m.unavailable.clone();
    if let Some(k) = m.cond2_k {
        // A symmetric K whose certified (Cholesky-based) route failed went to the eigenvalues.
        if matches!(
            k.route,
            conditioning::CondRoute::SymmetricEigen
                | conditioning::CondRoute::DensifiedSymmetricEigen
        ) {
            w.push(format!(
                "{} (cond₂(K) found it indefinite: σ_min = {:e})",
                crate::strategy::NOT_SPD_WARNING,
                k.sigma_min
            ));
        }
    }
    // A bracket that is not proven: the value is an estimate, whatever its width says.
    for (name, r) in [("K", m.cond2_k), ("the system matrix", m.cond2_system)] {
        w.extend(r.and_then(|r| r.unproven_caveat(name)));
    }
    w.extend(m.cond2_k.and_then(|k| k.singular_caveat("K")));
    if let Some(c) = m.cond2_system {
        if c.cond2 * f64::EPSILON > DIGITS_LOST_THRESHOLD {
            w.push(format!(
                "cond2 of the system matrix is {:.3e}: cond·ε_mach = {:.1e} > {DIGITS_LOST_THRESHOLD:e}, \
                 fewer than ~10 significant digits of u are reliable",
                c.cond2,
                c.cond2 * f64::EPSILON
            ));
        }
    }
    w
}

/// Relative error `‖u − u_ref‖₂ / ‖u_ref‖₂` (absolute if u_ref = 0).
pub fn relative_error(u: &[f64], u_ref: &[f64]) -> f64 {
    let num: f64 = u
        .iter()
        .zip(u_ref)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let den: f64 = u_ref.iter().map(|b| b * b).sum::<f64>().sqrt();
    if den > 0.0 {
        num / den
    } else {
        num
    }
}
