//! The top Lanczos start of a penalized system `A = K + D E Dᵀ` at large penalties.
//!
//! With D Boolean (constraint c on DOF d_c) and the active DOFs 𝒜 = {d_c : E_cc > 0}, ℱ the
//! rest, once every active penalty exceeds K's diagonal at its DOF the top of A's spectrum
//! belongs to the active block: as ε → ∞,
//!
//! `λ_max(A) = λ_max(A_𝒜𝒜) + O(‖K_𝒜ℱ‖² / ε)`,  A_𝒜𝒜 = K_𝒜𝒜 + E_𝒜 (the principal submatrix),
//!
//! and A's top eigenvector tends to A_𝒜𝒜's, padded with zeros on ℱ. K's own top Ritz vector —
//! the start a sweep shares between the rows of a scene — spreads over every DOF and is far from
//! it: on the folder's 289-DOF membrane (56 active DOFs) the top run from K's vector took 24–44
//! products at ε = 1e2–1e10.
//!
//! [`penalty_top_start`] forms the padded vector by plain Lanczos on A_𝒜𝒜 (products with the
//! m_𝒜 × m_𝒜 submatrix, started from K's vector restricted to 𝒜) and returns whichever of it
//! and K's vector has the larger Rayleigh quotient on A: for a unit v,
//! `λ_max − ρ_A(v) ≥ (λ_max − λ₂)·sin²∠(v, u_max)`, so the larger quotient has the smaller
//! bound on its angle to the wanted eigenvector.
//!
//! What rests on it: how many steps the top run takes, and so where inside its certified
//! bracket the reported value lands (the estimate converges to the same eigenvalue from
//! another vector: its last digits, within the bracket, may differ). Nothing certified rests
//! on a start ([`super::sparse::extreme_eigenvalues`]: a run that settles short fails its
//! inertia test, a bracket that misses its target is recomputed from the generic start, and
//! every warm start carries a part of the seeded generic one). It is a function of A, K's
//! Ritz vector and 𝒜 alone, so `solve` and a sweep form the same start and report the same
//! rows bit for bit. Its own run (products with A_𝒜𝒜, up to [`PLAIN_LANCZOS_STEPS`]) and two
//! products with A are not counted in the certificate's `lanczos_steps`; the timings of
//! docs/performance.md include them.
//! Where to use it: a penalized system with single-DOF constraints whose every active
//! penalty exceeds K's diagonal entry at its DOF (the metrics decide); below that, the top of
//! A is K's and K's vector is the better start.

