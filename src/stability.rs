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
//!   few DOFs) passes [`Factorization`]'s "singular to working precision" test after scaling.
//!
//! # Stress studies
//! [`eps_study`] sweeps a uniform ε over a grid on one problem (constraints active as in the
//! exact contact solution) and records, per ε: exact cond₂, the forward error of every solve
//! variant, the penalty's model error against the exact contact solution (`lagrange`), and the
//! constant strategy's own outcome. [`strategy_study`] runs every strategy at extreme knobs
//! (tiny/huge ε, factors, δ, tolerances) and records status (ok / clean error / panic /
//! non-finite), warnings, cond₂ and errors. [`figures`] turns the rows into plots.

use crate::conditioning;
use crate::error::{Error, Result};
use crate::linalg::Factorization;
use crate::metrics::{self, MetricSet};
use crate::plot::{Figure, Mark, Scale, Series};
use crate::strategy::{self, Method, Solution, SystemKind};
use crate::system::{ConstraintKind, Problem, Stiffness};
use serde::Serialize;
use std::ops::{Add, Div, Mul, Neg, Sub};
use std::panic::{catch_unwind, AssertUnwindSafe};

// ---------------------------------------------------------------------------------------
// Double-double arithmetic
// ---------------------------------------------------------------------------------------

/// A double-double number `hi + lo` with `|lo| ≤ ulp(hi)/2` (Dekker 1971; Hida, Li & Bailey's
/// QD library): about 106 significant bits, the exponent range of f64.
///
/// Error-free transformations: `two_sum(a, b) = (s, e)` with `s + e = a + b` exactly (Knuth),
/// `two_prod(a, b) = (p, e)` with `p + e = a·b` exactly (one fused multiply-add).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    /// Leading part (the f64 nearest to the value).
    pub hi: f64,
    /// Trailing part.
    pub lo: f64,
}

/// `(s, e)` with `s = fl(a + b)` and `s + e = a + b` exactly.
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// `(p, e)` with `p = fl(a·b)` and `p + e = a·b` exactly (barring underflow).
#[inline]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

#[inline]
fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

impl Dd {
    /// Zero.
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    /// The exact value of an f64.
    pub fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// Nearest f64.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// `|x|`.
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0) {
            -self
        } else {
            self
        }
    }

    /// `true` if both parts are finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// `a·b` for two f64, exactly.
    pub fn prod(a: f64, b: f64) -> Dd {
        let (p, e) = two_prod(a, b);
        Dd { hi: p, lo: e }
    }

    /// `a + b` for two f64, exactly.
    pub fn sum(a: f64, b: f64) -> Dd {
        let (s, e) = two_sum(a, b);
        Dd { hi: s, lo: e }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Dd {
        Dd::from_f64(x)
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    /// IEEE-style (accurate) double-double addition.
    fn add(self, b: Dd) -> Dd {
        let (s1, s2) = two_sum(self.hi, b.hi);
        let (t1, t2) = two_sum(self.lo, b.lo);
        let s2 = s2 + t1;
        let r = quick_two_sum(s1, s2);
        let s2 = t2 + r.lo;
        quick_two_sum(r.hi, s2)
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, b: Dd) -> Dd {
        let (p1, p2) = two_prod(self.hi, b.hi);
        let p2 = p2 + (self.hi * b.lo + self.lo * b.hi);
        quick_two_sum(p1, p2)
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three f64 quotient digits.
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * Dd::from_f64(q1);
        let q2 = r.hi / b.hi;
        let r = r - b * Dd::from_f64(q2);
        let q3 = r.hi / b.hi;
        let q = quick_two_sum(q1, q2);
        q + Dd::from_f64(q3)
    }
}

// ---------------------------------------------------------------------------------------
// The penalized system
// ---------------------------------------------------------------------------------------

/// Precision of the residual `b − A x` in iterative refinement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ResidualPrecision {
    /// f64, with the f64-assembled matrix `K + D E Dᵀ` and right-hand side `q + D E û`.
    Working,
    /// Double-double from the exact data (`K x + ε_c x[d_c]`, `q + ε_c û_c`), rounded once.
    Extended,
}

/// The penalized system `(K + D E Dᵀ) u = q + D E ℓ` of a problem for given penalties ε_c
/// (0 = unpenalized) and limits ℓ (normally û).
#[derive(Clone, Debug)]
pub struct PenalizedSystem<'a> {
    /// The problem (K, q, the constraint DOFs).
    pub problem: &'a Problem,
    /// ε_c ≥ 0 per constraint.
    pub penalties: Vec<f64>,
    /// ℓ_c per constraint.
    pub limits: Vec<f64>,
}

/// Largest N for which [`PenalizedSystem::reference`] runs (dense double-double elimination,
/// ≈ N³/3 double-double operations: about 1 s at N = 600).
pub const REFERENCE_MAX_N: usize = 800;

/// The extended-precision solution of a penalized system.
#[derive(Clone, Debug)]
pub struct Reference {
    /// u* rounded to f64.
    pub u: Vec<f64>,
    /// `‖last refinement correction‖₂ / ‖u*‖₂`: an estimate of the reference's own error.
    pub correction: f64,
}

impl<'a> PenalizedSystem<'a> {
    /// The system with limits û. Errors on a wrong length, NaN/Inf or a negative penalty.
    pub fn new(problem: &'a Problem, penalties: &[f64]) -> Result<Self> {
        let limits = problem.constraints.iter().map(|c| c.limit).collect();
        Self::with_limits(problem, penalties, limits)
    }

