//! Exact, certified cond₂ of a sparse saddle-point matrix without forming or densifying it.
//!
//! `A = [K D; Dᵀ 0]` with K sparse SPD (N×N) and D Boolean with distinct DOFs B (N×m, one
//! column `e_d` per active constraint). A is symmetric indefinite with N positive and m
//! negative eigenvalues, and `σ = |λ|`:
//!
//! `σ_max = max(λ_max, −λ_min)`,  `σ_min = min(λ⁺_min, −λ⁻_max)`
//!
//! (λ⁺_min the smallest positive, λ⁻_max the negative eigenvalue closest to 0).
//!
//! **Inertia through the block structure.** For σ ≠ 0, eliminating the multiplier block
//! (−σI_m, diagonal) is a congruence: `A − σI ≅ (−σI_m) ⊕ H(σ)`,
//!
//! `H(σ) = K − σI + σ⁻¹ Σ_{d∈B} e_d e_dᵀ`  (K's pattern, only the diagonal changes),
//!
//! so by Sylvester `#{λ < σ} = m·[σ > 0] + #neg(H(σ))`. Three ends are certified by sparse
//! Cholesky tests (success ⇔ positive definite), as in the SPD route ([`super::sparse`]):
//!
//! * `λ_max < σ` ⇔ `−H(σ) ≻ 0` (σ > 0);
//! * `λ⁺_min > σ` ⇔ `H(σ) ≻ 0` (σ > 0);
//! * `λ_min > −s` ⇔ `H(−s) = K + sI − s⁻¹1_B ≻ 0` (s > 0).
//!
//! The fourth is not a definiteness test of H: for s > 0 there is no eigenvalue in (−s, 0)
//! iff `λ_min(M(s)) ≥ s` with `M(s) = Dᵀ(K + sI)⁻¹D` (m×m; from the congruence eliminating
//! K + sI instead). It is tested with m solves with the Cholesky factor of K + sI and a dense
//! Cholesky of `M(s) − sI` when `m ≤` [`SCHUR_TEST_MAX`]; where −λ⁻_max is estimated above
//! λ⁺_min's bracket, one such test at the bracket's top settles `σ_min = λ⁺_min`. Without
//! any solve, `H_BB ≺ 0` when
//! `s·(g_B + s) < 1` (g_B the Gershgorin bound of K_BB), and then the F-Schur complement is
//! SPD, so `#neg H(−s) = m`: no eigenvalue in (−s, 0). That bound `s₀ ≤ −λ⁻_max` is enough
//! whenever λ⁺_min's bracket lies below it (σ_min = λ⁺_min; e.g. the membranes). Otherwise,
//! for `m >` [`SCHUR_TEST_MAX`], the bracket of σ_min keeps only certified ends,
//! `[min(λ⁺_lo, s₀), λ⁺_hi]`, with the Lanczos estimate inside it as the value: the
//! certificate's width says how far it is from proven.
//!
//! **Estimates** by Lanczos: plain on A and −A for λ_max and λ_min, and on `A⁻¹` and `−A⁻¹`
//! for λ⁺_min and λ⁻_max, each stopped at 1/64 of the bracket width it will be certified to
//! (as in the SPD route). λ_max is the top of A's spectrum, so the Rayleigh quotient of its
//! Ritz vector (stored Lanczos vectors, up to [`super::sparse::RITZ_VECTOR_MAX_N`] unknowns, a second pass above) is one side of
//! its bracket and one inertia test the other. `A⁻¹` costs one solve with K_FF (K without the
//! rows and columns of B, factored once; `|det A| = det K_FF` comes with it): for
//! `A [x; y] = [f; g]`, `x_B = g`, `K_FF x_F = f_F − K_FB g`, `y = f_B − (K x)_B`.
//!
//! **Value and bounds.** The reported σ_max and σ_min are the converged Lanczos estimates
//! (stagnation 1e-14), clamped into the brackets. The brackets are proven as in
//! [`super::certify`]: σ_max ≥ |ρ(y_top)|, σ_max < s once `−H(s) ≻ 0` and `H(−s) ≻ 0` are
//! *verified* (a Cholesky test shifted down by its backward-error margin, so that success
//! proves definiteness of the exact matrix); σ_min ≤ ‖Ax̂‖/‖x̂‖ for x̂ = A⁻¹y, y a Ritz vector
//! of A⁻¹ (compensated residual, `certify::image_norm_upper`). σ_min from below, first by
//! Temple's inequality ([`super::temple`]'s Theorem 9, second order in the residual of x̂),
//! which holds for the eigenvalue of ±A closest to 0 on its positive side as for λ₁ of an SPD
//! matrix, given a gap μ from one LDLᵀ inertia test of `H(±τ)` with its backward error
//! bounded (Lemma 8 read for this congruence, `Shifts::side_gap`): `λ⁺_min ≥ lo⁺` and
//! `|λ⁻_max| ≥ lo⁻` leave no eigenvalue in (−lo⁻, lo⁺), so σ_min ≥ min(lo⁺, lo⁻)
//! (`SaddleRun::side_lower`; with s₀, or an inertia test of `H(−lo⁺)`, in place of lo⁻ where
//! the −A⁻¹ run was not needed). On the beams' graded saddle points this takes the bracket
//! from 1e-9–1e-6 to ≈ 1e-13. Where the negative side's bound misses the bracket width
//! wanted (clustered negative eigenvalues, as on the elasticity scenes, where no inertia test
//! isolates one), |λ⁻_max| is bracketed through the Schur complement of K onto B
//! ([`schur`]: the root of `s·λ_max(S_B(s)) = 1`, m×m dense eigenproblems with their rounding
//! bounded, a few units of rounding wide), and σ_min ≥ min(p, lo⁻) with p from Temple or a
//! verified `H(p) ≻ 0` placed above the negative side (`SaddleRun::schur_floor`); 0.48 → 9e-14
//! on the quad block. On a supernodal factor (no LDLᵀ) λ⁺_min's gap comes from a verified
//! Cholesky test of `H(τ)` with one free DOF pinned (Cauchy's interlacing,
//! `Shifts::pinned_gap`). σ_max's upper end comes from tests just above the estimate (or the
//! inertia search's upper end) judged by their factors' own margins (Lemmas 7a and 7,
//! `Shifts::tested_factor`; 7a read in place on supernodal factors), its lower end from a
//! compensated Rayleigh quotient where the plain one is wider than 2.5e-13, of a Ritz vector
//! refined by a shift-invert run with the passing test's factor where a cluster at the top
//! left it short (`SaddleRun::refine_top`). Where neither Temple nor the Schur complement
//! gives a bound (m or N·m above [`schur`]'s limits, no gap): σ_min ≥ s
//! once `H(s) ≻ 0` is verified, since then σ_min ≥ min(s, t) with t = s₀ or, where s lies
//! above s₀, t from an LDLᵀ inertia test of `H(−s)` with exactly m negative pivots
//! (`Shifts::no_eigenvalue_above`; a simplicial factor of K). Where that bracket would leave cond₂ uncertain by more than a
//! factor of 2 (the inertia test unavailable or inconclusive, or a margin m·cond₂ ≳ 1) the
//! inertia brackets of the search are reported instead, with `CondReport::bounds_proven =
//! false`; their target width is `max(1e-11, 64·ε_mach·cond₂)`.
//!
//! **Order.** Where K's factor is simplicial (it has an LDLᵀ), the proof is tried first from
//! the Lanczos estimates alone (σ_max = λ_max; the −A⁻¹ run only where λ⁺_min lies above s₀);
//! the inertia searches that give the unproven brackets run only where it fails or leaves
//! σ_max wider than the bracket width wanted (−λ_min above λ_max, clustered spectra), and
//! always on a supernodal factor. The λ_max and λ⁺_min runs start from K's Ritz
//! vectors where the caller has them ([`cond2_saddle_warm`]).
//!
//! **Coupled rows** ([`cond2_saddle_rows`]: `d_c = Σ_j a_cj e_j`, inclined planes,
//! node-to-segment, mortar). Every congruence above holds for any D of full column rank, with
//! `H(σ) = K − σI + σ⁻¹DDᵀ` on the pattern of `K + DDᵀ` (K widened with explicit zeros) and
//! every monotonicity step resting on `DDᵀ ⪰ 0`. The test matrices' rounding is no longer
//! diagonal: each entry of `β·DDᵀ` is bounded (`γ_{k+4}` of its terms) and the whole in 2-norm
//! by the largest row sum, which every margin above includes. `A⁻¹` goes through the
//! augmented block `K_ρ = K + ρDDᵀ` and the dense m×m `S = DᵀK_ρ⁻¹D` (`|det A| = det K_ρ ·
//! det S`; rows whose S spreads its Cholesky pivots by more than 1/(64ε_mach) are refused as
//! dependent). s₀ and the Schur complement onto B are written for a Boolean D; in their place
//! the negative side's floor is proven by **Lemma R**: for any X̂,
//! `Dᵀ(K + tI)⁻¹D ⪰ X̂ᵀD + RᵀX̂` with `R = D − (K + tI)X̂` (the solves' error enters through a
//! dropped term ⪰ 0), so a dense Cholesky of that m×m matrix minus tI, its rounding bounded,
//! puts m eigenvalues at or below −t' for a t' a few roundings below t; with the positive
//! side's `#{λ < s} ≤ m`, none lies in (−t', s). On the inclined plane,
//! the two-body patch test and Hertz between two bodies the brackets are proven (Hertz,
//! cond₂ ≈ 5e12: 2.5e-13 wide, where the dense route's value is off by 1.6e-4;
//! tests/verification/saddle_rows.rs).
//!
//! Cost: one Cholesky of K_FF, Lanczos products and solves (O(nnz) and O(nnz of the factor)
//! each), 3–4 shifted factorizations for the proof (2–4 more per end for the searches where
//! they run); memory O(nnz of the factor).
//! Use it for the `lagrange` system of any symmetric K (the metrics pick it automatically,
//! a dense K in compressed columns).

