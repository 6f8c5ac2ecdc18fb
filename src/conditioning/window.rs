//! The r largest eigenpairs of a symmetric positive semidefinite operator (a "window" at the
//! top of its spectrum), for the sparse route of `strategy::optimal`, which needs them at
//! every evaluation of a smooth function of the spectrum, for matrices that change a little
//! from one evaluation to the next.
//!
//! Lanczos with full reorthogonalization (classical Gram–Schmidt, two passes: "twice is
//! enough"), started from the previous window's vectors plus a fixed dense vector (every
//! component nonzero, so an eigenvalue that moves into the window is found), Ritz pairs from
//! faer's dense eigensolver of the tridiagonal `T_k` every [`CHECK`] steps, stopped when the
//! window's Ritz residuals `β_k |s_{k,i}| = ‖A y_i − θ_i y_i‖` are all ≤ `tol · θ₁`, at a
//! breakdown (an invariant Krylov subspace: the Ritz pairs are then exact), or at
//! `max_steps`.
//!
//! Written here rather than taken from faer: `matrix_free::eigen::partial_self_adjoint_eigen`
//! (faer 0.24) repeats its reorthogonalization without a pass limit and looped forever on a
//! 90-DOF beam whose Krylov subspace became numerically invariant (observed in this
//! project), and it takes one start vector where a warm start needs the whole window.

use super::lanczos::{start_vector, WINDOW_MIX};
use super::tridiagonal::tridiagonal_dense;
use faer::linalg::matmul::matmul;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Col, ColRef, Mat, Par, Side};

/// Lanczos steps between two Ritz checks.
pub const CHECK: usize = 8;

/// The window found: Ritz values `values[i]` (largest first) and unit Ritz vectors
/// `vectors[i]`.
pub struct Window {
    /// Ritz values, largest first.
    pub values: Vec<f64>,
    /// Unit Ritz vectors, in the order of `values`.
    pub vectors: Vec<Vec<f64>>,
    /// Lanczos steps (operator applications).
    pub steps: usize,
    /// Every window residual ≤ tol·θ₁ (or an invariant subspace was reached).
    pub converged: bool,
}

