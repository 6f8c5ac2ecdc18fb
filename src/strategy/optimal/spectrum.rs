//! What one evaluation of the optimiser needs of `A = K + Σ_j ε_j d_j d_jᵀ` (d_j the penalized
//! constraint rows; `e_{d_j}` for single-DOF rows): the eigenpairs that enter the smoothed
//! ln cond₂ (their values and `d_jᵀv` of their vectors) and solves with A, by one of two
//! routes ([`Route`]).
//!
//! * **Dense**: one symmetric eigendecomposition of the n×n A (faer); every eigenpair enters
//!   both ends of the smoothing, solves are `V Λ⁻¹ Vᵀ b`. Exact to rounding, ≈ 9n³ flops.
//! * **Sparse**: a numeric sparse Cholesky of A on the pattern of `K + DDᵀ` (K's own where the
//!   rows are single-DOF; symbolic analysis once, each row's entries located once), the
//!   [`WINDOW`] largest eigenpairs of A and the [`WINDOW`] largest of A⁻¹ (the smallest of A,
//!   shift-invert at 0 through the factor) by Lanczos
//!   ([`conditioning::window`](crate::conditioning::window)), each started from the window
//!   of the previous evaluation, Ritz residuals ≤ [`RESIDUAL`] relative to the end's
//!   eigenvalue; solves through the factor. The smoothing runs over these windows only,
//!   which keeps it an upper bound of ln cond₂ to the Ritz values' accuracy (module docs of
//!   [`super`]). A window not converged within its step limit is used as it stands: it
//!   steers the optimiser only; the reported cond₂ is computed exactly afterwards.

use crate::conditioning::window::top_window;
use crate::error::{Error, Result};
use crate::linalg::{symmetric_matvec, DiagonalPattern, SparseLlt};
use crate::system::{Constraint, Problem};
use faer::{Mat, Side};
use std::cell::RefCell;

/// How an evaluation gets its spectrum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// Full dense eigendecomposition of A at every evaluation.
    Dense,
    /// Sparse Cholesky and the extreme eigenpairs only.
    Sparse,
}

impl Route {
    /// The route `optimal` takes for n DOFs: dense up to [`super::DENSE_MAX_N`], sparse above.
    pub fn for_size(n: usize) -> Route {
        if n <= super::DENSE_MAX_N {
            Route::Dense
        } else {
            Route::Sparse
        }
    }

    /// Name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Route::Dense => "dense",
            Route::Sparse => "sparse",
        }
    }
}

/// Eigenpairs kept at each end of the spectrum by the sparse route.
pub const WINDOW: usize = 8;
/// Ritz residual ‖A y − θ y‖ of the sparse route's windows, relative to the end's extreme
/// eigenvalue (λ_max for A, 1/λ_min for A⁻¹).
pub const RESIDUAL: f64 = 1e-8;
/// Lanczos steps per window at most.
const MAX_STEPS: usize = 300;
/// Smallest n of the sparse route (a window at each end, apart).
pub const SPARSE_MIN_N: usize = 4 * WINDOW;

/// One eigenpair: λ and `d_jᵀv` of its eigenvector v for the penalized rows (in set order).
pub(super) struct Pair {
    pub lambda: f64,
    pub at: Vec<f64>,
}

/// The spectrum of one A: `pairs[top]` enter the upper end of the smoothing, `pairs[bottom]`
/// the lower end (the dense route: all pairs in both).
pub(super) struct Linearization {
    pub pairs: Vec<Pair>,
    pub top: std::ops::Range<usize>,
    pub bottom: std::ops::Range<usize>,
    solver: Solver,
}

enum Solver {
    Dense { v: Mat<f64>, lam: Vec<f64> },
    Sparse(SparseLlt),
}

impl Linearization {
    /// `A⁻¹ b`.
    pub(super) fn solve(&self, mut b: Vec<f64>) -> Vec<f64> {
        match &self.solver {
            Solver::Dense { v, lam } => {
                let n = b.len();
                let y: Vec<f64> = (0..n)
                    .map(|k| (0..n).map(|i| v[(i, k)] * b[i]).sum::<f64>() / lam[k])
                    .collect();
                (0..n)
                    .map(|i| (0..n).map(|k| v[(i, k)] * y[k]).sum())
                    .collect()
            }
            Solver::Sparse(l) => {
                l.solve_vec_in_place(&mut b);
                b
            }
        }
    }
}

/// K in the form a route works on.
pub(super) enum Spectrum {
    Dense(Mat<f64>),
    Sparse {
        pattern: DiagonalPattern,
        /// Per constraint row: the positions of its outer product `d dᵀ` in the pattern's
        /// values, with the products `a_i a_j`.
        outer: Vec<Vec<(usize, f64)>>,
        /// The last evaluation's windows (top of A, top of A⁻¹): where the next Lanczos
        /// runs start (the evaluation sequence is deterministic, so are the starts).
        warm: RefCell<[Vec<Vec<f64>>; 2]>,
    },
}