use super::certify::{self, Margin};
use super::sparse::{
    bracket, bracket_tol, bracket_top, lanczos, rayleigh_interval, Certificate, Keep, RitzStarts,
    MAX_LANCZOS_STEPS, STAGNATION,
};
use super::{CondReport, CondRoute};
use crate::error::{Error, Result};
use crate::linalg::{symmetric_matvec, DiagonalPattern};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

mod blocks;
mod coupling;
mod negative;
mod null_space;
pub mod schur;
mod shifts;
mod top;
mod warm;
use blocks::{constrained_mask, free_block_values, s0, saddle_csc, BlockInverse};
pub(crate) use blocks::{dof_error, dof_mask, free_block_factor};
use coupling::{AugmentedInverse, Blocks, Inverse};
pub use coupling::{Row, MAX_ROWS_ENTRIES};
use negative::schur_test_fails;
pub use null_space::{null_space_lambda_min, NullSpaceMin};
use shifts::Shifts;
use warm::{warm_start, SaddleStarts};

/// Largest m for which the fourth end (λ⁻_max) is certified by the m×m test `λ_min(M(s)) ≥ s`.
pub const SCHUR_TEST_MAX: usize = 1500;

/// cond₂ of `[K D; Dᵀ 0]` (D: columns `e_d` for `dofs`, distinct) for sparse SPD K (both
/// triangles stored), certified as in the module docs. Errors with [`Error::DofOutOfRange`] on
/// an out-of-range DOF, [`Error::Duplicate`] on a repeated one, [`Error::OutOfRange`] unless
/// 0 < m < N, and [`Error::Singular`] if K_FF is not positive definite (A singular).
pub fn cond2_saddle(k: &SparseColMat<usize, f64>, dofs: &[usize]) -> Result<CondReport> {
    cond2_saddle_with(k, dofs, SCHUR_TEST_MAX)
}

