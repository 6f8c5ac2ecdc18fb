//! The block structure of `A = [K D; Dᵀ 0]` ([`super`]): A itself in compressed columns,
//! `A⁻¹` by block elimination with the factor of K_FF, the constrained-DOF mask, K_FF's
//! factor (shifted for [`super::schur`]) and the analytic floor s₀.

use crate::error::{Error, Result};
use crate::linalg::{DiagonalPattern, SparseLlt};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// `[K D; Dᵀ 0]` in CSC with both triangles (K's columns from `pattern`, then the unit
/// entries of D and Dᵀ), for products and Rayleigh quotients.
pub(super) fn saddle_csc(
    pattern: &DiagonalPattern,
    dofs: &[usize],
) -> (SymbolicSparseColMat<usize>, Vec<f64>) {
    let (n, m) = (pattern.n(), dofs.len());
    let mut column_of = vec![usize::MAX; n];
    for (c, &d) in dofs.iter().enumerate() {
        column_of[d] = c;
    }
    let (cp, ri) = (pattern.pattern.col_ptr(), pattern.pattern.row_idx());
    let mut col_ptr = Vec::with_capacity(n + m + 1);
    let mut row_idx = Vec::with_capacity(ri.len() + 2 * m);
    let mut values = Vec::with_capacity(ri.len() + 2 * m);
    col_ptr.push(0);
    for j in 0..n {
        row_idx.extend_from_slice(&ri[cp[j]..cp[j + 1]]);
        values.extend_from_slice(&pattern.values[cp[j]..cp[j + 1]]);
        if column_of[j] != usize::MAX {
            row_idx.push(n + column_of[j]);
            values.push(1.0);
        }
        col_ptr.push(row_idx.len());
    }
    for &d in dofs {
        row_idx.push(d);
        values.push(1.0);
        col_ptr.push(row_idx.len());
    }
    let size = n + m;
    (
        SymbolicSparseColMat::new_checked(size, size, col_ptr, None, row_idx),
        values,
    )
}

/// `±A⁻¹` by block elimination with the factor of K_FF: for `A [x; y] = [f; g]`, `x_B = g`,
/// `K_FF x_F = f_F − K_FB g`, `y = f_B − (K x)_B`. K enters only through its B columns
/// (K symmetric: `(K x)_B` is those columns against x), so a product costs one solve and
/// O(n + nnz of K's B columns).
pub(super) struct BlockInverse<'a> {
    pub(super) pattern: &'a DiagonalPattern,
    pub(super) dofs: &'a [usize],
    pub(super) in_b: &'a [bool],
    pub(super) kff: &'a SparseLlt,
    /// K_{·B} g.
    pub(super) kxb: Vec<f64>,
}

impl BlockInverse<'_> {
    pub(super) fn apply(&mut self, v: &[f64], out: &mut [f64], sign: f64) {
        let n = self.in_b.len();
        let (f, g) = v.split_at(n);
        let (x, y) = out.split_at_mut(n);
        let (cp, ri) = (
            self.pattern.pattern.col_ptr(),
            self.pattern.pattern.row_idx(),
        );
        let vals = &self.pattern.values;
        self.kxb.iter_mut().for_each(|e| *e = 0.0);
        for (c, &d) in self.dofs.iter().enumerate() {
            for p in cp[d]..cp[d + 1] {
                self.kxb[ri[p]] += vals[p] * g[c];
            }
        }
        for i in 0..n {
            x[i] = if self.in_b[i] {
                0.0
            } else {
                f[i] - self.kxb[i]
            };
        }
        self.kff.solve_vec_in_place(x);
        for (c, &d) in self.dofs.iter().enumerate() {
            x[d] = g[c];
        }
        for (c, &d) in self.dofs.iter().enumerate() {
            let kx_d: f64 = (cp[d]..cp[d + 1]).map(|p| vals[p] * x[ri[p]]).sum();
            y[c] = f[d] - kx_d;
        }
        if sign < 0.0 {
            out.iter_mut().for_each(|o| *o = -*o);
        }
    }
}