    /// The system with explicit limits ℓ (shifted limits of the augmented Lagrangian).
    pub fn with_limits(problem: &'a Problem, penalties: &[f64], limits: Vec<f64>) -> Result<Self> {
        let m = problem.m();
        if penalties.len() != m || limits.len() != m {
            return Err(Error::input(format!(
                "penalized system: {} penalties and {} limits for {m} constraints",
                penalties.len(),
                limits.len()
            )));
        }
        if let Some(c) = penalties.iter().position(|e| !(e.is_finite() && *e >= 0.0)) {
            return Err(Error::input(format!(
                "penalized system: penalty {c} is {} (need a finite ε ≥ 0)",
                penalties[c]
            )));
        }
        if let Some(c) = limits.iter().position(|l| !l.is_finite()) {
            return Err(Error::input(format!(
                "penalized system: limit {c} is not finite"
            )));
        }
        Ok(PenalizedSystem {
            problem,
            penalties: penalties.to_vec(),
            limits,
        })
    }

    /// `K + D E Dᵀ` assembled in f64 (as the strategies do).
    pub fn matrix(&self) -> Stiffness {
        strategy::penalized_matrix(self.problem, &self.penalties)
    }

    /// `q + D E ℓ` in f64 (as the strategies do).
    pub fn rhs(&self) -> Vec<f64> {
        let mut b = self.problem.q.clone();
        for ((c, &e), &l) in self
            .problem
            .constraints
            .iter()
            .zip(&self.penalties)
            .zip(&self.limits)
        {
            b[c.dof] += e * l;
        }
        b
    }

    /// `b − A x` in the given precision (see [`ResidualPrecision`]).
    pub fn residual(&self, x: &[f64], precision: ResidualPrecision) -> Vec<f64> {
        match precision {
            ResidualPrecision::Working => {
                let a = self.matrix();
                let ax = a.matvec(x);
                self.rhs().iter().zip(ax).map(|(b, v)| b - v).collect()
            }
            ResidualPrecision::Extended => {
                let p = self.problem;
                let mut r: Vec<Dd> = p.q.iter().map(|&v| Dd::from_f64(v)).collect();
                p.k.for_each_entry(|i, j, v| r[i] = r[i] - Dd::prod(v, x[j]));
                for ((c, &e), &l) in p.constraints.iter().zip(&self.penalties).zip(&self.limits) {
                    if e != 0.0 {
                        let d = c.dof;
                        r[d] = r[d] + Dd::prod(e, l) - Dd::prod(e, x[d]);
                    }
                }
                r.into_iter().map(Dd::to_f64).collect()
            }
        }
    }

    /// The exactly formed matrix (row-major, double-double) and right-hand side.
    fn exact_dense(&self) -> Result<(Vec<Dd>, Vec<Dd>)> {
        let p = self.problem;
        let n = p.n();
        if n > REFERENCE_MAX_N {
            return Err(Error::input(format!(
                "extended-precision reference limited to N ≤ {REFERENCE_MAX_N} (N = {n})"
            )));
        }
        let mut a = vec![Dd::ZERO; n * n];
        p.k.for_each_entry(|i, j, v| a[i * n + j] = a[i * n + j] + Dd::from_f64(v));
        let mut b: Vec<Dd> = p.q.iter().map(|&v| Dd::from_f64(v)).collect();
        for ((c, &e), &l) in p.constraints.iter().zip(&self.penalties).zip(&self.limits) {
            if e != 0.0 {
                let d = c.dof;
                a[d * n + d] = a[d * n + d] + Dd::from_f64(e);
                b[d] = b[d] + Dd::prod(e, l);
            }
        }
        Ok((a, b))
    }

    /// cond₂ of the exactly formed matrix A, accurate at any size of cond₂:
    /// `σ_max(A) · σ_max(A⁻¹)`, with A⁻¹ computed column by column in double-double and
    /// rounded once (so its largest singular value carries a relative error of order
    /// n·ε_mach, where the smallest singular value of A computed in f64 carries an absolute
    /// error of order ε_mach·σ_max(A) and is noise once cond₂ ≳ 1/ε_mach).
    /// Same size limit as [`PenalizedSystem::reference`].
    pub fn cond2_extended(&self) -> Result<f64> {
        let n = self.problem.n();
        let (a, _) = self.exact_dense()?;
        let lu = DdLu::factor(a.clone(), n)?;
        let af = faer::Mat::from_fn(n, n, |i, j| a[i * n + j].to_f64());
        let mut inv = faer::Mat::zeros(n, n);
        let mut e = vec![Dd::ZERO; n];
        for j in 0..n {
            e[j] = Dd::from_f64(1.0);
            let col = lu.solve(&e);
            e[j] = Dd::ZERO;
            for (i, v) in col.iter().enumerate() {
                inv[(i, j)] = v.to_f64();
            }
        }
        let smax = |m: &faer::Mat<f64>| -> Result<f64> {
            let sv = m
                .singular_values()
                .map_err(|e| Error::Numerical(format!("singular values failed: {e:?}")))?;
            Ok(sv.first().copied().unwrap_or(0.0))
        };
        let c = smax(&af)? * smax(&inv)?;
        if c.is_finite() {
            Ok(c)
        } else {
            Err(Error::Numerical("cond₂ overflows f64".into()))
        }
    }

    /// The solution in double-double: Gaussian elimination with partial pivoting on the
    /// exactly formed matrix, then two refinement steps with a double-double residual.
    /// Errors for N > [`REFERENCE_MAX_N`] or an exactly singular pivot.
    pub fn reference(&self) -> Result<Reference> {
        let n = self.problem.n();
        let (a, b) = self.exact_dense()?;
        let lu = DdLu::factor(a.clone(), n)?;
        let mut x = lu.solve(&b);
        let xnorm = |x: &[Dd]| x.iter().map(|v| v.hi * v.hi).sum::<f64>().sqrt();
        let mut correction = f64::INFINITY;
        for _ in 0..2 {
            let mut r = b.clone();
            for i in 0..n {
                let row = &a[i * n..(i + 1) * n];
                let mut s = Dd::ZERO;
                for (aij, xj) in row.iter().zip(&x) {
                    if aij.hi != 0.0 {
                        s = s + *aij * *xj;
                    }
                }
                r[i] = r[i] - s;
            }
            let dx = lu.solve(&r);
            let dn = dx.iter().map(|v| v.hi * v.hi).sum::<f64>().sqrt();
            for (xi, di) in x.iter_mut().zip(&dx) {
                *xi = *xi + *di;
            }
            let xn = xnorm(&x);
            correction = if xn > 0.0 { dn / xn } else { dn };
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(Error::Numerical(
                "extended-precision reference is not finite (overflow)".into(),
            ));
        }
        Ok(Reference {
            u: x.into_iter().map(Dd::to_f64).collect(),
            correction,
        })
    }
}

