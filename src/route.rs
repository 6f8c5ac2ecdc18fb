//! The one route policy of the numerics: from a matrix's [`Structure`] (and whether it is
//! symmetric), where it is stored, which factorization and which cond₂ route it takes, and
//! which solve route the contact strategies use. Every caller asks here — storage
//! (`system::Stiffness::in_preferred_storage`), cond₂ (`conditioning::cond2_warm` and the
//! saddle-point route in `metrics`), the strategies' elimination route
//! (`strategy::eliminated::applies`) — so one threshold moves them together.
//!
//! When to use: whenever code must choose dense or sparse. The thresholds are measured
//! (`cond_cost`, docs/performance.md), not guessed.

use serde::{Deserialize, Serialize};

/// Below this dimension matrices stay dense: a dense factorization is cheaper than the sparse
/// machinery for small n. The crossover of the cond₂ routes, measured with `cond_cost` on the
/// membrane and beam families, lies at n ≈ 24–36 (docs/performance.md); the threshold also
/// chooses the storage and the strategies' solve route ([`ELIMINATION_MIN_N`]).
pub const SPARSE_ROUTE_MIN_N: usize = 32;

/// Largest dimension for which a sparse matrix is densified (storage, or an exact dense cond₂).
pub const DENSIFY_LIMIT: usize = 6000;

/// Smallest n for which `condensed`/`lagrange` use the elimination route on sparse K: the
/// size from which K is stored sparse at all. On the sweep's 20-file folder it takes about a
/// quarter of the time of the dense S = DᵀK⁻¹D route (m solves and an m×m box QP) and of the
/// saddle-point LU it replaced below 2 000 unknowns, with the same rows to rounding
/// (docs/history/performance-log.md).
pub const ELIMINATION_MIN_N: usize = SPARSE_ROUTE_MIN_N;

/// The cond₂ route [`Structure::cond_plan`] chooses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CondPlan {
    /// Lanczos + certificate on the sparse pattern (`conditioning::sparse`).
    SparseSpd,
    /// A dense route (certified SPD on the full pattern, eigen or SVD).
    Dense,
}

/// The saddle-point system `[K D; Dᵀ 0]` takes the block-structure cond₂ route
/// (`conditioning::saddle`, never densified) wherever K is symmetric, whatever its size and
/// storage (a dense K is handed to it in compressed columns): its σ_min comes from Temple's
/// bounds, second order, where a dense eigensolver's Kahan bounds are first order in
/// ε_mach·cond₂ (the default sweep's 13 dense `lagrange` systems: 1e-9–9e-3 wide before,
/// ≤ 6e-12 with it). Small systems cost microseconds either way.
pub fn saddle_route(k_symmetric: bool) -> bool {
    k_symmetric
}

/// The strategies' elimination route (`strategy::eliminated`) for K of n unknowns: K sparse
/// and n ≥ [`ELIMINATION_MIN_N`] (the constraint DOFs must be distinct too, which the caller
/// checks).
pub fn elimination_route(n: usize, k_sparse: bool) -> bool {
    k_sparse && n >= ELIMINATION_MIN_N
}

/// What a matrix is, whatever its storage (`system::Stiffness::structure`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Structure {
    /// Dimension N.
    pub n: usize,
    /// Nonzero entries (both triangles).
    pub nnz: usize,
    /// `max |i − j|` over the nonzero entries, natural ordering.
    pub half_bandwidth: usize,
}

/// Largest fraction of nonzero entries, nnz / N², for which a matrix is stored sparse.
///
/// On this project's families (`cond_cost`, docs/performance.md) the sparse routes (sparse
/// Cholesky with AMD ordering; Lanczos + certificate for cond₂) beat the dense ones from
/// N ≈ 25–36 for the 5-point membrane (5/N nonzeros) and the frame beam (≈ 9/N, half-
/// bandwidth 5), i.e. at densities up to ≈ 0.25–0.35; a banded matrix is a sparse one here,
/// since the AMD ordering keeps a band's fill inside the band.
pub const SPARSE_MAX_DENSITY: f64 = 0.25;

impl Structure {
    /// An N×N matrix with no entry counted yet ([`Structure::count`] adds them).
    pub(crate) fn empty(n: usize) -> Self {
        Structure {
            n,
            nnz: 0,
            half_bandwidth: 0,
        }
    }

    /// Counts entry (i, j) = v: exact zeros (±0.0), stored or not, do not count.
    pub(crate) fn count(&mut self, i: usize, j: usize, v: f64) {
        if v != 0.0 {
            self.nnz += 1;
            self.half_bandwidth = self.half_bandwidth.max(i.abs_diff(j));
        }
    }

    /// nnz / N².
    pub fn density(&self) -> f64 {
        self.nnz as f64 / (self.n as f64 * self.n as f64)
    }

    /// Storage, and with it the solve and cond₂ routes: sparse pays where N ≥
    /// [`SPARSE_ROUTE_MIN_N`] and density ≤ [`SPARSE_MAX_DENSITY`].
    pub fn prefers_sparse(&self) -> bool {
        self.n >= SPARSE_ROUTE_MIN_N && self.density() <= SPARSE_MAX_DENSITY
    }

    /// A matrix stored sparse may be densified (storage conversion, a dense cond₂ route):
    /// N ≤ [`DENSIFY_LIMIT`].
    pub fn densify_allowed(&self) -> bool {
        self.n <= DENSIFY_LIMIT
    }

    /// The cond₂ route of a matrix of this structure: the certified sparse SPD route
    /// where it is symmetric and [`Structure::prefers_sparse`] (a matrix that turns out not
    /// positive definite then falls back to [`CondPlan::Dense`]); else a dense route, which a
    /// sparse-stored matrix takes densified only up to [`DENSIFY_LIMIT`].
    pub fn cond_plan(&self, symmetric: bool) -> CondPlan {
        if symmetric && self.prefers_sparse() {
            CondPlan::SparseSpd
        } else {
            CondPlan::Dense
        }
    }
}
