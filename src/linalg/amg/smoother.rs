//! The (block) Gauss–Seidel smoother of the V-cycle and PyAMG's `improve_candidates` (module
//! doc of [`super`], steps 3 and 6).

use super::Csr;
use crate::error::{Error, Result};

/// PyAMG's `improve_candidates` on the finest level: each column of B relaxed by 4 symmetric
/// (block) Gauss–Seidel sweeps on `A x = 0` (the near-null space made smoother where A's
/// boundary rows break it, e.g. ones next to a Dirichlet boundary).
pub(super) fn improve_candidates(a: &Csr, blocks: &BlockDiag, b: &mut [f64], k: usize) {
    let n = a.n_rows;
    let zero = vec![0.0; n];
    for c in 0..k {
        let x = &mut b[c * n..(c + 1) * n];
        for _ in 0..4 {
            gauss_seidel(a, blocks, &zero, x, true);
            gauss_seidel(a, blocks, &zero, x, false);
        }
    }
}

/// What the Gauss–Seidel smoother divides by: A's diagonal (scalar levels), or the inverses
/// of A's diagonal `bs × bs` node blocks, each row-major and symmetrized, `(M + Mᵀ)/2` (the
/// block of an SPD A is SPD; rounding in the inverse would otherwise leave the smoother, and
/// the V-cycle, slightly unsymmetric).
pub(super) enum BlockDiag {
    Point(Vec<f64>),
    Block { bs: usize, inv: Vec<f64> },
}

impl BlockDiag {
    /// From A and its diagonal `diag`, for node blocks of `bs` unknowns.
    pub(super) fn new(a: &Csr, diag: &[f64], bs: usize) -> Result<BlockDiag> {
        if bs == 1 {
            return Ok(BlockDiag::Point(diag.to_vec()));
        }
        let nodes = a.n_rows / bs;
        let mut inv = vec![0.0; nodes * bs * bs];
        let mut block = nalgebra::DMatrix::<f64>::zeros(bs, bs);
        for node in 0..nodes {
            block.fill(0.0);
            for r in 0..bs {
                let i = node * bs + r;
                for (j, v) in a.row(i) {
                    if j / bs == node {
                        block[(r, j - node * bs)] = v;
                    }
                }
            }
            let m = block
                .clone()
                .try_inverse()
                .filter(|m| m.iter().all(|v| v.is_finite()));
            let Some(m) = m else {
                return Err(Error::input(format!(
                    "AMG: diagonal block {node} ({bs}×{bs}) of a level matrix is singular"
                )));
            };
            let out = &mut inv[node * bs * bs..(node + 1) * bs * bs];
            for r in 0..bs {
                for c in 0..bs {
                    out[r * bs + c] = 0.5 * (m[(r, c)] + m[(c, r)]);
                }
            }
        }
        Ok(BlockDiag::Block { bs, inv })
    }
}

/// One (block) Gauss–Seidel sweep on `A x = b`, forward or backward over the node blocks:
/// `x_I = D_I⁻¹ (b_I − Σ_{J≠I} A_IJ x_J)` (PyAMG's `block_gauss_seidel`; point Gauss–Seidel
/// for `bs = 1`).
pub(super) fn gauss_seidel(a: &Csr, blocks: &BlockDiag, b: &[f64], x: &mut [f64], forward: bool) {
    let (bs, inv) = match blocks {
        BlockDiag::Block { bs, inv } => (*bs, inv),
        BlockDiag::Point(diag) => {
            // Point Gauss–Seidel, dividing by a_ii (as PyAMG's `gauss_seidel`).
            let mut step = |i: usize| {
                let s: f64 = a
                    .row(i)
                    .filter(|&(j, _)| j != i)
                    .map(|(j, v)| v * x[j])
                    .sum();
                x[i] = (b[i] - s) / diag[i];
            };
            if forward {
                (0..b.len()).for_each(&mut step);
            } else {
                (0..b.len()).rev().for_each(&mut step);
            }
            return;
        }
    };
    let nodes = b.len() / bs;
    let mut r = vec![0.0; bs];
    let mut step = |node: usize| {
        let lo = node * bs;
        for (ri, rv) in r.iter_mut().enumerate() {
            let i = lo + ri;
            // `j` outside the node's block [lo, lo + bs) (no integer division per entry).
            let s: f64 = a
                .row(i)
                .filter(|&(j, _)| j.wrapping_sub(lo) >= bs)
                .map(|(j, v)| v * x[j])
                .sum();
            *rv = b[i] - s;
        }
        let m = &inv[node * bs * bs..(node + 1) * bs * bs];
        for c in 0..bs {
            x[lo + c] = (0..bs).map(|d| m[c * bs + d] * r[d]).sum();
        }
    };
    if forward {
        (0..nodes).for_each(&mut step);
    } else {
        (0..nodes).rev().for_each(&mut step);
    }
}