/// Dense LU with partial pivoting in double-double (row-major, in place).
struct DdLu {
    a: Vec<Dd>,
    perm: Vec<usize>,
    n: usize,
}

impl DdLu {
    fn factor(mut a: Vec<Dd>, n: usize) -> Result<Self> {
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let (piv, pmax) = (k..n)
                .map(|i| (i, a[i * n + k].abs().hi))
                .fold((k, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
            if pmax <= 0.0 || !pmax.is_finite() {
                return Err(Error::singular(format!(
                    "extended-precision reference: zero pivot in column {k} (matrix exactly singular)"
                )));
            }
            if piv != k {
                for j in 0..n {
                    a.swap(k * n + j, piv * n + j);
                }
                perm.swap(k, piv);
            }
            let akk = a[k * n + k];
            for i in k + 1..n {
                if a[i * n + k].hi == 0.0 {
                    continue;
                }
                let l = a[i * n + k] / akk;
                a[i * n + k] = l;
                for j in k + 1..n {
                    let akj = a[k * n + j];
                    if akj.hi != 0.0 {
                        a[i * n + j] = a[i * n + j] - l * akj;
                    }
                }
            }
        }
        Ok(DdLu { a, perm, n })
    }

    fn solve(&self, b: &[Dd]) -> Vec<Dd> {
        let n = self.n;
        let mut y: Vec<Dd> = self.perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            let row = &self.a[i * n..i * n + i];
            let mut s = y[i];
            for (l, yj) in row.iter().zip(&y[..i]) {
                if l.hi != 0.0 {
                    s = s - *l * *yj;
                }
            }
            y[i] = s;
        }
        for i in (0..n).rev() {
            let row = &self.a[i * n + i + 1..(i + 1) * n];
            let mut s = y[i];
            for (u, yj) in row.iter().zip(&y[i + 1..]) {
                if u.hi != 0.0 {
                    s = s - *u * *yj;
                }
            }
            y[i] = s / self.a[i * n + i];
        }
        y
    }
}

// ---------------------------------------------------------------------------------------
// Solves with refinement and equilibration
// ---------------------------------------------------------------------------------------

/// How to solve a penalized system in f64.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SolveOptions {
    /// Factor `S A S` (power-of-two diagonal scaling) instead of A.
    pub equilibrate: bool,
    /// Iterative refinement with this residual precision (`None`: none).
    pub refine: Option<ResidualPrecision>,
    /// Maximum refinement steps.
    pub max_steps: usize,
}

impl SolveOptions {
    /// One factorization and one solve, nothing else.
    pub const PLAIN: SolveOptions = SolveOptions {
        equilibrate: false,
        refine: None,
        max_steps: 0,
    };

    /// The five variants compared by the stress study, with names.
    pub fn variants(max_steps: usize) -> [(&'static str, SolveOptions); 5] {
        let o = |equilibrate, refine| SolveOptions {
            equilibrate,
            refine,
            max_steps,
        };
        [
            ("plain", SolveOptions::PLAIN),
            (
                "refined_working",
                o(false, Some(ResidualPrecision::Working)),
            ),
            (
                "refined_extended",
                o(false, Some(ResidualPrecision::Extended)),
            ),
            ("equilibrated", o(true, None)),
            (
                "equilibrated_refined_extended",
                o(true, Some(ResidualPrecision::Extended)),
            ),
        ]
    }
}

/// An f64 solution with the refinement history.
#[derive(Clone, Debug, Serialize)]
pub struct RefinedSolve {
    /// The solution.
    pub x: Vec<f64>,
    /// Refinement steps taken.
    pub steps: usize,
    /// Normwise relative backward error `‖b − A x‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` (in the residual
    /// precision used, Working if none) before each step and after the last.
    pub backward_errors: Vec<f64>,
    /// `max_k |S_kk|/min_k |S_kk|` of the scaling used (1 without equilibration).
    pub scaling_spread: f64,
}

/// Power-of-two scaling `s_i = 2^round(−log2|a_ii| / 2)` (1 for a zero or non-finite diagonal).
pub fn equilibration(a: &Stiffness) -> Vec<f64> {
    (0..a.n())
        .map(|i| {
            let d = a.diag(i).abs();
            if d > 0.0 && d.is_finite() {
                let k = (-d.log2() / 2.0).round().clamp(-500.0, 500.0);
                2f64.powi(k as i32)
            } else {
                1.0
            }
        })
        .collect()
}

fn scaled(a: &Stiffness, s: &[f64]) -> Stiffness {
    match a {
        Stiffness::Dense(m) => {
            let n = m.nrows();
            Stiffness::Dense(faer::Mat::from_fn(n, n, |i, j| s[i] * m[(i, j)] * s[j]))
        }
        Stiffness::Sparse(_) => {
            let mut t = Vec::with_capacity(a.nnz());
            a.for_each_entry(|i, j, v| t.push((i, j, s[i] * v * s[j])));
            Stiffness::from_triplets(a.n(), &t).expect("same pattern")
        }
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

fn matrix_inf_norm(a: &Stiffness) -> f64 {
    let mut rows = vec![0.0f64; a.n()];
    a.for_each_entry(|i, _, v| rows[i] += v.abs());
    inf_norm(&rows)
}

/// Solves a penalized system in f64 with optional equilibration and iterative refinement.
///
/// Refinement stops after `max_steps`, or when a step no longer halves the correction
/// (`‖dx‖ > ‖dx_prev‖/2`, the standard stagnation test), or when the correction falls below
/// `ε_mach ‖x‖`. Errors: [`Error::Singular`] when the (scaled) matrix fails the factorization's
/// singularity test.
pub fn solve(sys: &PenalizedSystem, opts: SolveOptions) -> Result<RefinedSolve> {
    let a = sys.matrix();
    let b = sys.rhs();
    let symmetric = a.is_symmetric();
    let (s, f) = if opts.equilibrate {
        let s = equilibration(&a);
        let f = Factorization::new(&scaled(&a, &s), symmetric)?;
        (Some(s), f)
    } else {
        (None, Factorization::new(&a, symmetric)?)
    };
    let apply_inverse = |r: &[f64]| -> Vec<f64> {
        match &s {
            Some(s) => {
                let rs: Vec<f64> = r.iter().zip(s).map(|(v, si)| v * si).collect();
                f.solve(&rs).iter().zip(s).map(|(v, si)| v * si).collect()
            }
            None => f.solve(r),
        }
    };
    let scaling_spread = s.as_ref().map_or(1.0, |s| {
        let (lo, hi) = s.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(*v), hi.max(*v))
        });
        hi / lo
    });
    let mut x = apply_inverse(&b);
    let anorm = matrix_inf_norm(&a);
    let bnorm = inf_norm(&b);
    let backward = |r: &[f64], x: &[f64]| {
        let den = anorm * inf_norm(x) + bnorm;
        if den > 0.0 {
            inf_norm(r) / den
        } else {
            inf_norm(r)
        }
    };
    let precision = opts.refine.unwrap_or(ResidualPrecision::Working);
    let mut r = sys.residual(&x, precision);
    let mut backward_errors = vec![backward(&r, &x)];
    let mut steps = 0;
    if opts.refine.is_some() {
        let mut prev = f64::INFINITY;
        while steps < opts.max_steps {
            let dx = apply_inverse(&r);
            let dn = inf_norm(&dx);
            if !dn.is_finite() || dn > 0.5 * prev {
                break;
            }
            for (xi, di) in x.iter_mut().zip(&dx) {
                *xi += di;
            }
            steps += 1;
            r = sys.residual(&x, precision);
            backward_errors.push(backward(&r, &x));
            if dn <= f64::EPSILON * inf_norm(&x) {
                break;
            }
            prev = dn;
        }
    }
    Ok(RefinedSolve {
        x,
        steps,
        backward_errors,
        scaling_spread,
    })
}

