//! Small dense helpers, independent of the library's linear algebra (nalgebra), shared by the
//! tests that recompute results on their own.

use nalgebra::DMatrix;
use penalty_lab::system::Stiffness;

/// K as a nalgebra matrix (entries summed, dense or sparse storage alike).
pub fn dense(k: &Stiffness) -> DMatrix<f64> {
    let n = k.n();
    let mut m = DMatrix::zeros(n, n);
    k.for_each_entry(|i, j, v| m[(i, j)] += v);
    m
}

/// ‖v‖∞.
pub fn inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}