/// The `r` largest eigenpairs of the symmetric positive semidefinite operator `apply`
/// (`y ← A x`) of dimension `n` (module docs); `warm`: vectors to start from (the previous
/// window), may be empty. None if the operator returned a non-finite value or the
/// tridiagonal's eigensolver failed.
pub fn top_window(
    apply: &mut dyn FnMut(&[f64], &mut [f64]),
    n: usize,
    r: usize,
    warm: &[Vec<f64>],
    tol: f64,
    max_steps: usize,
) -> Option<Window> {
    let r = r.min(n).max(1);
    let max_steps = max_steps.clamp(r, n);
    let mut sum = vec![0.0; n];
    for v in warm {
        for (s, x) in sum.iter_mut().zip(v) {
            *s += x;
        }
    }
    let q0 = start_vector(n, (!warm.is_empty()).then_some(&sum[..]), WINDOW_MIX);
    // Lanczos vectors as the columns of one matrix: the reorthogonalization is two
    // matrix-vector products per pass (faer), c = Vᵀw and w ← w − V c.
    let mut basis = Mat::<f64>::zeros(n, max_steps);
    basis.col_mut(0).copy_from(ColRef::from_slice(&q0));
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    let mut w = Col::<f64>::zeros(n);
    let mut c = Col::<f64>::zeros(max_steps);
    let mut k = 0;
    loop {
        apply(
            basis
                .col(k)
                .try_as_col_major()
                .expect("contiguous")
                .as_slice(),
            w.try_as_col_major_mut().expect("contiguous").as_slice_mut(),
        );
        let a = basis.col(k).transpose() * &w;
        alpha.push(a);
        k += 1;
        let v = basis.as_ref().subcols(0, k);
        for _ in 0..2 {
            let mut ck = c.as_mut().subrows_mut(0, k);
            matmul(
                ck.rb_mut(),
                Accum::Replace,
                v.transpose(),
                w.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(w.as_mut(), Accum::Add, v, ck.rb(), -1.0, Par::Seq);
        }
        let b = w.norm_l2();
        let scale = alpha
            .iter()
            .chain(&beta)
            .fold(0.0f64, |m: f64, x: &f64| m.max(x.abs()));
        if !(a.is_finite() && b.is_finite()) {
            return None;
        }
        let breakdown = b <= 1e3 * f64::EPSILON * scale;
        if breakdown || k == max_steps || (k >= r && (k - r).is_multiple_of(CHECK)) {
            let (values, s) = ritz(&alpha, &beta, r)?;
            let top = values[0].abs().max(f64::MIN_POSITIVE);
            let done = breakdown || s.iter().all(|si| b * si[k - 1].abs() <= tol * top);
            if done || k == max_steps {
                let vectors = s
                    .iter()
                    .map(|si| {
                        let y = v * ColRef::from_slice(si);
                        let ny = y.norm_l2();
                        y.iter().map(|x| x / ny).collect()
                    })
                    .collect();
                return Some(Window {
                    values,
                    vectors,
                    steps: k,
                    converged: done,
                });
            }
        }
        beta.push(b);
        let mut next = basis.col_mut(k);
        next.copy_from(&w);
        next *= faer::Scale(1.0 / b);
    }
}

/// The `r` largest eigenvalues of the tridiagonal `T_k` (diagonal `a`, off-diagonal `b`) and
/// their unit eigenvectors, largest first (faer's dense symmetric eigensolver; None if it
/// fails).
fn ritz(a: &[f64], b: &[f64], r: usize) -> Option<(Vec<f64>, Vec<Vec<f64>>)> {
    let k = a.len();
    let evd = tridiagonal_dense(a, b)
        .self_adjoint_eigen(Side::Lower)
        .ok()?;
    let (u, s) = (evd.U(), evd.S().column_vector());
    Some(
        (0..r.min(k))
            .map(|i| k - 1 - i)
            .map(|c| (s[c], (0..k).map(|row| u[(row, c)]).collect()))
            .unzip(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_top_of_a_known_spectrum_and_stops_at_an_invariant_subspace() {
        // Diagonal operator with eigenvalues 1..=n: the window is n, n−1, ..., exact.
        let n = 200;
        let mut apply = |x: &[f64], y: &mut [f64]| {
            for i in 0..n {
                y[i] = (i + 1) as f64 * x[i];
            }
        };
        let w = top_window(&mut apply, n, 5, &[], 1e-10, 200).unwrap();
        assert!(w.converged);
        for (i, v) in w.values.iter().enumerate() {
            let exact = (n - i) as f64;
            assert!((v - exact).abs() <= 1e-9 * n as f64, "{v} vs {exact}");
            // The Ritz vector is the unit vector e_{n−1−i} up to sign.
            assert!((w.vectors[i][n - 1 - i].abs() - 1.0).abs() < 1e-6);
        }
        // A start inside a 3-dimensional invariant subspace breaks down after 3 steps (the
        // loop that a reorthogonalization without a pass limit would not leave).
        let mut warm = vec![vec![0.0; n]; 3];
        for (j, v) in warm.iter_mut().enumerate() {
            v[n - 1 - j] = 1.0;
        }
        let mut apply3 = |x: &[f64], y: &mut [f64]| {
            for i in 0..n {
                y[i] = if i >= n - 3 {
                    (i + 1) as f64 * x[i]
                } else {
                    0.0
                };
            }
        };
        let w = top_window(&mut apply3, n, 3, &warm, 1e-10, 200).unwrap();
        assert!(w.converged && w.steps <= 5, "{} steps", w.steps);
        assert!((w.values[0] - n as f64).abs() <= 1e-9 * n as f64);
    }
}
