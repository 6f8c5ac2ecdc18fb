//! Preconditioners for the Krylov solvers of [`super::krylov`]: Jacobi (`M = diag(A)`) and
//! incomplete Cholesky with zero fill, IC(0) (Meijerink & van der Vorst 1977): `M = L Lᵀ`
//! with L on the pattern of A's lower triangle, the entries Cholesky would compute there and
//! every fill-in dropped.
//!
//! IC(0) can break down on an SPD matrix that is not an M-matrix (a pivot ≤ 0). Then, as
//! Manteuffel (1980) proposed, it factors `A + α·diag(A)` instead, with α = 10⁻³ doubled until
//! every pivot is positive; the shift used is [`Ic0::shift`] (0 when none was needed). A
//! pivot counts as broken down when it is ≤ ε_mach times the original diagonal entry.
//!
//! Why hand-written: faer 0.24 has no incomplete factorizations; the crates that have one
//! (e.g. `sprs`'s ecosystem) do not expose IC(0) on faer's CSC matrices, and it is 60 lines.

use super::krylov::Preconditioner;
use crate::error::{Error, Result};
use faer::sparse::SparseColMatRef;

/// `M = diag(d)`, applied as `z = d⁻¹ ∘ r`.
#[derive(Clone, Debug)]
pub struct Jacobi {
    inv: Vec<f64>,
}

impl Jacobi {
    /// Jacobi of A: errors if a diagonal entry is ≤ 0 or not finite (M must be SPD).
    pub fn new(a: SparseColMatRef<'_, usize, f64>) -> Result<Jacobi> {
        Jacobi::from_inverse_diagonal(diagonal(a)?.iter().map(|d| 1.0 / d).collect())
    }

    /// `M⁻¹ = diag(inv)`: errors unless every entry is positive and finite.
    pub fn from_inverse_diagonal(inv: Vec<f64>) -> Result<Jacobi> {
        if let Some(i) = inv.iter().position(|&v| !(v > 0.0 && v.is_finite())) {
            return Err(Error::NotPositive {
                name: format!("Jacobi preconditioner: entry {i} of diag(M)⁻¹"),
                value: inv[i],
            });
        }
        Ok(Jacobi { inv })
    }
}

impl Preconditioner for Jacobi {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        z.iter_mut()
            .zip(r)
            .zip(&self.inv)
            .for_each(|((z, r), d)| *z = r * d);
    }
}

/// The diagonal of A; errors on an entry ≤ 0 or not finite.
pub fn diagonal(a: SparseColMatRef<'_, usize, f64>) -> Result<Vec<f64>> {
    let (cp, ri, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let d: Vec<f64> = (0..a.ncols())
        .map(|j| {
            (cp[j]..cp[j + 1])
                .find(|&p| ri[p] == j)
                .map_or(0.0, |p| v[p])
        })
        .collect();
    if let Some(i) = d.iter().position(|&x| !(x > 0.0 && x.is_finite())) {
        return Err(Error::NotPositive {
            name: format!("diagonal entry {i} (for Jacobi scaling)"),
            value: d[i],
        });
    }
    Ok(d)
}

/// IC(0): `L` (lower triangle with diagonal, compressed columns, rows sorted, the diagonal
/// first in each column) with `L Lᵀ ≈ A + shift·diag(A)`.
#[derive(Clone, Debug)]
pub struct Ic0 {
    col_ptr: Vec<usize>,
    row: Vec<usize>,
    val: Vec<f64>,
    /// The Manteuffel shift α used (module doc); 0 when A itself factored.
    pub shift: f64,
}

impl Ic0 {
    /// IC(0) of the symmetric A (both triangles stored, rows sorted); errors on a diagonal
    /// entry ≤ 0 or not finite, or when no shift up to α = 10³ gives positive pivots.
    pub fn new(a: SparseColMatRef<'_, usize, f64>) -> Result<Ic0> {
        let diag = diagonal(a)?;
        let mut shift = 0.0;
        loop {
            if let Some(ic) = Ic0::with_shift(a, &diag, shift) {
                return Ok(ic);
            }
            shift = if shift == 0.0 { 1e-3 } else { 2.0 * shift };
            if shift > 1e3 {
                return Err(Error::Numerical(
                    "IC(0) broke down for every diagonal shift up to 1e3·diag(A)".into(),
                ));
            }
        }
    }

    /// IC(0) of `A + shift·diag(A)`, `None` at a breakdown.
    fn with_shift(a: SparseColMatRef<'_, usize, f64>, diag: &[f64], shift: f64) -> Option<Ic0> {
        let n = a.ncols();
        let (cp, ri, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
        let mut ic = Ic0 {
            col_ptr: Vec::with_capacity(n + 1),
            row: Vec::new(),
            val: Vec::new(),
            shift,
        };
        ic.col_ptr.push(0);
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                if ri[p] >= j {
                    ic.row.push(ri[p]);
                    ic.val
                        .push(v[p] + if ri[p] == j { shift * diag[j] } else { 0.0 });
                }
            }
            ic.col_ptr.push(ic.row.len());
        }
        ic.factor(diag).then_some(ic)
    }

    /// Right-looking IC(0) in place; false at a pivot ≤ ε_mach·diag (breakdown).
    fn factor(&mut self, diag: &[f64]) -> bool {
        let n = self.col_ptr.len() - 1;
        let (cp, ri) = (&self.col_ptr, &self.row);
        let val = &mut self.val;
        // pos[i]: index of row i in the column being updated (valid while stamp[i] == j).
        let (mut pos, mut stamp) = (vec![0usize; n], vec![usize::MAX; n]);
        for k in 0..n {
            let p0 = cp[k];
            let d = val[p0];
            if !(d > f64::EPSILON * diag[k] && d.is_finite()) {
                return false;
            }
            let lkk = d.sqrt();
            val[p0] = lkk;
            for x in &mut val[p0 + 1..cp[k + 1]] {
                *x /= lkk;
            }
            for p in p0 + 1..cp[k + 1] {
                let (j, ljk) = (ri[p], val[p]);
                for t in cp[j]..cp[j + 1] {
                    pos[ri[t]] = t;
                    stamp[ri[t]] = j;
                }
                for q in p..cp[k + 1] {
                    if stamp[ri[q]] == j {
                        val[pos[ri[q]]] -= val[q] * ljk;
                    }
                }
            }
        }
        true
    }
}