/// [`cond2_saddle`] with the limit on m for the m×m test of the fourth end given (0: never).
pub fn cond2_saddle_with(
    k: &SparseColMat<usize, f64>,
    dofs: &[usize],
    schur_test_max: usize,
) -> Result<CondReport> {
    cond2_saddle_warm(k, dofs, schur_test_max, None)
}

/// [`cond2_saddle_with`] whose Lanczos runs for λ_max (on A) and λ⁺_min (on A⁻¹) start from
/// K's Ritz vectors ([`RitzStarts`] of K, padded with zeros on the multipliers): D adds unit
/// entries only, so A's top eigenvector is close to K's; the run for λ⁻_max (on −A⁻¹) from
/// `[0; Dᵀv_top]` (`SaddleStarts::negative`). Fewer steps, the same certificate.
pub fn cond2_saddle_warm(
    k: &SparseColMat<usize, f64>,
    dofs: &[usize],
    schur_test_max: usize,
    starts: Option<&RitzStarts>,
) -> Result<CondReport> {
    let n = k.nrows();
    let in_b = constrained_mask(n, dofs)?;
    let pattern = DiagonalPattern::new(k)?;
    let blocks = Blocks::selection(dofs, in_b);
    let kff = free_block_factor(&pattern, &blocks.in_b)?;
    // |det A| = det K_FF (module `conditioning`, `log10_abs_det_saddle`): the B rows of the
    // stored factor are the identity.
    let log10_det = kff.log10_det();
    let inverse = Inverse::Free(BlockInverse {
        pattern: &pattern,
        dofs,
        in_b: &blocks.in_b,
        kff: &kff,
        kxb: vec![0.0; n],
    });
    let a = saddle_csc(&pattern, dofs);
    let floor = s0(k, &blocks.in_b);
    run_saddle(
        &pattern,
        &blocks,
        inverse,
        a,
        floor,
        log10_det,
        schur_test_max,
        starts,
    )
}

/// cond₂ of `[K D; Dᵀ 0]` for general constraint rows (row c = column c of D: its
/// `(DOF, coefficient)` terms) and sparse symmetric K (both triangles stored), certified as
/// in the module docs with the changes its *Coupled rows* lists: the shifted matrices on the
/// pattern of `K + DDᵀ`, A⁻¹ through `K + ρDDᵀ`, no analytic floor s₀ and no Schur
/// complement onto B. Errors with [`Error::DofOutOfRange`], [`Error::Duplicate`] (a DOF twice
/// in a row), [`Error::NotFinite`] (a zero or non-finite row), [`Error::OutOfRange`] unless
/// 0 < m < N or where N·m exceeds [`MAX_ROWS_ENTRIES`], and [`Error::Singular`] where
/// `K + ρDDᵀ` or `DᵀK_ρ⁻¹D` is not positive definite (A singular or K not positive
/// semidefinite). Single-DOF rows with coefficient 1 are better served by
/// [`cond2_saddle_warm`] (its analytic floor and Schur complement).
pub fn cond2_saddle_rows(
    k: &SparseColMat<usize, f64>,
    rows: &[Row],
    schur_test_max: usize,
    starts: Option<&RitzStarts>,
) -> Result<CondReport> {
    // K must be symmetric with both triangles stored (one triangle would be read as a
    // different matrix and "proven" about it).
    coupling::square_and_finite(k)?;
    if !crate::system::Stiffness::Sparse(k.clone()).is_symmetric() {
        return Err(Error::Unsupported {
            what: "saddle-point cond₂ with coupled rows: K".into(),
            needs: "a square symmetric K with both triangles stored".into(),
        });
    }
    let (pattern, blocks) = coupling::rows_on(k, rows)?;
    let augmented = AugmentedInverse::new(&pattern, &blocks)?;
    let log10_det = augmented.log10_det();
    let a = coupling::rows_csc(&pattern, &blocks);
    run_saddle(
        &pattern,
        &blocks,
        Inverse::Augmented(augmented),
        a,
        0.0,
        log10_det,
        schur_test_max,
        starts,
    )
}

