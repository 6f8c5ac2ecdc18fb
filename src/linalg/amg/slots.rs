//! Unknowns in slots ([`crate::system::NearNull::with_slots`]): the nodal hierarchy is built on
//! `Â`, A with each of its unknowns moved to its slot and every empty slot (a prescribed
//! component) a decoupled identity row `s·e eᵀ`, s the mean of A's diagonal, so that every
//! node block is whole. `Â = P(A ⊕ sI)Pᵀ` is SPD, so is its V-cycle `M̂⁻¹`, and the
//! preconditioner applied to A, `Eᵀ M̂⁻¹ E` (E: unknowns to slots, zeros in the empty ones),
//! is a principal submatrix of it: SPD. The values the cycle leaves in empty slots are dropped.

use super::Csr;
use crate::error::{Error, Result};

/// Checks `slots` (increasing, below `n_slots`, one per row of `a`) and returns `Â`.
pub(super) fn padded(a: &Csr, slots: &[usize], n_slots: usize) -> Result<Csr> {
    if slots.len() != a.n_rows {
        return Err(Error::length_mismatch(
            "AMG: slots (one per unknown)",
            slots.len(),
            a.n_rows,
        ));
    }
    crate::system::check_slots("AMG", slots, n_slots)?;
    let diag = a.diagonal();
    let s = diag.iter().sum::<f64>() / diag.len().max(1) as f64;
    let mut owner = vec![usize::MAX; n_slots];
    for (i, &slot) in slots.iter().enumerate() {
        owner[slot] = i;
    }
    let mut ptr = Vec::with_capacity(n_slots + 1);
    let (mut col, mut val) = (Vec::with_capacity(a.col.len()), Vec::new());
    ptr.push(0);
    for &i in &owner {
        if i == usize::MAX {
            col.push(ptr.len() - 1);
            val.push(s);
        } else {
            // Slots increase with the unknowns: the row's columns stay sorted.
            for (j, v) in a.row(i) {
                col.push(slots[j]);
                val.push(v);
            }
        }
        ptr.push(col.len());
    }
    Ok(Csr {
        n_rows: n_slots,
        n_cols: n_slots,
        ptr,
        col,
        val,
    })
}

/// `x` (one value per unknown) in its slots, zeros in the empty ones.
pub(super) fn scatter(x: &[f64], slots: &[usize], n_slots: usize) -> Vec<f64> {
    let mut out = vec![0.0; n_slots];
    for (v, &s) in x.iter().zip(slots) {
        out[s] = *v;
    }
    out
}

/// The unknowns' values of the slotted `x`.
pub(super) fn gather(x: &[f64], slots: &[usize], out: &mut [f64]) {
    for (o, &s) in out.iter_mut().zip(slots) {
        *o = x[s];
    }
}
