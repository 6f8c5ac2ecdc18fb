//! The membrane stiffness: 5-point finite differences of `−T Δu` on `side × side` interior
//! nodes of the unit square (Dirichlet boundary), scaled by h² so that
//!
//! `K = T · tridiag-block(−1, 4, −1)`, `λ_jk = T (4 − 2 cos jπh − 2 cos kπh)`, h = 1/(side+1).
//!
//! Node (i, j) is DOF `i·side + j`. Used by the sweep's `membrane` family, the exact-cond tests
//! and benchmarks; the closed-form spectrum makes it the reference sparse SPD matrix.

use crate::error::Result;
use crate::system::Stiffness;

/// DOF of interior node (i, j).
pub fn dof(side: usize, i: usize, j: usize) -> usize {
    i * side + j
}

/// The sparse stiffness `K` (N = side²) for tension `T`.
pub fn stiffness(side: usize, tension: f64) -> Result<Stiffness> {
    let n = side * side;
    let mut t = Vec::with_capacity(5 * n);
    for i in 0..side {
        for j in 0..side {
            let r = dof(side, i, j);
            t.push((r, r, 4.0 * tension));
            if i > 0 {
                t.push((r, dof(side, i - 1, j), -tension));
            }
            if i + 1 < side {
                t.push((r, dof(side, i + 1, j), -tension));
            }
            if j > 0 {
                t.push((r, dof(side, i, j - 1), -tension));
            }
            if j + 1 < side {
                t.push((r, dof(side, i, j + 1), -tension));
            }
        }
    }
    Stiffness::from_triplets(n, &t)
}

/// `(λ_min, λ_max)` in closed form.
pub fn extreme_eigenvalues(side: usize, tension: f64) -> (f64, f64) {
    let h = std::f64::consts::PI / (side as f64 + 1.0);
    (
        tension * (4.0 - 4.0 * h.cos()),
        tension * (4.0 - 4.0 * (side as f64 * h).cos()),
    )
}