/// The route of the module docs once D's blocks, A⁻¹, A in CSC (`a`), the floor s₀ and
/// `log10|det A|` are set up.
#[allow(clippy::too_many_arguments)]
fn run_saddle(
    pattern: &DiagonalPattern,
    blocks: &Blocks<'_>,
    inverse: Inverse<'_>,
    a: (SymbolicSparseColMat<usize>, Vec<f64>),
    s0: f64,
    log10_det: f64,
    schur_test_max: usize,
    starts: Option<&RitzStarts>,
) -> Result<CondReport> {
    let (n, m) = (pattern.n(), blocks.m);
    let (a_pattern, a_values) = a;
    let mut run = SaddleRun {
        shifts: Shifts {
            pattern,
            blocks,
            factorizations: 1,
            work: Vec::new(),
        },
        blocks,
        inverse,
        a_pattern,
        a_values,
        size: n + m,
        s0,
        lanczos_steps: 0,
        bottom_vectors: Vec::new(),
        positive: None,
        negative: None,
        negative_value: None,
        starts: starts.and_then(|s| SaddleStarts::of(s, blocks)),
    };
    // Each estimate is wanted only to 1/64 of the bracket width it will be certified to,
    // `bracket_tol(cond₂)` (as in the SPD route), with cond₂ bounded below by what is known
    // when the run starts: cond₂ ≥ λ_max / λ⁺_min ≥ max_i K_ii · θ for the top Ritz value θ
    // of A⁻¹ (K_ii = e_iᵀ A e_i ≤ λ_max), then by the estimates found so far.
    // λ⁺_min first: its estimate sets the bracket width of both ends (sparse::bracket_tol).
    let pos_min_est = 1.0 / usable("1/λ⁺_min", run.inverse_top(1.0)?)?;
    let top_est = run.top_estimate(pos_min_est)?;
    // The proof first, from the estimates alone (σ_max = λ_max; σ_min's negative side from
    // the −A⁻¹ run only where λ⁺_min lies above s₀): where it holds with σ_max pinned to the
    // bracket width wanted, the inertia searches below are not needed (on the benchmark
    // folder: every row, 5–7 factorizations and the Schur test fewer). Not tried on a
    // supernodal factor of K: without an LDLᵀ (Temple's bounds, the inertia test of H(−s))
    // it rarely proves σ_min, and at 10⁵–10⁶ DOFs its failed tests cost a fifth more.
    let first = if pattern.has_ldlt() {
        if pos_min_est >= run.s0 {
            usable("−1/λ⁻_max", run.inverse_top(-1.0)?)?;
        }
        let bottom_est = End {
            bracket: (0.0, f64::INFINITY),
            estimate: run
                .negative
                .map_or(pos_min_est, |(t, _)| pos_min_est.min(t)),
            tol: top_est.tol,
            top_rq: None,
        };
        run.proven(pattern, &top_est, &bottom_est)
            .filter(|p| p.0 .1 / p.0 .0 - 1.0 <= top_est.tol)
            .map(|p| (bottom_est, p))
    } else {
        None
    };
    let (top, bottom, proven) = match first {
        Some((bottom_est, p)) => (top_est, bottom_est, Some(p)),
        None => {
            let top = run.sigma_max(&top_est)?;
            let bottom = run.sigma_min(pos_min_est, &top, schur_test_max)?;
            let proven = run.proven(pattern, &top, &bottom);
            (top, bottom, proven)
        }
    };
    let (sigma_max, sigma_min) = proven.unwrap_or((top.bracket, bottom.bracket));
    let certificate = Certificate {
        lambda_max_lo: sigma_max.0,
        lambda_max_hi: sigma_max.1,
        lambda_min_lo: sigma_min.0,
        lambda_min_hi: sigma_min.1,
        lanczos_steps: run.lanczos_steps,
        factorizations: run.shifts.factorizations,
    };
    if !(sigma_max.0 > 0.0 && sigma_max.1.is_finite() && sigma_min.1.is_finite()) {
        return Err(Error::Numerical(format!(
            "saddle-point inertia brackets did not close: σ_max ∈ [{:e}, {:e}], σ_min ∈ [{:e}, {:e}]",
            sigma_max.0, sigma_max.1, sigma_min.0, sigma_min.1
        )));
    }
    // The converged estimates, clamped into the brackets.
    let smax = top
        .estimate
        .max(top.bracket.0)
        .clamp(sigma_max.0, sigma_max.1);
    // |λ⁻_max| from the Schur complement where it ran: converged to rounding where the −A⁻¹
    // run stops short in a cluster.
    let estimate = match run.negative_value {
        Some(v) => run.positive.map_or(v, |(p, _)| p.min(v)),
        None => bottom.estimate,
    };
    let smin = estimate.clamp(sigma_min.0, sigma_min.1);
    Ok(CondReport::with_certificate(
        smax,
        smin,
        CondRoute::SparseSaddleInertia,
        certificate,
        proven.is_some(),
        Some(log10_det),
    ))
}