impl Spectrum {
    /// K of `p` prepared for `route` (the sparse route needs n ≥ [`SPARSE_MIN_N`]).
    pub(super) fn new(p: &Problem, route: Route) -> Result<Spectrum> {
        Ok(match route {
            Route::Dense => Spectrum::Dense(p.k.to_dense()),
            Route::Sparse => {
                let n = p.n();
                if n < SPARSE_MIN_N {
                    return Err(Error::unsupported(
                        "optimal: the sparse route",
                        format!("n ≥ {SPARSE_MIN_N} (got {n})"),
                    ));
                }
                // K widened by explicit zeros to the rows' fill (K itself for single DOFs).
                let zeros: Vec<(usize, usize, f64)> =
                    p.constraints.iter().flat_map(|c| c.outer(0.0)).collect();
                let k = crate::system::Stiffness::Sparse(p.k.to_sparse());
                let pattern = DiagonalPattern::new(&k.with_entries_added(&zeros).to_sparse())?;
                let outer = p
                    .constraints
                    .iter()
                    .map(|c| outer_positions(&pattern, c))
                    .collect::<Result<_>>()?;
                Spectrum::Sparse {
                    pattern,
                    outer,
                    warm: RefCell::new([Vec::new(), Vec::new()]),
                }
            }
        })
    }

    /// The spectrum of `A = K + Σ_j eps[j] d_c d_cᵀ` over the constraints `c = set[j]` of
    /// `p`; None if A is not positive definite or a penalty is not finite.
    pub(super) fn linearize(
        &self,
        p: &Problem,
        set: &[usize],
        eps: &[f64],
    ) -> Result<Option<Linearization>> {
        let rows: Vec<&Constraint> = set.iter().map(|&c| &p.constraints[c]).collect();
        if !eps.iter().all(|e| e.is_finite()) {
            return Ok(None);
        }
        match self {
            Spectrum::Dense(k) => {
                let mut a = k.clone();
                for (row, &e) in rows.iter().zip(eps) {
                    for (i, j, v) in row.outer(e) {
                        a[(i, j)] += v;
                    }
                }
                let evd = a
                    .self_adjoint_eigen(Side::Lower)
                    .map_err(|e| Error::Numerical(format!("symmetric eigen failed: {e:?}")))?;
                let (v, s) = (evd.U(), evd.S().column_vector());
                let n = a.nrows();
                let lam: Vec<f64> = (0..n).map(|k| s[k]).collect();
                if !lam.iter().all(|l| l.is_finite() && *l > 0.0) {
                    return Ok(None);
                }
                let pairs = (0..n)
                    .map(|k| Pair {
                        lambda: lam[k],
                        at: rows.iter().map(|r| r.apply(|d| v[(d, k)])).collect(),
                    })
                    .collect();
                Ok(Some(Linearization {
                    pairs,
                    top: 0..n,
                    bottom: 0..n,
                    solver: Solver::Dense {
                        v: v.to_owned(),
                        lam,
                    },
                }))
            }
            Spectrum::Sparse {
                pattern,
                outer,
                warm,
            } => {
                let mut values = pattern.values.clone();
                for (&c, &e) in set.iter().zip(eps) {
                    for &(pos, ab) in &outer[c] {
                        values[pos] += e * ab;
                    }
                }
                let Some(llt) = pattern.factor(&values) else {
                    return Ok(None);
                };
                let n = pattern.n();
                let mut warm = warm.borrow_mut();
                let mut times_a =
                    |x: &[f64], y: &mut [f64]| symmetric_matvec(pattern.pat(), &values, x, y);
                let Some(top) = top_window(&mut times_a, n, WINDOW, &warm[0], RESIDUAL, MAX_STEPS)
                else {
                    return Ok(None);
                };
                let mut solve = |x: &[f64], y: &mut [f64]| {
                    y.copy_from_slice(x);
                    llt.solve_vec_in_place(y);
                };
                let Some(bottom) = top_window(&mut solve, n, WINDOW, &warm[1], RESIDUAL, MAX_STEPS)
                else {
                    return Ok(None);
                };
                let at = |v: &Vec<f64>| rows.iter().map(|r| r.value(v)).collect::<Vec<f64>>();
                let mut pairs: Vec<Pair> = top
                    .values
                    .iter()
                    .zip(&top.vectors)
                    .map(|(&lambda, v)| Pair { lambda, at: at(v) })
                    .collect();
                let t = pairs.len();
                pairs.extend(
                    bottom
                        .values
                        .iter()
                        .zip(&bottom.vectors)
                        .map(|(&mu, v)| Pair {
                            lambda: 1.0 / mu,
                            at: at(v),
                        }),
                );
                *warm = [top.vectors, bottom.vectors];
                if !pairs.iter().all(|p| p.lambda.is_finite() && p.lambda > 0.0) {
                    return Ok(None);
                }
                let n = pairs.len();
                Ok(Some(Linearization {
                    pairs,
                    top: 0..t,
                    bottom: t..n,
                    solver: Solver::Sparse(llt),
                }))
            }
        }
    }
}

/// The positions of `d dᵀ`'s entries in `pattern`'s values (columns hold sorted row indices),
/// with the products `a_i a_j`.
fn outer_positions(pattern: &DiagonalPattern, row: &Constraint) -> Result<Vec<(usize, f64)>> {
    row.outer(1.0)
        .map(|(i, j, ab)| {
            crate::system::csc_position(pattern.pat(), i, j)
                .map(|p| (p, ab))
                .ok_or_else(|| Error::Numerical(format!("optimal: entry ({i}, {j}) of a row's outer product is not in the widened pattern")))
        })
        .collect()
}
