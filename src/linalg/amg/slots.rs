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

#[cfg(test)]
mod tests {
    use super::*;

    /// A = [[4, −1], [−1, 3]] in slots {0, 2} of 3: slot 1 an identity row of mean diag 3.5.
    #[test]
    fn padding_moves_rows_and_fills_empty_slots() {
        let a = Csr {
            n_rows: 2,
            n_cols: 2,
            ptr: vec![0, 2, 4],
            col: vec![0, 1, 0, 1],
            val: vec![4.0, -1.0, -1.0, 3.0],
        };
        let p = padded(&a, &[0, 2], 3).unwrap();
        let dense = |i: usize| -> Vec<f64> {
            let mut r = vec![0.0; 3];
            p.row(i).for_each(|(j, v)| r[j] = v);
            r
        };
        assert_eq!(dense(0), vec![4.0, 0.0, -1.0]);
        assert_eq!(dense(1), vec![0.0, 3.5, 0.0]);
        assert_eq!(dense(2), vec![-1.0, 0.0, 3.0]);
        let x = scatter(&[1.5, -2.0], &[0, 2], 3);
        assert_eq!(x, vec![1.5, 0.0, -2.0]);
        let mut back = vec![0.0; 2];
        gather(&x, &[0, 2], &mut back);
        assert_eq!(back, vec![1.5, -2.0]);
        // Slots must increase, lie below the count and be one per unknown.
        assert!(padded(&a, &[2, 0], 3).is_err());
        assert!(padded(&a, &[0, 3], 3).is_err());
        assert!(padded(&a, &[0], 3).is_err());
    }
}