/// A Lanczos estimate, or an error naming it where it is not a positive finite number.
fn usable(what: &str, v: f64) -> Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(Error::Numerical(format!(
            "saddle-point Lanczos estimate of {what} is not usable ({v:e})"
        )))
    }
}

/// One end of the spectrum of |A|: the search's inertia bracket and the converged estimate.
struct End {
    bracket: (f64, f64),
    estimate: f64,
    /// The bracket width wanted (`bracket_tol`).
    tol: f64,
    /// ρ(y_top) with its rounding bounded, where the top Ritz vector was kept.
    top_rq: Option<(f64, f64)>,
}

/// The state of one saddle-point cond₂: the shifted factorizations, A⁻¹ through K_FF, A itself
/// and the work counted so far.
struct SaddleRun<'a> {
    shifts: Shifts<'a>,
    /// D and the DOFs it touches.
    blocks: &'a Blocks<'a>,
    inverse: Inverse<'a>,
    a_pattern: SymbolicSparseColMat<usize>,
    a_values: Vec<f64>,
    size: usize,
    /// s₀ = 2/(g_B + √(g_B² + 4))·(1 − 1e-12), g_B the Gershgorin bound of K_BB: no
    /// eigenvalue of A in (−s₀, 0) (module docs).
    s0: f64,
    lanczos_steps: usize,
    /// Ritz vectors of A⁻¹'s extreme eigenvalues: the vectors of σ_min's proven upper bound
    /// (the first one λ⁺_min's, for Temple's lower bound).
    bottom_vectors: Vec<Vec<f64>>,
    /// λ⁺_min as estimated by the A⁻¹ run, and λ⁺₂ (from above) by its second Ritz value
    /// where it gives one: they place Temple's inertia test.
    positive: Option<(f64, Option<f64>)>,
    /// The same of |λ⁻_max| and the next negative eigenvalue's modulus (the −A⁻¹ run).
    negative: Option<(f64, Option<f64>)>,
    /// Warm starts of the λ_max, λ⁺_min and λ⁻_max runs ([`SaddleStarts`]).
    starts: Option<SaddleStarts>,
    /// |λ⁻_max| by the Schur complement's Newton steps, where they ran ([`schur`]).
    negative_value: Option<f64>,
}

