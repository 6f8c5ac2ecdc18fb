//! Numerical stability of the penalized solve `(K + D E Dᵀ) u = q + D E û`: forward errors
//! against an extended-precision reference, iterative refinement and diagonal scaling.
//!
//! # The measurement
//! For given data K, q, û and penalties ε_c (all f64), the **exact** solution u* of the
//! penalized system is computed in double-double arithmetic ([`Dd`], ≈ 106-bit significand,
//! unit roundoff u_dd = 2⁻¹⁰⁴ ≈ 4.9e-32) by Gaussian elimination with partial pivoting plus
//! two refinement steps with a double-double residual ([`PenalizedSystem::reference`]). The
//! matrix is formed exactly: `K[d,d] + ε` is a double-double sum, not the rounded f64 sum, so
//! the rounding that swamps `K[d,d]` when ε is huge counts as an error of the f64 solve, as it
//! should. The reference is accurate to about `n · cond₂ · u_dd` (1e-10 at cond₂ = 1e20 and
//! n = 100); its last refinement correction is reported as an a-posteriori estimate.
//!
//! The forward error of an f64 solution x is `‖x − u*‖₂ / ‖u*‖₂`; the classical bound for a
//! backward-stable solve is `≈ cond₂ · ε_mach` (Higham, *Accuracy and Stability of Numerical
//! Algorithms*, §7).
//!
//! # What can be done about it ([`solve`])
//! * **Iterative refinement** `x ← x + A⁻¹ (b − A x)` with the f64 factor:
//!   - residual in working precision ([`ResidualPrecision::Working`], `b − A x` with the
//!     f64-assembled A and b): improves the backward error, not the forward error (Skeel);
//!   - residual in extended precision ([`ResidualPrecision::Extended`], `b − A x` from the
//!     exact data in double-double, rounded once): converges to the correctly rounded
//!     solution while `cond₂ · ε_mach ≲ 1`, and recovers what forming `K[d,d] + ε` in f64 lost.
//! * **Equilibration** `Â = S A S`, `S = diag(2^k_i)` with `2^k_i ≈ 1/√A_ii` (powers of two:
//!   the scaling itself is exact). Cholesky is invariant under such a scaling (van der Sluis:
//!   its rounding errors are those of the scaled problem already), so equilibration changes the
//!   computed u only when LU pivots differently; what it does change is the smallest/largest
//!   pivot ratio, so a penalized matrix whose ill-conditioning is purely diagonal (huge ε on a
//!   few DOFs) passes [`Factorization`](crate::linalg::Factorization)'s "singular to working precision" test after scaling.
//!
//! # Stress studies
//! [`eps_study`] sweeps a uniform ε over a grid on one problem (constraints active as in the
//! exact contact solution) and records, per ε: exact cond₂, the forward error of every solve
//! variant, the penalty's model error against the exact contact solution (`lagrange`), and the
//! constant strategy's own outcome. [`strategy_study`] runs every strategy at extreme knobs
//! (tiny/huge ε, factors, δ, tolerances) and records status (ok / clean error / panic /
//! non-finite), warnings, cond₂ and errors. [`figures()`] turns the rows into plots.

//!
//! # Layout
//! [`dd`]: the double-double LU (arithmetic in [`crate::dd`]); [`system`]: the exactly formed penalized system and
//! its reference; [`refine`]: f64 solves with refinement and equilibration; [`study`]: the
//! studies; [`record`]: a whole run, its CSV, summary and record; [`figures`](mod@figures): its
//! figures; [`report`]: the printed line; [`cli`]: the flags and [`Stress`], the study as the
//! shared entry ([`crate::study::shape::main`]) runs it.

pub mod cli;
pub mod dd;
pub mod figures;
/// A whole run: studies with progress, outputs, record.
pub mod record;
pub mod refine;
pub mod report;
pub mod study;
pub mod system;

pub use crate::dd::{two_prod, two_sum, Dd};
pub use cli::Stress;
pub use figures::*;
pub use refine::*;
pub use study::*;
pub use system::*;