use super::lanczos::{dot, lanczos, Keep, TOP_STAGNATION};
use super::sparse::PLAIN_LANCZOS_STEPS;
use crate::linalg::symmetric_matvec;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// The principal submatrix `A_𝒜𝒜` of `a` (compressed columns with sorted row indices, both
/// triangles stored, as every sparse matrix of the crate) on the sorted, distinct DOFs
/// `keep`, in the same storage; None where a DOF is out of range.
fn principal_submatrix(
    a: &SparseColMat<usize, f64>,
    keep: &[usize],
) -> Option<SparseColMat<usize, f64>> {
    let n = a.nrows();
    let mut at = vec![usize::MAX; n];
    for (i, &d) in keep.iter().enumerate() {
        *at.get_mut(d)? = i;
    }
    let (ri, av) = (a.symbolic().row_idx(), a.val());
    let (mut col_ptr, mut row_idx, mut values) =
        (Vec::with_capacity(keep.len() + 1), Vec::new(), Vec::new());
    col_ptr.push(0);
    for &j in keep {
        for p in a.symbolic().col_range(j) {
            let i = at[ri[p]];
            if i != usize::MAX {
                row_idx.push(i);
                values.push(av[p]);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let m = keep.len();
    let symbolic = SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx);
    Some(SparseColMat::new(symbolic, values))
}

/// `vᵀAv / vᵀv` with A in compressed columns (both triangles stored).
fn rayleigh(a: &SparseColMat<usize, f64>, v: &[f64], scratch: &mut [f64]) -> f64 {
    symmetric_matvec(a.symbolic(), a.val(), v, scratch);
    dot(v, scratch) / dot(v, v)
}

/// The top Lanczos start for `a = K + D E Dᵀ` (see the module docs; `a` in compressed
/// columns with sorted row indices, both triangles stored): the top Ritz vector of the
/// principal submatrix on `active` (sorted, distinct DOFs), padded with zeros, where its
/// Rayleigh quotient on `a` exceeds that of `k_top` (K's top Ritz vector); else None (keep
/// K's). None also where `active` is empty or every DOF, or the run fails.
pub fn penalty_top_start(
    a: &SparseColMat<usize, f64>,
    k_top: &[f64],
    active: &[usize],
) -> Option<Vec<f64>> {
    let n = a.nrows();
    if active.is_empty() || active.len() >= n || k_top.len() != n {
        return None;
    }
    let sub = principal_submatrix(a, active)?;
    let restricted: Vec<f64> = active.iter().map(|&d| k_top[d]).collect();
    let start = restricted
        .iter()
        .any(|&x| x != 0.0)
        .then_some(restricted.as_slice());
    let run = lanczos(
        active.len(),
        PLAIN_LANCZOS_STEPS,
        |_| TOP_STAGNATION,
        start,
        Keep::Always,
        |x, y| symmetric_matvec(sub.symbolic(), sub.val(), x, y),
    )
    .ok()?;
    let mut padded = vec![0.0; n];
    for (&d, &x) in active.iter().zip(run.vector.as_ref()?) {
        padded[d] = x;
    }
    let mut scratch = vec![0.0; n];
    let (mine, ks) = (
        rayleigh(a, &padded, &mut scratch),
        rayleigh(a, k_top, &mut scratch),
    );
    (mine.is_finite() && mine > ks).then_some(padded)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K the second-difference matrix plus ε on a block of DOFs: the padded start is A's top
    /// eigenvector to O(1/ε) — its angle to the dense eigenvector below 1e-5 at ε = 1e6 (a basis
    /// vector of the block is more than 0.1 rad away) — and it beats K's top eigenvector,
    /// whose quotient stays near λ_max(K) ≈ 4; with no active DOF there is no start.
    #[test]
    fn the_padded_start_tends_to_the_top_eigenvector() {
        let n = 60;
        let active: Vec<usize> = (20..32).collect();
        let eps = 1e6;
        let mut t = Vec::new();
        for i in 0..n {
            let d = if active.contains(&i) { 2.0 + eps } else { 2.0 };
            t.push(faer::sparse::Triplet::new(i, i, d));
            if i + 1 < n {
                t.push(faer::sparse::Triplet::new(i, i + 1, -1.0));
                t.push(faer::sparse::Triplet::new(i + 1, i, -1.0));
            }
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        let k_top: Vec<f64> = (1..=n).map(|i| (i as f64 * n as f64 * th).sin()).collect();
        let v = penalty_top_start(&a, &k_top, &active).expect("the padded start wins");
        let evd = a.to_dense().self_adjoint_eigen(faer::Side::Lower).unwrap();
        let (u, s) = (evd.U(), evd.S().column_vector());
        let top = (0..n).max_by(|&i, &j| s[i].total_cmp(&s[j])).unwrap();
        let cos = |x: &[f64]| {
            let c: f64 = (0..n).map(|i| x[i] * u[(i, top)]).sum();
            (c.abs() / dot(x, x).sqrt()).min(1.0)
        };
        let angle = cos(&v).acos();
        assert!(angle < 1e-5, "angle {angle}");
        let e20: Vec<f64> = (0..n).map(|i| if i == 20 { 1.0 } else { 0.0 }).collect();
        assert!(cos(&e20).acos() > 0.1, "a basis vector would pass");
        assert!(v
            .iter()
            .enumerate()
            .all(|(i, &x)| active.contains(&i) || x == 0.0));
        assert!(penalty_top_start(&a, &k_top, &[]).is_none());
    }

    /// On a five-point membrane (12 × 12, 29 DOFs penalized at ε = 1e6), the certified cond₂
    /// of A started from the padded top vector takes fewer Lanczos steps than from K's
    /// vectors alone, and both brackets hold the same value (each within the other's bracket).
    #[test]
    fn the_padded_start_saves_steps_on_a_membrane() {
        use crate::conditioning::{cond2_warm, Reuse};
        use crate::system::Stiffness;
        let side = 12;
        let n = side * side;
        let active: Vec<usize> = (0..n).step_by(5).collect();
        let laplacian = |eps: f64| {
            let mut t = Vec::new();
            for r in 0..side {
                for c in 0..side {
                    let i = r * side + c;
                    let e = if active.contains(&i) { eps } else { 0.0 };
                    t.push(faer::sparse::Triplet::new(i, i, 4.0 + e));
                    for (rr, cc) in [(r + 1, c), (r, c + 1)] {
                        if rr < side && cc < side {
                            let j = rr * side + cc;
                            t.push(faer::sparse::Triplet::new(i, j, -1.0));
                            t.push(faer::sparse::Triplet::new(j, i, -1.0));
                        }
                    }
                }
            }
            SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
        };
        let (k, a) = (laplacian(0.0), laplacian(1e6));
        let (_, ritz) = cond2_warm(&Stiffness::Sparse(k), Reuse::keeping_ritz()).unwrap();
        let ritz = ritz.expect("K's Ritz vectors");
        let top = penalty_top_start(&a, &ritz.top, &active).expect("the padded start wins");
        let padded = crate::conditioning::sparse::RitzStarts {
            top,
            bottom: ritz.bottom.clone(),
        };
        let system = Stiffness::Sparse(a);
        let run = |starts| {
            let reuse = Reuse {
                starts: Some(starts),
                ..Reuse::default()
            };
            cond2_warm(&system, reuse).unwrap().0
        };
        let (plain, better) = (run(&ritz), run(&padded));
        let steps = |r: &crate::conditioning::CondReport| r.certificate.unwrap().lanczos_steps;
        assert!(
            steps(&better) < steps(&plain),
            "{} vs {}",
            steps(&better),
            steps(&plain)
        );
        for (x, y) in [(&plain, &better), (&better, &plain)] {
            assert!(
                x.cond2_lo <= y.cond2 && y.cond2 <= x.cond2_hi,
                "{x:?} {y:?}"
            );
        }
    }
}
