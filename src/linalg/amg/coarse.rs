//! The coarsest level's solve (module doc of [`super`], step 5): PyAMG's `pinv`, or a sparse
//! Cholesky factorization above [`super::MAX_DENSE_COARSE`] unknowns.

use super::{Csr, MAX_DENSE_COARSE};
use crate::error::Result;
use crate::linalg::Factorization;

/// The coarsest level's solver (module doc, step 5).
pub(super) enum Coarse {
    /// The dense pseudo-inverse, row-major.
    Pinv { n: usize, m: Vec<f64> },
    /// A sparse Cholesky factorization.
    Factor(Box<Factorization>),
}

impl Coarse {
    pub(super) fn new(a: &Csr) -> Result<Coarse> {
        let n = a.n_rows;
        if n > MAX_DENSE_COARSE {
            return Ok(Coarse::Factor(Box::new(Factorization::new(
                &a.to_stiffness()?,
                true,
            )?)));
        }
        let mut d = nalgebra::DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for (j, v) in a.row(i) {
                d[(i, j)] = v;
            }
        }
        let eig = d.symmetric_eigen();
        if eig.eigenvalues.iter().any(|v| !v.is_finite()) {
            return Err(crate::error::Error::Numerical(
                "AMG: the coarsest matrix has a non-finite eigenvalue".into(),
            ));
        }
        let top = eig.eigenvalues.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let cut = n as f64 * f64::EPSILON * top;
        let mut m = vec![0.0; n * n];
        for (k, &lam) in eig.eigenvalues.iter().enumerate() {
            // Signed: a rounding-negative eigenvalue is dropped too, so the pseudo-inverse
            // stays positive semidefinite and the V-cycle symmetric positive definite.
            if lam <= cut {
                continue;
            }
            let q = eig.eigenvectors.column(k);
            for i in 0..n {
                let qi = q[i] / lam;
                for j in 0..n {
                    m[i * n + j] += qi * q[j];
                }
            }
        }
        Ok(Coarse::Pinv { n, m })
    }

    pub(super) fn solve(&self, b: &[f64], x: &mut [f64]) {
        match self {
            Coarse::Factor(f) => x.copy_from_slice(&f.solve(b)),
            Coarse::Pinv { n, m } => {
                for (i, xi) in x.iter_mut().enumerate() {
                    *xi = m[i * n..(i + 1) * n]
                        .iter()
                        .zip(b)
                        .map(|(a, b)| a * b)
                        .sum();
                }
            }
        }
    }
}
