//! The penalized system `(K + D E Dᵀ) u = q + D E ℓ` formed exactly, and its
//! extended-precision reference solution.

use super::dd::DdLu;
use super::*;
use crate::error::{Error, Result};
use crate::strategy;
use crate::system::{Problem, Stiffness};
use serde::Serialize;

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
            let (what, got) = if penalties.len() != m {
                ("penalized system: the penalties", penalties.len())
            } else {
                ("penalized system: the limits", limits.len())
            };
            return Err(Error::length_mismatch(
                format!("{what} (one per constraint)"),
                got,
                m,
            ));
        }
        if let Some(c) = penalties.iter().position(|e| !(e.is_finite() && *e >= 0.0)) {
            return Err(Error::out_of_range(
                format!("penalized system: penalty {c}"),
                penalties[c],
                "a finite ε ≥ 0",
            ));
        }
        if let Some(c) = limits.iter().position(|l| !l.is_finite()) {
            return Err(Error::not_finite(format!("penalized system: limit {c}")));
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
            c.scatter(&mut b, e * l);
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
                    match (e != 0.0, c.single_dof()) {
                        (false, _) => {}
                        (true, Some(d)) => r[d] = r[d] + Dd::prod(e, l) - Dd::prod(e, x[d]),
                        (true, None) => {
                            // r += e·d_c·(ℓ − d_cᵀx), every product in double-double.
                            let gx = c
                                .terms
                                .iter()
                                .fold(Dd::ZERO, |s, &(j, a)| s + Dd::prod(a, x[j]));
                            let t = Dd::prod(e, l) - Dd::from_f64(e) * gx;
                            for &(i, a) in &c.terms {
                                r[i] = r[i] + Dd::from_f64(a) * t;
                            }
                        }
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
            return Err(Error::out_of_range(
                "N of the extended-precision reference",
                n,
                format!("≤ {REFERENCE_MAX_N}"),
            ));
        }
        let mut a = vec![Dd::ZERO; n * n];
        p.k.for_each_entry(|i, j, v| a[i * n + j] = a[i * n + j] + Dd::from_f64(v));
        let mut b: Vec<Dd> = p.q.iter().map(|&v| Dd::from_f64(v)).collect();
        for ((c, &e), &l) in p.constraints.iter().zip(&self.penalties).zip(&self.limits) {
            match (e != 0.0, c.single_dof()) {
                (false, _) => {}
                (true, Some(d)) => {
                    a[d * n + d] = a[d * n + d] + Dd::from_f64(e);
                    b[d] = b[d] + Dd::prod(e, l);
                }
                (true, None) => {
                    for &(i, ai) in &c.terms {
                        for &(j, aj) in &c.terms {
                            a[i * n + j] = a[i * n + j] + Dd::prod(e, ai) * Dd::from_f64(aj);
                        }
                        b[i] = b[i] + Dd::prod(e, l) * Dd::from_f64(ai);
                    }
                }
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