impl Preconditioner for Ic0 {
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        let n = self.col_ptr.len() - 1;
        let (cp, ri, v) = (&self.col_ptr, &self.row, &self.val);
        z.copy_from_slice(r);
        for j in 0..n {
            z[j] /= v[cp[j]];
            let zj = z[j];
            for p in cp[j] + 1..cp[j + 1] {
                z[ri[p]] -= v[p] * zj;
            }
        }
        for j in (0..n).rev() {
            let s: f64 = (cp[j] + 1..cp[j + 1]).map(|p| v[p] * z[ri[p]]).sum();
            z[j] = (z[j] - s) / v[cp[j]];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::Stiffness;

    #[test]
    fn ic0_of_a_tridiagonal_matrix_is_its_cholesky_factor() {
        // No fill for a tridiagonal pattern: M = A, so M⁻¹A x = x.
        let n = 30;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 3.0 + i as f64));
            if i + 1 < n {
                t.push((i, i + 1, -1.5));
                t.push((i + 1, i, -1.5));
            }
        }
        let a = Stiffness::from_triplets(n, &t).unwrap();
        let s = a.to_sparse();
        let ic = Ic0::new(s.as_ref()).unwrap();
        assert_eq!(ic.shift, 0.0);
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut z = vec![0.0; n];
        ic.apply(&a.matvec(&x), &mut z);
        for (zi, xi) in z.iter().zip(&x) {
            assert!((zi - xi).abs() <= 64.0 * f64::EPSILON, "{zi} vs {xi}");
        }
    }

    #[test]
    fn ic0_shifts_where_a_pivot_breaks_down() {
        // Kershaw's matrix (1978): SPD, yet IC(0) meets a negative pivot.
        let a = Stiffness::from_rows(&[
            vec![3.0, -2.0, 0.0, 2.0],
            vec![-2.0, 3.0, -2.0, 0.0],
            vec![0.0, -2.0, 3.0, -2.0],
            vec![2.0, 0.0, -2.0, 3.0],
        ])
        .unwrap();
        assert!(a.to_dense().llt(faer::Side::Lower).is_ok(), "SPD");
        let ic = Ic0::new(a.to_sparse().as_ref()).unwrap();
        assert!(ic.shift > 0.0, "IC(0) of Kershaw's matrix needs a shift");
        // The unshifted factorization breaks down, and the shift is the first that works.
        let (s, d) = (a.to_sparse(), [3.0; 4]);
        assert!(Ic0::with_shift(s.as_ref(), &d, 0.0).is_none());
        assert!(Ic0::with_shift(s.as_ref(), &d, ic.shift / 2.0).is_none());
    }

    #[test]
    fn jacobi_refuses_a_nonpositive_diagonal() {
        let a = Stiffness::from_rows(&[vec![1.0, 0.0], vec![0.0, -2.0]]).unwrap();
        let e = Jacobi::new(a.to_sparse().as_ref()).unwrap_err();
        assert!(e.to_string().contains("diagonal entry 1"), "{e}");
    }
}