// ---------------------------------------------------------------------------------------
// Stress studies
// ---------------------------------------------------------------------------------------

/// A named problem for the stress studies.
#[derive(Clone, Debug)]
pub struct StressScene {
    /// Name (e.g. `paper-beam`, `spectrum-0001`).
    pub name: String,
    /// Family (`paper`, `beam`, `membrane`, `spectrum`).
    pub family: String,
    /// The problem.
    pub problem: Problem,
}

/// Outcome of one guarded strategy run.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    /// `Ok` with finite outputs.
    Ok,
    /// A clean `Err` (message).
    Error {
        /// The error message.
        message: String,
    },
    /// `Ok` but some output (u, penalties, gaps, forces, max penetration) is NaN/Inf.
    NonFinite {
        /// Which field.
        field: String,
    },
    /// The strategy panicked (message).
    Panic {
        /// The panic payload.
        message: String,
    },
}

impl Outcome {
    /// `ok`, `error`, `non_finite` or `panic`.
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Ok => "ok",
            Outcome::Error { .. } => "error",
            Outcome::NonFinite { .. } => "non_finite",
            Outcome::Panic { .. } => "panic",
        }
    }
    /// The message (empty for `ok`).
    pub fn message(&self) -> String {
        match self {
            Outcome::Ok => String::new(),
            Outcome::Error { message } | Outcome::Panic { message } => message.clone(),
            Outcome::NonFinite { field } => format!("{field} contains NaN/Inf"),
        }
    }
}

/// The first non-finite output field of a solution, if any.
pub fn non_finite_field(sol: &Solution) -> Option<&'static str> {
    let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
    if bad(&sol.u) {
        Some("u")
    } else if bad(&sol.penalties) {
        Some("penalties")
    } else if bad(&sol.gaps) {
        Some("gaps")
    } else if bad(&sol.forces) {
        Some("forces")
    } else if !sol.max_penetration.is_finite() {
        Some("max_penetration")
    } else {
        None
    }
}

/// Runs a strategy, turning a panic into [`Outcome::Panic`] and non-finite output into
/// [`Outcome::NonFinite`].
pub fn guarded_solve(problem: &Problem, method: Method) -> (Outcome, Option<Solution>) {
    match catch_unwind(AssertUnwindSafe(|| strategy::solve(problem, method))) {
        Ok(Ok(sol)) => match non_finite_field(&sol) {
            Some(f) => (
                Outcome::NonFinite {
                    field: f.to_string(),
                },
                Some(sol),
            ),
            None => (Outcome::Ok, Some(sol)),
        },
        Ok(Err(e)) => (
            Outcome::Error {
                message: e.to_string(),
            },
            None,
        ),
        Err(p) => (
            Outcome::Panic {
                message: p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "unknown panic payload".into()),
            },
            None,
        ),
    }
}

/// Forward errors of the five [`SolveOptions::variants`] (`None` where the solve errored).
#[derive(Clone, Debug, Default, Serialize, serde::Deserialize)]
pub struct VariantErrors {
    /// One factorization, one solve.
    pub plain: Option<f64>,
    /// Refinement with an f64 residual.
    pub refined_working: Option<f64>,
    /// Refinement with a double-double residual.
    pub refined_extended: Option<f64>,
    /// Power-of-two equilibration.
    pub equilibrated: Option<f64>,
    /// Equilibration and refinement with a double-double residual.
    pub equilibrated_refined_extended: Option<f64>,
}

