//! f64 solves of a penalized system with iterative refinement (working or extended
//! residual) and power-of-two equilibration.

use super::*;
use crate::error::Result;
use crate::linalg::Factorization;
use crate::system::Stiffness;
use serde::Serialize;

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
/// `ε_mach ‖x‖`. Errors: [`Error::Singular`](crate::error::Error::Singular) when the (scaled) matrix fails the factorization's
/// singularity test.
pub fn solve(sys: &PenalizedSystem, opts: SolveOptions) -> Result<RefinedSolve> {
    let a = sys.matrix();
    let b = sys.rhs();
    let symmetric = a.is_symmetric();
    let (s, f) = if opts.equilibrate {
        let s = a.equilibration();
        let f = Factorization::new(&a.scaled(&s), symmetric)?;
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