impl SaddleRun<'_> {
    /// A·[x; y] = [K x + D y; Dᵀ x], times `sign`.
    fn apply_a(&self, v: &[f64], out: &mut [f64], sign: f64) {
        symmetric_matvec(self.a_pattern.as_ref(), &self.a_values, v, out);
        if sign < 0.0 {
            out.iter_mut().for_each(|o| *o = -*o);
        }
    }

    /// The top Ritz value of `sign`·A⁻¹ (its vector kept for σ_min's proven upper bound).
    fn inverse_top(&mut self, sign: f64) -> Result<f64> {
        let inverse = &mut self.inverse;
        let start = warm_start(&self.starts, sign, false);
        let run = lanczos(
            self.size,
            MAX_LANCZOS_STEPS,
            |_| STAGNATION,
            start,
            Keep::Always,
            |x, y| inverse.apply(x, y, sign),
        )?;
        self.lanczos_steps += run.steps;
        let second = run.second().filter(|&v| v > 0.0).map(|v| 1.0 / v);
        let estimates = Some((1.0 / run.theta, second));
        if sign > 0.0 {
            self.positive = estimates;
        } else {
            self.negative = estimates;
        }
        self.bottom_vectors.extend(run.vector);
        Ok(run.theta)
    }

    /// The eigenvalue of `sign·A` closest to 0 on its positive side from below by Temple's
    /// inequality (`temple`'s Theorem 9): λ⁺_min for sign > 0, |λ⁻_max| for sign < 0. The
    /// theorem holds for this indefinite A as it stands: with μ from [`Shifts::side_gap`], let
    /// `k = #{λ(sign·A) < μ}` and λ_k the largest eigenvalue of sign·A below μ; then
    /// `(λ_i − λ_k)(λ_i − μ) ≥ 0` for every eigenvalue (both factors ≤ 0 below λ_k, the
    /// other side's eigenvalues included, both ≥ 0 from μ on), which is all the proof uses.
    /// So the returned `lo` proves `#{λ(sign·A) < lo} ≤ k − 1`, i.e. `#{λ < lo} ≤ m` (sign > 0)
    /// or `#{λ ≤ −lo} ≥ m` (sign < 0). The tests sit at `τ = θ(1 + f)`, placed as the SPD route
    /// places them (`temple::lambda_min_lower`: halfway to the estimate of the next
    /// eigenvalue, then `f/(2k)` after k eigenvalues in (0, τ)). With m = 1 the negative side
    /// has one eigenvalue, and `μ = 2·σ_max_hi` needs no test. `x = A⁻¹y` for the side's Ritz
    /// vector y. None where no test gives μ or the hypotheses fail as computed.
    fn side_lower(&mut self, sign: f64, x: &[f64], sigma_max_hi: f64) -> Option<f64> {
        use super::temple::{temple_lower, FIRST_SHIFT, MAX_TESTS, MIN_SHIFT};
        let (theta, second) = if sign > 0.0 {
            self.positive?
        } else {
            self.negative?
        };
        if !(theta > 0.0 && theta.is_finite()) {
            return None;
        }
        let m = self.blocks.m;
        let values: std::borrow::Cow<[f64]> = if sign > 0.0 {
            std::borrow::Cow::Borrowed(&self.a_values)
        } else {
            std::borrow::Cow::Owned(self.a_values.iter().map(|v| -v).collect())
        };
        let temple =
            |mu: f64| temple_lower(self.a_pattern.as_ref(), &values, x, mu).filter(|&l| l > 0.0);
        if sign < 0.0 && m == 1 {
            return (sigma_max_hi.is_finite()).then(|| temple(2.0 * sigma_max_hi))?;
        }
        if !self.shifts.pattern.has_ldlt() {
            // No LDLᵀ (supernodal): the positive side's gap by interlacing
            // (`Shifts::pinned_gap`); the negative side has none.
            if sign < 0.0 {
                return None;
            }
            let in_b = &self.blocks.in_b;
            let pin = (0..in_b.len())
                .filter(|&i| !in_b[i])
                .fold(None, |b: Option<usize>, i| match b {
                    Some(j) if x[j].abs() >= x[i].abs() => Some(j),
                    _ => Some(i),
                })?;
            let margin = Margin::of(&self.shifts.pattern.symbolic);
            let mu = super::temple::INTERLACED_SHIFTS
                .iter()
                .find_map(|f| self.shifts.pinned_gap(theta * (1.0 + f), pin, margin))?;
            return temple(mu);
        }
        let mut f = second
            .map(|l2| 0.5 * (l2 / theta - 1.0))
            .filter(|&f| f >= MIN_SHIFT)
            .map_or(FIRST_SHIFT, |f| f.min(FIRST_SHIFT));
        for _ in 0..MAX_TESTS {
            if f < MIN_SHIFT {
                break;
            }
            match self.shifts.side_gap(sign, theta * (1.0 + f), m) {
                Ok(mu) => return temple(mu),
                Err(0) | Err(usize::MAX) => return None,
                Err(k) => f /= 2.0 * k as f64,
            }
        }
        None
    }

    /// The top Ritz value of `sign`·A, and its vector where `keep`.
    fn top(&mut self, sign: f64, keep: bool) -> Result<(f64, Option<Vec<f64>>)> {
        let this = &*self;
        let start = warm_start(&this.starts, sign, true);
        let run = lanczos(
            this.size,
            MAX_LANCZOS_STEPS,
            |_| STAGNATION,
            start,
            if keep { Keep::Always } else { Keep::Never },
            |x, y| this.apply_a(x, y, sign),
        )?;
        self.lanczos_steps += run.steps;
        Ok((run.theta, run.vector))
    }

    /// λ_max's estimate: the top Ritz value of A, the Rayleigh interval of its vector (one
    /// side of its bracket, Courant–Fischer) and the bracket width wanted; the bracket's upper
    /// end is the estimate itself (a scale, not a bound).
    fn top_estimate(&mut self, pos_min_est: f64) -> Result<End> {
        // The Ritz vector always (above RITZ_VECTOR_MAX_N by a second pass of the recurrence,
        // memory O(n)): without it σ_max's proven lower end is only max_i K_ii.
        let (theta, vector) = self.top(1.0, true)?;
        let lmax_est = usable("λ_max", theta)?;
        // The plain interval (≈ (n + k)·u wide), compensated where that exceeds a quarter of
        // the contract's floor of 1e-12.
        let top_rq = vector.as_deref().and_then(|y| {
            let plain = rayleigh_interval(self.a_pattern.as_ref(), &self.a_values, y)?;
            if plain.1 / plain.0 - 1.0 <= 2.5e-13 {
                return Some(plain);
            }
            certify::rayleigh_interval_dot2(self.a_pattern.as_ref(), &self.a_values, y)
                .map(|(lo, hi)| (lo.max(plain.0), hi.min(plain.1)))
                .or(Some(plain))
        });
        let lo = top_rq.map_or(0.0, |(lo, _)| lo);
        Ok(End {
            bracket: (lo, lmax_est.max(lo)),
            estimate: lmax_est,
            tol: bracket_tol(lmax_est / pos_min_est),
            top_rq,
        })
    }

    /// σ_max: λ_max, and −λ_min only where one test does not already show −λ_min < λ_max.
    /// λ_max is the top of A's spectrum, so the Rayleigh quotient of its Ritz vector is one
    /// side of its bracket (Courant–Fischer, as in the SPD route) and one test the other.
    fn sigma_max(&mut self, est: &End) -> Result<End> {
        let (lmax_est, tol, top_rq) = (est.estimate, est.tol, est.top_rq);
        let shifts = &mut self.shifts;
        let (max_lo, max_hi) =
            bracket_top(top_rq, lmax_est, tol, |s| shifts.is_pd(-1.0, s, -1.0 / s));
        if max_lo > 0.0 && shifts.is_pd(1.0, max_lo, -1.0 / max_lo) {
            return Ok(End {
                bracket: (max_lo, max_hi),
                estimate: lmax_est,
                tol,
                top_rq,
            });
        }
        let est = usable("−λ_min", self.top(-1.0, false)?.0)?;
        let shifts = &mut self.shifts;
        let (lo, hi) = bracket(est, tol, |s| shifts.is_pd(1.0, s, -1.0 / s));
        Ok(End {
            bracket: (max_lo.max(lo), max_hi.max(hi)),
            estimate: lmax_est.max(est),
            tol,
            top_rq,
        })
    }

    /// σ_min: λ⁺_min, and −λ⁻_max unless s₀ already shows −λ⁻_max > λ⁺_min.
    fn sigma_min(&mut self, pos_min_est: f64, top: &End, schur_test_max: usize) -> Result<End> {
        let tol = top.tol.max(bracket_tol(top.bracket.1 / pos_min_est));
        let shifts = &mut self.shifts;
        let (pmin_lo, pmin_hi) = bracket(pos_min_est, tol, |s| !shifts.is_pd(1.0, -s, 1.0 / s));
        let s0 = self.s0;
        if pmin_hi < s0 {
            return Ok(End {
                bracket: (pmin_lo, pmin_hi),
                estimate: pos_min_est,
                tol,
                top_rq: None,
            });
        }
        // The −A⁻¹ run of the proof's first attempt, where it ran.
        let near_est = match self.negative {
            Some((t, _)) => t,
            None => 1.0 / usable("−1/λ⁻_max", self.inverse_top(-1.0)?)?,
        };
        let tol = tol.max(bracket_tol(top.bracket.1 / near_est));
        let estimate = pos_min_est.min(near_est);
        let blocks = self.blocks;
        let bracket = if blocks.m <= schur_test_max {
            // Where −λ⁻_max is estimated clearly above λ⁺_min's bracket, one test at its top
            // settles σ_min = λ⁺_min; otherwise (or if that test finds an eigenvalue in
            // [−λ⁺_hi, 0)) −λ⁻_max gets its own bracket.
            let shifts = &mut self.shifts;
            let separated = near_est > pmin_hi * (1.0 + tol)
                && schur_test_fails(shifts, blocks, pmin_hi) == Some(false);
            let (lo, hi) = if separated {
                (pmin_hi, f64::INFINITY)
            } else {
                bracket(near_est, tol, |s| {
                    schur_test_fails(shifts, blocks, s).unwrap_or(true)
                })
            };
            (pmin_lo.min(lo), pmin_hi.min(hi))
        } else {
            // Only certified ends: [min(λ⁺_lo, s₀), λ⁺_hi]; the estimate inside as the value.
            (pmin_lo.min(s0), pmin_hi)
        };
        Ok(End {
            bracket,
            estimate,
            tol,
            top_rq: None,
        })
    }

    /// σ_min from below with the negative side bracketed through the Schur complement onto B
    /// ([`schur`]): `(min(p, lo⁻), hi⁻)` where `|λ⁻_max| ∈ [lo⁻, hi⁻]` and p proves
    /// `#{λ < p} ≤ m` — Temple's `lo⁺` where it was had, else a verified `H(p) ≻ 0`, placed
    /// at 2·hi⁻ where λ⁺_min is estimated above 4·hi⁻ (so that p ≥ lo⁻), else stepping down
    /// from λ⁺_min's estimate. Either proves K_FF ≻ 0 (`H(p)`'s F block is `K_FF − pI`),
    /// which Lemma S2 assumes with λ_min(K_FF) ≥ 0. The Newton value of |λ⁻_max| is kept as
    /// its estimate. None where the sizes exceed schur's limits or a step fails.
    fn schur_floor(
        &mut self,
        temple_pos: Option<f64>,
        tol: f64,
        margin: Margin,
    ) -> Option<(f64, f64)> {
        let neg_est = self.negative.map(|(t, _)| t);
        let pos_est = self.positive?.0;
        // (lo⁻, hi⁻, the Newton value): through the Schur complement onto B for a Boolean D;
        // for coupled rows lo⁻ alone, by Lemma R's tests stepping down from the estimate
        // (`coupling::negative_floor`), with the estimate in place of hi⁻ to place p.
        let (nb_lo, nb_hi, place, value) = match &self.inverse {
            Inverse::Free(free) => {
                let nb = schur::negative_bracket(
                    &mut self.shifts,
                    free.kff,
                    free.dofs,
                    neg_est,
                    0.0,
                    0.25 * tol.min(1e-12),
                )?;
                (nb.lo, nb.hi, nb.hi, Some(nb.value))
            }
            Inverse::Augmented(_) => {
                let neg = neg_est?;
                let shifts = &mut self.shifts;
                let w0 = (4.0 * f64::EPSILON).max(0.25 * tol.min(1e-12));
                let lo = certify::step_outwards(w0, |w, _| {
                    negative::negative_floor(shifts, neg * (1.0 - w), margin)
                })?;
                (lo, f64::INFINITY, neg, None)
            }
        };
        let shifts = &mut self.shifts;
        let p = match temple_pos {
            Some(lo) => lo,
            None => {
                let s = 2.0 * place;
                if pos_est > 4.0 * place && shifts.verified_pd(1.0, -s, 1.0 / s, margin) {
                    s
                } else {
                    certify::step_outwards((4.0 * f64::EPSILON).max(0.25 * tol), |w, _| {
                        let s = pos_est * (1.0 - w);
                        (s > 0.0 && shifts.verified_pd(1.0, -s, 1.0 / s, margin)).then_some(s)
                    })?
                }
            }
        };
        if p.is_nan() || p <= 0.0 {
            return None;
        }
        if value.is_some() {
            self.negative_value = value;
        }
        Some((p.min(nb_lo), nb_hi))
    }

    /// The proven brackets (certify) of σ_max and σ_min, where they pin cond₂ within a factor
    /// of 2: σ_max ≥ |ρ(y_top)| and σ_max < s once both −H(s) ≻ 0 and H(−s) ≻ 0 are
    /// verified; σ_min ≤ ‖Ax̂‖/‖x̂‖ for x̂ = A⁻¹y (y a Ritz vector of A⁻¹), and σ_min ≥ s once
    /// H(s) ≻ 0 is verified (λ⁺_min > s) and no eigenvalue lies in [−t, 0) for t ≥ s (t = s₀,
    /// or an LDLᵀ inertia test of H(−s), [`Shifts::no_eigenvalue_above`]). Where neither
    /// reaches s, or a margin m·cond₂ ≳ 1 makes them wide, None: the search's inertia brackets
    /// are reported, not proven.
    #[allow(clippy::type_complexity)]
    fn proven(
        &mut self,
        pattern: &DiagonalPattern,
        top: &End,
        bottom: &End,
    ) -> Option<((f64, f64), (f64, f64))> {
        let margin = Margin::of(&pattern.symbolic);
        let (max_lo, max_hi) = self.proven_top(pattern, top, margin);
        let mut min_hi = f64::INFINITY;
        let mut x_hats = Vec::new();
        for y in &self.bottom_vectors {
            let mut x = vec![0.0; self.size];
            self.inverse.apply(y, &mut x, 1.0);
            let nx = certify::dot_interval(&x, &x).0.sqrt() * (1.0 - 4.0 * f64::EPSILON);
            let ax = certify::image_norm_upper(self.a_pattern.as_ref(), &self.a_values, &x, y);
            if nx > 0.0 {
                min_hi = min_hi.min(ax / nx * (1.0 + 4.0 * f64::EPSILON));
            }
            x_hats.push(x);
        }
        let base = bottom.estimate.min(min_hi);
        let (s0, m) = (self.s0, self.blocks.m);
        // σ_min ≥ min(s, t) once `#{λ < s} ≤ m` is proven for an s > 0 and no eigenvalue lies
        // in [−t, 0) (t = s₀ or, above it, t from an inertia test of H(−s)).
        let floor = |shifts: &mut Shifts, s: f64| {
            let mut t = if s > s0 {
                s0.max(shifts.no_eigenvalue_above(s, m).unwrap_or(0.0))
            } else {
                s0
            };
            // Coupled rows (no s₀): Lemma R's test at s where the LDLᵀ test did not settle it.
            if t < s && !shifts.blocks.is_selection() {
                t = t.max(negative::negative_floor(shifts, s, margin).unwrap_or(0.0));
            }
            s.min(t)
        };
        // By Temple's bounds (second order in the residuals of x = A⁻¹y): λ⁺_min ≥ lo⁺ gives
        // `#{λ < lo⁺} ≤ m`, and where the −A⁻¹ run gave |λ⁻_max| its vector too, |λ⁻_max| ≥ lo⁻
        // gives `#{λ ≤ −lo⁻} ≥ m`: no eigenvalue in (−lo⁻, lo⁺), σ_min ≥ min(lo⁺, lo⁻); without
        // it, lo⁺ with t as above. Else verified Cholesky tests of H(s) stepping down from the
        // estimate (first order: Lemma 1's margin times cond₂).
        let temple_pos = x_hats.first().and_then(|x| self.side_lower(1.0, x, max_hi));
        let temple = match (temple_pos, x_hats.get(1)) {
            (Some(lo), Some(x)) => self
                .side_lower(-1.0, x, max_hi)
                .map(|l| lo.min(l))
                .or_else(|| Some(floor(&mut self.shifts, lo))),
            (Some(lo), None) => Some(floor(&mut self.shifts, lo)),
            (None, _) => None,
        };
        // Where Temple's bounds miss the bracket width wanted (clustered negative
        // eigenvalues), the negative side through the Schur complement onto B (schur).
        let temple = match temple {
            Some(lo) if min_hi / lo - 1.0 <= bottom.tol => Some(lo),
            _ => match self.schur_floor(temple_pos, bottom.tol, margin) {
                Some((lo, hi)) => {
                    min_hi = min_hi.min(hi);
                    Some(temple.map_or(lo, |t| t.max(lo)))
                }
                None => temple,
            },
        };
        let shifts = &mut self.shifts;
        let min_lo = match temple {
            Some(s) => s,
            None => {
                let w0 = (4.0 * margin.m * top.bracket.1 / base).max(4.0 * f64::EPSILON);
                certify::step_outwards(w0, |w, _| {
                    let s = base * (1.0 - w);
                    (s > 0.0 && shifts.verified_pd(1.0, -s, 1.0 / s, margin))
                        .then(|| floor(shifts, s))
                })?
            }
        };
        let informative = max_hi.is_finite()
            && min_hi.is_finite()
            && min_lo > 0.0
            && max_hi / min_lo <= 2.0 * max_lo / min_hi;
        informative.then_some(((max_lo, max_hi), (min_lo, min_hi)))
    }
}