/// `mask[i]` = whether DOF i is among `dofs` (N = `n`); `Err(d)` for the first DOF d that is
/// out of range or repeated (the callers word the error).
pub(crate) fn dof_mask(n: usize, dofs: &[usize]) -> std::result::Result<Vec<bool>, usize> {
    let mut mask = vec![false; n];
    for &d in dofs {
        if d >= n || std::mem::replace(&mut mask[d], true) {
            return Err(d);
        }
    }
    Ok(mask)
}

/// The error for DOF `d` that [`dof_mask`] refused: [`Error::DofOutOfRange`] for `d ≥ n`,
/// else [`Error::Duplicate`] (a DOF listed twice); `context` names the computation.
pub(crate) fn dof_error(context: &str, n: usize, d: usize) -> Error {
    if d >= n {
        Error::DofOutOfRange {
            context: context.to_string(),
            dof: d,
            n,
        }
    } else {
        Error::duplicate(format!("{context}: constraint DOF"), d)
    }
}

/// The mask of the constrained DOFs B; errors on a repeated or out-of-range DOF and unless
/// 0 < m < N.
pub(super) fn constrained_mask(n: usize, dofs: &[usize]) -> Result<Vec<bool>> {
    let m = dofs.len();
    let in_b = dof_mask(n, dofs).map_err(|d| dof_error("saddle-point cond₂", n, d))?;
    if m == 0 || m >= n {
        return Err(Error::out_of_range(
            "saddle-point cond₂: the number of constraint DOFs m",
            m,
            format!("0 < m < N = {n}"),
        ));
    }
    Ok(in_b)
}

/// Cholesky of K_FF, stored as K with the rows and columns of B replaced by the identity (for
/// the block elimination behind A⁻¹); errors when K_FF is not positive definite.
pub(crate) fn free_block_factor(pattern: &DiagonalPattern, in_b: &[bool]) -> Result<SparseLlt> {
    let mut vff = Vec::new();
    free_block_values(pattern, in_b, 0.0, &mut vff);
    pattern.factor(&vff).ok_or_else(|| {
        Error::singular("saddle-point matrix is singular: K without the constrained DOFs is not positive definite")
    })
}

/// `K_FF + sI` on K's pattern with the rows and columns of B replaced by the identity.
pub(super) fn free_block_values(
    pattern: &DiagonalPattern,
    in_b: &[bool],
    s: f64,
    out: &mut Vec<f64>,
) {
    let (cp, ri) = (pattern.pattern.col_ptr(), pattern.pattern.row_idx());
    out.clear();
    out.extend_from_slice(&pattern.values);
    for j in 0..in_b.len() {
        for p in cp[j]..cp[j + 1] {
            if in_b[ri[p]] || in_b[j] {
                out[p] = if ri[p] == j { 1.0 } else { 0.0 };
            } else if ri[p] == j {
                out[p] += s;
            }
        }
    }
}

/// Gershgorin upper bound of the principal submatrix K_BB.
/// s₀: s·(g_B + s) < 1 ⇒ no eigenvalue in (−s, 0), g_B = [`gershgorin_b`].
pub(super) fn s0(k: &SparseColMat<usize, f64>, in_b: &[bool]) -> f64 {
    let g_b = gershgorin_b(k, in_b);
    2.0 / (g_b + (g_b * g_b + 4.0).sqrt()) * (1.0 - 1e-12)
}

fn gershgorin_b(k: &SparseColMat<usize, f64>, in_b: &[bool]) -> f64 {
    let (cp, ri, v) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    (0..k.ncols())
        .filter(|&j| in_b[j])
        .map(|j| {
            (cp[j]..cp[j + 1])
                .filter(|&p| in_b[ri[p]])
                .map(|p| if ri[p] == j { v[p] } else { v[p].abs() })
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}