impl VariantErrors {
    fn set(&mut self, name: &str, v: Option<f64>) {
        match name {
            "plain" => self.plain = v,
            "refined_working" => self.refined_working = v,
            "refined_extended" => self.refined_extended = v,
            "equilibrated" => self.equilibrated = v,
            _ => self.equilibrated_refined_extended = v,
        }
    }
    /// `(name, value)` pairs in the order of [`SolveOptions::variants`].
    pub fn pairs(&self) -> [(&'static str, Option<f64>); 5] {
        [
            ("plain", self.plain),
            ("refined_working", self.refined_working),
            ("refined_extended", self.refined_extended),
            ("equilibrated", self.equilibrated),
            (
                "equilibrated_refined_extended",
                self.equilibrated_refined_extended,
            ),
        ]
    }
}

/// One point of [`eps_study`].
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct EpsRow {
    /// Scene name.
    pub scene: String,
    /// Scene family.
    pub family: String,
    /// N.
    pub n: usize,
    /// Penalized constraints (the exact solution's active set).
    pub m_active: usize,
    /// Uniform penalty ε.
    pub eps: f64,
    /// cond₂ of `K + ε D_A D_Aᵀ` by [`PenalizedSystem::cond2_extended`] (accurate beyond
    /// 1/ε_mach); `None` if it could not be computed.
    pub cond2: Option<f64>,
    /// cond₂ of the f64-assembled matrix by [`conditioning::cond2`] (the harness's exact route,
    /// all in f64: reliable while cond₂ ≲ 1e15, noise beyond).
    pub cond2_f64: Option<f64>,
    /// cond₂ · ε_mach: the classical forward-error bound.
    pub cond_eps_mach: Option<f64>,
    /// cond₂ of the equilibrated matrix `S A S` ([`equilibration`]): it bounds Cholesky's
    /// forward error in the S⁻¹-weighted norm (van der Sluis; Demmel 1989), and is far below
    /// cond₂ when the ill-conditioning is a matter of diagonal scale, as with a few huge
    /// penalties. Against the plain 2-norm error it is an empirical predictor only (see the
    /// `forward_error_vs_scaled_cond` figure).
    pub cond2_scaled: Option<f64>,
    /// `cond₂ · ε_mach` exceeds [`metrics::DIGITS_LOST_THRESHOLD`], the threshold of
    /// [`metrics::precision_warnings`].
    pub precision_warning: bool,
    /// [`Reference::correction`] (a-posteriori error estimate of u*).
    pub reference_correction: Option<f64>,
    /// Forward errors `‖x − u*‖/‖u*‖` per solve variant.
    pub forward: VariantErrors,
    /// Messages of variants that errored (`variant: message`).
    pub variant_errors: Vec<String>,
    /// Refinement steps taken by `refined_extended`.
    pub steps_extended: Option<usize>,
    /// Model error of the penalty: `‖u* − u_lagrange‖/‖u_lagrange‖` (`None` when lagrange
    /// refuses the scene). u_lagrange is itself an f64 solve, accurate to about
    /// cond₂(saddle)·ε_mach, which is where this error levels off at large ε.
    pub penalty_error: Option<f64>,
    /// Total error of the plain f64 solve: `‖x_plain − u_lagrange‖/‖u_lagrange‖`.
    pub total_error_plain: Option<f64>,
    /// Total error of the best variant (`equilibrated_refined_extended`) against lagrange.
    pub total_error_refined: Option<f64>,
    /// The `constant` strategy at this ε: outcome name.
    pub strategy_status: String,
    /// The `constant` strategy's message (error/panic), empty if ok.
    pub strategy_message: String,
    /// The `constant` strategy's max penetration.
    pub strategy_max_penetration: Option<f64>,
    /// The `constant` strategy's warnings plus the precision warnings of its system.
    pub strategy_warnings: usize,
}

/// Configuration of the stress studies.
#[derive(Clone, Debug, Serialize)]
pub struct StressConfig {
    /// ε grid for `constant` and [`eps_study`] (absolute values).
    pub eps: Vec<f64>,
    /// Factors for `scaled`.
    pub factors: Vec<f64>,
    /// δ relative to the displacement scale max_c |u0\[d_c\]| (spring, paper, condensed).
    pub deltas_rel: Vec<f64>,
    /// Augmented: ε relative to max_c K\[d_c,d_c\].
    pub augmented_eps_rel: Vec<f64>,
    /// Augmented: tolerance relative to the displacement scale.
    pub augmented_tol_rel: Vec<f64>,
    /// Maximum refinement steps.
    pub max_steps: usize,
}

impl Default for StressConfig {
    fn default() -> Self {
        StressConfig {
            eps: (0..=46)
                .map(|k| 10f64.powf(-3.0 + 0.5 * k as f64))
                .collect(),
            factors: vec![1e-12, 1e-6, 1.0, 1e4, 1e8, 1e12, 1e16, 1e20],
            deltas_rel: vec![1e-18, 1e-14, 1e-10, 1e-6, 1e-3, 0.1, 1.0, 1e3, 1e8],
            augmented_eps_rel: vec![1e-9, 1.0, 1e9],
            augmented_tol_rel: vec![1e-15, 1e-6],
            max_steps: 10,
        }
    }
}

/// The exact contact solution (`lagrange`) and the constraints active in it.
pub fn exact_contact(problem: &Problem) -> Result<(Vec<f64>, Vec<bool>)> {
    let sol = strategy::solve(problem, Method::Lagrange)?;
    let mut active = vec![false; problem.m()];
    if let SystemKind::SaddlePoint { active: a } = &sol.system {
        for &c in a {
            active[c] = true;
        }
    }
    Ok((sol.u, active))
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Cond₂ of a matrix, `None` if not computable or infinite.
fn cond_of(a: &Stiffness) -> Option<f64> {
    conditioning::cond2(a).ok().and_then(|c| finite(c.cond2))
}

/// Uniform-ε study on one scene: for each ε, the penalized system `K + ε D_A D_Aᵀ` over the
/// constraints active in the exact contact solution (all of them for bilateral scenes) is
/// solved by every [`SolveOptions::variants`] and compared with the double-double reference
/// and with lagrange; the `constant` strategy is run at the same ε.
pub fn eps_study(scene: &StressScene, cfg: &StressConfig) -> Result<Vec<EpsRow>> {
    let p = &scene.problem;
    // Lagrange may refuse a near-singular K: then every constraint is penalized and the
    // errors against the exact contact solution are left empty.
    let (u_lag, active) = match exact_contact(p) {
        Ok((u, a)) => (Some(u), a),
        Err(_) => (None, vec![true; p.m()]),
    };
    let mut rows = Vec::with_capacity(cfg.eps.len());
    for &eps in &cfg.eps {
        let pen: Vec<f64> = active.iter().map(|&a| if a { eps } else { 0.0 }).collect();
        let sys = PenalizedSystem::new(p, &pen)?;
        let a = sys.matrix();
        let cond2_f64 = cond_of(&a);
        let cond2_scaled = cond_of(&scaled(&a, &equilibration(&a)));
        let cond2 = sys.cond2_extended().ok();
        let reference = sys.reference().ok();
        let mut forward = VariantErrors::default();
        let mut variant_errors = Vec::new();
        let mut steps_extended = None;
        let mut x_plain = None;
        let mut x_best = None;
        for (name, opts) in SolveOptions::variants(cfg.max_steps) {
            match solve(&sys, opts) {
                Ok(r) => {
                    let err = reference
                        .as_ref()
                        .map(|rf| metrics::relative_error(&r.x, &rf.u))
                        .and_then(finite);
                    forward.set(name, err);
                    if name == "refined_extended" {
                        steps_extended = Some(r.steps);
                    }
                    if name == "plain" {
                        x_plain = Some(r.x);
                    } else if name == "equilibrated_refined_extended" {
                        x_best = Some(r.x);
                    }
                }
                Err(e) => variant_errors.push(format!("{name}: {e}")),
            }
        }
        let (outcome, sol) = guarded_solve(p, Method::Constant { eps });
        let strategy_warnings = sol.as_ref().map_or(0, |s| {
            let m = metrics::compute_with_k(
                p,
                s,
                MetricSet {
                    cond: true,
                    det: false,
                },
                None,
            )
            .unwrap_or_default();
            s.warnings.len() + metrics::precision_warnings(&m).len()
        });
        let precision_warning = match cond2 {
            Some(c) => c * f64::EPSILON > metrics::DIGITS_LOST_THRESHOLD,
            None => true,
        };
        rows.push(EpsRow {
            scene: scene.name.clone(),
            family: scene.family.clone(),
            n: p.n(),
            m_active: active.iter().filter(|&&a| a).count(),
            eps,
            cond2,
            cond2_f64,
            cond_eps_mach: cond2.map(|c| c * f64::EPSILON),
            cond2_scaled,
            precision_warning,
            reference_correction: reference.as_ref().map(|r| r.correction).and_then(finite),
            forward,
            variant_errors,
            steps_extended,
            penalty_error: match (&reference, &u_lag) {
                (Some(r), Some(ul)) => finite(metrics::relative_error(&r.u, ul)),
                _ => None,
            },
            total_error_plain: match (&x_plain, &u_lag) {
                (Some(x), Some(ul)) => finite(metrics::relative_error(x, ul)),
                _ => None,
            },
            total_error_refined: match (&x_best, &u_lag) {
                (Some(x), Some(ul)) => finite(metrics::relative_error(x, ul)),
                _ => None,
            },
            strategy_status: outcome.name().into(),
            strategy_message: outcome.message(),
            strategy_max_penetration: sol.as_ref().map(|s| s.max_penetration).and_then(finite),
            strategy_warnings,
        });
    }
    Ok(rows)
}

/// One strategy run of [`strategy_study`].
#[derive(Clone, Debug, Serialize)]
pub struct StrategyRow {
    /// Scene name.
    pub scene: String,
    /// Scene family.
    pub family: String,
    /// N.
    pub n: usize,
    /// m.
    pub m: usize,
    /// Method name.
    pub method: String,
    /// The knob's name (`eps`, `factor`, `delta`, `eps,tol`, `-`).
    pub knob: String,
    /// The knob's value (ε, factor or δ; ε for augmented).
    pub value: f64,
    /// Second knob (augmented tolerance), else `None`.
    pub value2: Option<f64>,
    /// Adaptive augmented.
    pub adaptive: bool,
    /// `ok`, `error`, `non_finite`, `panic`.
    pub status: String,
    /// Error / panic message.
    pub message: String,
    /// Max penetration.
    pub max_penetration: Option<f64>,
    /// Largest penalty used.
    pub max_penalty: Option<f64>,
    /// Exact cond₂ of the final system matrix.
    pub cond2_system: Option<f64>,
    /// cond₂ · ε_mach > [`metrics::DIGITS_LOST_THRESHOLD`].
    pub precision_expected: bool,
    /// The solution's warnings plus [`metrics::precision_warnings`].
    pub warnings: Vec<String>,
    /// `‖u − u*‖/‖u*‖` against the double-double solution of its own penalized system
    /// (penalty strategies except `augmented`, whose final limits are shifted).
    pub forward_error: Option<f64>,
    /// `‖u − u_lagrange‖/‖u_lagrange‖`.
    pub error_vs_lagrange: Option<f64>,
}

/// Every strategy at the knobs of `cfg` (extremes included) on one scene, guarded.
pub fn strategy_study(scene: &StressScene, cfg: &StressConfig) -> Result<Vec<StrategyRow>> {
    let p = &scene.problem;
    let u_lag = exact_contact(p).ok().map(|(u, _)| u);
    let scale = strategy::Prepared::new(p)
        .map(|pr| crate::sweep::displacement_scale(p, pr.u0()))
        .unwrap_or(1.0);
    let kmax = p
        .constraints
        .iter()
        .map(|c| p.k.diag(c.dof).abs())
        .fold(0.0f64, f64::max);
    let kmax = if kmax > 0.0 { kmax } else { 1.0 };
    let mut jobs: Vec<(Method, &'static str, f64, Option<f64>)> = Vec::new();
    for &eps in &cfg.eps {
        jobs.push((Method::Constant { eps }, "eps", eps, None));
    }
    for &factor in &cfg.factors {
        jobs.push((Method::Scaled { factor }, "factor", factor, None));
    }
    for &r in &cfg.deltas_rel {
        let delta = r * scale;
        if delta > 0.0 && delta.is_finite() {
            jobs.push((Method::Spring { delta }, "delta", delta, None));
            jobs.push((Method::Paper { delta }, "delta", delta, None));
            jobs.push((Method::Condensed { delta }, "delta", delta, None));
        }
    }
    for &er in &cfg.augmented_eps_rel {
        for &tr in &cfg.augmented_tol_rel {
            for adaptive in [false, true] {
                let (eps, tol) = (er * kmax, tr * scale);
                jobs.push((
                    Method::Augmented { eps, tol, adaptive },
                    "eps,tol",
                    eps,
                    Some(tol),
                ));
            }
        }
    }
    jobs.push((Method::Lagrange, "-", 0.0, None));
    let mut rows = Vec::with_capacity(jobs.len());
    for (method, knob, value, value2) in jobs {
        let (outcome, sol) = guarded_solve(p, method);
        let mut warnings = Vec::new();
        let mut cond2_system = None;
        let mut forward_error = None;
        if let Some(s) = &sol {
            warnings.extend(s.warnings.iter().cloned());
            if let Ok(m) = metrics::compute_with_k(
                p,
                s,
                MetricSet {
                    cond: true,
                    det: false,
                },
                None,
            ) {
                cond2_system = m.cond2_system.map(|c| c.cond2).and_then(finite);
                warnings.extend(metrics::precision_warnings(&m));
            }
            let penalty_method = !matches!(method, Method::Lagrange | Method::Augmented { .. });
            if penalty_method && outcome.name() == "ok" {
                forward_error = PenalizedSystem::new(p, &s.penalties)
                    .and_then(|sys| sys.reference())
                    .ok()
                    .map(|r| metrics::relative_error(&s.u, &r.u))
                    .and_then(finite);
            }
        }
        let precision_expected =
            cond2_system.is_some_and(|c| c * f64::EPSILON > metrics::DIGITS_LOST_THRESHOLD);
        rows.push(StrategyRow {
            scene: scene.name.clone(),
            family: scene.family.clone(),
            n: p.n(),
            m: p.m(),
            method: method.name().into(),
            knob: knob.into(),
            value,
            value2,
            adaptive: matches!(method, Method::Augmented { adaptive: true, .. }),
            status: outcome.name().into(),
            message: outcome.message(),
            max_penetration: sol.as_ref().map(|s| s.max_penetration).and_then(finite),
            max_penalty: sol
                .as_ref()
                .map(|s| s.penalties.iter().fold(0.0f64, |a, v| a.max(*v)))
                .and_then(finite),
            cond2_system,
            precision_expected,
            warnings,
            forward_error,
            error_vs_lagrange: match (&sol, &u_lag) {
                (Some(s), Some(ul)) => finite(metrics::relative_error(&s.u, ul)),
                _ => None,
            },
        });
    }
    Ok(rows)
}

/// The stress scenes: the paper's beam (bilateral, and with `upper` obstacles), then `count`
/// generated scenes per family with sizes small enough for the dense double-double reference
/// (beams of 3–12 elements, a 10×10 membrane, spectrum matrices of N = 8–40 with eigenvalue
/// spreads 10¹⁰–10¹⁶).
pub fn stress_scenes(seed: u64, count: usize, families: &[String]) -> Result<Vec<StressScene>> {
    use crate::sweep::generate::{generate, Family, GeneratorConfig};
    let mut out = vec![
        StressScene {
            name: "paper-beam".into(),
            family: "paper".into(),
            problem: crate::model::beam::paper::problem(),
        },
        StressScene {
            name: "paper-beam-upper".into(),
            family: "paper".into(),
            problem: crate::model::beam::paper::problem_with_kind(ConstraintKind::Upper),
        },
    ];
    let cfg = GeneratorConfig {
        beam_elements: (3, 12),
        membrane_side: (10, 10),
        spectrum_n: (8, 40),
        spectrum_log10_spread: (10.0, 16.0),
    };
    for f in families {
        let family = Family::from_name(f)?;
        for i in 0..count {
            let g = generate(family, i, seed, &cfg)?;
            out.push(StressScene {
                name: g.name,
                family: family.name().into(),
                problem: g.problem,
            });
        }
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------
// Figures
// ---------------------------------------------------------------------------------------

/// Errors below this are drawn at this value on log axes (an exactly zero error has no
/// logarithm); the CSV keeps the raw values.
pub const PLOT_FLOOR: f64 = 1e-17;

fn floored(v: Option<f64>) -> f64 {
    v.map_or(f64::NAN, |x| x.max(PLOT_FLOOR))
}

/// Labels of the five solve variants in figures.
pub fn variant_label(name: &str) -> &'static str {
    match name {
        "plain" => "f64 Cholesky",
        "refined_working" => "+ refinement, f64 residual",
        "refined_extended" => "+ refinement, extended residual",
        "equilibrated" => "equilibrated",
        _ => "equilibrated + extended refinement",
    }
}

/// Figures of the ε study: per scene, forward error against ε for every variant with the
/// cond₂·ε_mach bound; per scene, error against the exact contact solution (penalty model
/// error, plain f64 total error, refined total error); and forward error against cond₂ over
/// all scenes.
pub fn figures(rows: &[EpsRow]) -> Vec<(String, Figure)> {
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let mut figs = Vec::new();
    for sc in &scenes {
        let rs: Vec<&EpsRow> = rows.iter().filter(|r| r.scene == *sc).collect();
        let x: Vec<f64> = rs.iter().map(|r| r.eps).collect();
        let mut fig = Figure::new(
            format!("Forward error vs penalty ε — {sc} (N = {})", rs[0].n),
            "uniform penalty ε",
            "‖u − u*‖ / ‖u*‖  (u* exact, double-double; 0 drawn at 1e-17)",
        )
        .scales(Scale::Log10, Scale::Log10);
        let get = |r: &EpsRow, name: &str| -> Option<f64> {
            r.forward
                .pairs()
                .iter()
                .find(|(n, _)| *n == name)
                .and_then(|p| p.1)
        };
        for (i, name, mark) in [
            (0, "plain", Mark::LinePoints),
            (1, "refined_working", Mark::Line),
            (2, "refined_extended", Mark::LinePoints),
        ] {
            let y: Vec<f64> = rs.iter().map(|r| floored(get(r, name))).collect();
            fig = fig.with_series(Series::new(variant_label(name), x.clone(), y, mark).color(i));
        }
        // Equilibrated Cholesky equals the plain one bit for bit wherever the plain
        // factorization is accepted: drawn only where it is refused.
        for (i, name) in [(3, "equilibrated"), (4, "equilibrated_refined_extended")] {
            let y: Vec<f64> = rs
                .iter()
                .map(|r| {
                    if r.forward.plain.is_none() {
                        floored(get(r, name))
                    } else {
                        f64::NAN
                    }
                })
                .collect();
            if y.iter().any(|v| v.is_finite()) {
                let label = format!("{} (where plain is refused)", variant_label(name));
                fig = fig.with_series(Series::new(label, x.clone(), y, Mark::Points).color(i));
            }
        }
        let bound: Vec<f64> = rs.iter().map(|r| floored(r.cond_eps_mach)).collect();
        fig =
            fig.with_series(Series::new("cond₂ · ε_mach", x.clone(), bound, Mark::Dashed).color(6));
        figs.push((format!("forward_error_vs_eps_{sc}"), fig));

        let fig = Figure::new(
            format!("Error vs exact contact solution — {sc}"),
            "uniform penalty ε",
            "‖u − u_lagrange‖ / ‖u_lagrange‖",
        )
        .scales(Scale::Log10, Scale::Log10)
        .with_series(
            Series::new(
                "penalty model error (exact u*)",
                x.clone(),
                rs.iter().map(|r| floored(r.penalty_error)).collect(),
                Mark::Dashed,
            )
            .color(6),
        )
        .with_series(
            Series::new(
                "f64 Cholesky",
                x.clone(),
                rs.iter().map(|r| floored(r.total_error_plain)).collect(),
                Mark::LinePoints,
            )
            .color(0),
        )
        .with_series(
            Series::new(
                "equilibrated + extended refinement",
                x.clone(),
                rs.iter().map(|r| floored(r.total_error_refined)).collect(),
                Mark::Line,
            )
            .color(4),
        );
        figs.push((format!("error_vs_lagrange_{sc}"), fig));
    }
    // Forward error against cond₂, all scenes.
    let mut fig = Figure::new(
        "Forward error vs exact cond₂, all scenes and ε",
        "cond₂(K + ε D Dᵀ)",
        "‖u − u*‖ / ‖u*‖",
    )
    .scales(Scale::Log10, Scale::Log10);
    for (i, name) in ["plain", "refined_extended", "equilibrated_refined_extended"]
        .iter()
        .enumerate()
    {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let e = r.forward.pairs().iter().find(|(n, _)| n == name)?.1?;
                Some((r.cond2?, e.max(PLOT_FLOOR)))
            })
            .collect();
        fig = fig.with_series(
            Series::new(
                variant_label(name),
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
                Mark::Points,
            )
            .color([0, 2, 4][i]),
        );
    }
    let mut cs: Vec<f64> = rows.iter().filter_map(|r| r.cond2).collect();
    cs.sort_by(f64::total_cmp);
    cs.dedup();
    if !cs.is_empty() {
        let xs = vec![cs[0], cs[cs.len() - 1]];
        let ys = xs
            .iter()
            .map(|c| (c * f64::EPSILON).max(PLOT_FLOOR))
            .collect();
        fig = fig.with_series(Series::new("cond₂ · ε_mach", xs, ys, Mark::Dashed).color(6));
    }
    figs.push(("forward_error_vs_cond".into(), fig));
    // The same errors against cond₂ of the equilibrated matrix.
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.cond2_scaled?, r.forward.plain?.max(PLOT_FLOOR))))
        .collect();
    if !pts.is_empty() {
        let lo = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|p| p.0).fold(0.0f64, f64::max);
        let fig = Figure::new(
            "Forward error of f64 Cholesky vs cond₂ of the equilibrated matrix",
            "cond₂(S A S), S = diag(2^k) ≈ diag(A)^(-1/2)",
            "‖u − u*‖ / ‖u*‖",
        )
        .scales(Scale::Log10, Scale::Log10)
        .with_series(
            Series::new(
                variant_label("plain"),
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
                Mark::Points,
            )
            .color(0),
        )
        .with_series(
            Series::new(
                "cond₂(SAS) · ε_mach",
                vec![lo, hi],
                vec![
                    (lo * f64::EPSILON).max(PLOT_FLOOR),
                    (hi * f64::EPSILON).max(PLOT_FLOOR),
                ],
                Mark::Dashed,
            )
            .color(6),
        );
        figs.push(("forward_error_vs_scaled_cond".into(), fig));
    }
    figs
}
