//! A reference solution of a stored linear system `A x = b` beyond double precision:
//! iterative refinement with double-double residuals (Wilkinson 1963; Moler 1967; Higham,
//! *Accuracy and Stability*, §12.1).
//!
//! `x₀` = the plain f64 solve; then repeatedly `r = b − A x` in double-double (A and b as
//! stored, exactly; x kept as a double-double vector), `d = A⁻¹r` by the same f64
//! factorization, `x ← x + d` in double-double. While `ε_mach·cond(A) < 1/2` each step
//! contracts the error by about `ε_mach·cond(A)` (Higham, Thm. 12.1), down to the level of the
//! residual's own error, about `u_dd·cond(A)` with `u_dd ≈ 1e-32`. The run stops when a
//! correction is below 10⁻²⁷ of ‖x‖∞, when corrections stop shrinking (by half) or after 30
//! steps; [`Refined::accuracy`] is the last correction relative to ‖x‖∞, an estimate of the
//! reference's relative error (an overestimate once the steps contract), and
//! [`Refined::converged`] says it is ≤ 10⁻²⁰.
//!
//! Tested against exact solutions of integer systems (`tests`) and, through the forward errors
//! it measures, against mpmath's LU solve at 50 digits (`tests/verification/solver_cost.rs`).

use super::Factorization;
use crate::dd::Dd;
use crate::system::Stiffness;

/// Largest number of refinement steps.
pub const MAX_STEPS: usize = 30;
/// A reference whose last correction is at most this (relative, ∞-norm) is converged.
pub const CONVERGED: f64 = 1e-20;

/// A refined solution.
#[derive(Clone, Debug)]
pub struct Refined {
    /// The solution, in double-double.
    pub x: Vec<Dd>,
    /// Refinement steps done.
    pub steps: usize,
    /// `‖d_last‖∞ / ‖x‖∞`: the estimated relative error of `x` (module doc).
    pub accuracy: f64,
    /// `accuracy ≤ 1e-20`.
    pub converged: bool,
}

/// `b − A x` in double-double: every product `a_ij·x_j` exact (two f64 products), every sum
/// double-double.
pub fn residual_dd(a: &Stiffness, x: &[Dd], b: &[f64]) -> Vec<Dd> {
    let mut r: Vec<Dd> = b.iter().map(|&v| Dd::from_f64(v)).collect();
    a.for_each_entry(|i, j, v| {
        r[i] = r[i] - Dd::prod(v, x[j].hi) - Dd::prod(v, x[j].lo);
    });
    r
}

/// `max |x_i|` (0 for no entries).
pub fn inf_norm(x: impl Iterator<Item = f64>) -> f64 {
    x.fold(0.0, |m, v| m.max(v.abs()))
}

/// Refines `x0` (the plain solve by `factor`, a factorization of `a`) into a reference
/// solution of the stored `a x = b` (module doc).
pub fn refine(a: &Stiffness, b: &[f64], factor: &Factorization, x0: &[f64]) -> Refined {
    let mut x: Vec<Dd> = x0.iter().map(|&v| Dd::from_f64(v)).collect();
    let mut out = Refined {
        x: Vec::new(),
        steps: 0,
        accuracy: f64::INFINITY,
        converged: false,
    };
    let mut prev = f64::INFINITY;
    for _ in 0..MAX_STEPS {
        let r = residual_dd(a, &x, b);
        let mut d: Vec<f64> = r.iter().map(|v| v.to_f64()).collect();
        factor.solve_vec_in_place(&mut d);
        if d.iter().any(|v| !v.is_finite()) {
            break;
        }
        let dn = inf_norm(d.iter().copied());
        for (x, d) in x.iter_mut().zip(&d) {
            *x = *x + Dd::from_f64(*d);
        }
        out.steps += 1;
        let xn = inf_norm(x.iter().map(|v| v.hi));
        out.accuracy = if dn == 0.0 { 0.0 } else { dn / xn };
        if out.accuracy <= 1e-27 || dn > 0.5 * prev {
            break;
        }
        prev = dn;
    }
    out.converged = out.accuracy <= CONVERGED;
    out.x = x;
    out
}

/// `‖x̂ − x_ref‖∞ / ‖x_ref‖∞` with the difference formed in double-double (absolute when
/// `x_ref = 0`).
pub fn relative_error_dd(x: &[f64], x_ref: &[Dd]) -> f64 {
    let num = inf_norm(
        x.iter()
            .zip(x_ref)
            .map(|(&a, &r)| (Dd::from_f64(a) - r).to_f64()),
    );
    let den = inf_norm(x_ref.iter().map(|v| v.hi));
    if den > 0.0 {
        num / den
    } else {
        num
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A graded integer system with an exactly known solution: the 1-D Laplacian with a
    /// penalty 2⁴⁰ on one diagonal entry; x* integer, so b = A x* is exact in f64.
    fn system(n: usize) -> (Stiffness, Vec<f64>, Vec<f64>) {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0 + if i == n / 3 { 2f64.powi(40) } else { 0.0 }));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let a = Stiffness::from_triplets(n, &t).unwrap();
        let x: Vec<f64> = (0..n).map(|i| ((i * 37) % 11) as f64 - 5.0).collect();
        let b = a.matvec(&x);
        (a, b, x)
    }

    #[test]
    fn refinement_recovers_an_exact_integer_solution() {
        let (a, b, exact) = system(200);
        let f = Factorization::new(&a, true).unwrap();
        let x0 = f.solve(&b);
        let exact_dd: Vec<Dd> = exact.iter().map(|&v| Dd::from_f64(v)).collect();
        let plain = relative_error_dd(&x0, &exact_dd);
        // The plain solve loses digits to the penalty (cond ≈ 2⁴⁰·n²/π²), so the test means
        // something: its error is far above the reference's.
        assert!(plain > 1e-15, "plain solve error {plain:e}");
        let r = refine(&a, &b, &f, &x0);
        assert!(r.converged, "{r:?}");
        let ref_err = inf_norm(
            r.x.iter()
                .zip(&exact)
                .map(|(x, &e)| (*x - Dd::from_f64(e)).to_f64()),
        ) / 5.0;
        assert!(ref_err <= 1e-24, "reference error {ref_err:e}");
        assert!(r.accuracy <= CONVERGED);
    }

    #[test]
    fn residual_dd_of_the_exact_solution_is_zero() {
        let (a, b, exact) = system(50);
        let x: Vec<Dd> = exact.iter().map(|&v| Dd::from_f64(v)).collect();
        assert!(residual_dd(&a, &x, &b)
            .iter()
            .all(|r| r.hi == 0.0 && r.lo == 0.0));
    }
}
