//! Lanczos starts of a penalized system `A = K + D E Dᵀ` at large penalties: the top one
//! from the active block ([`penalty_top_start`]), the bottom one from the free block at the
//! exact contact set ([`free_block_bottom`]).
//!
//! ## The top start
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
//!
//! ## The bottom start
//!
//! At the other end, as the penalties on a set ℬ of DOFs grow, A's smallest eigenpair tends
//! to K_ℱℱ's (ℱ the other DOFs), padded with zeros on ℬ:
//!
//! `λ_min(A) ≤ λ_min(K_ℱℱ)` (K_ℱℱ is a principal submatrix of A: Cauchy interlacing), with
//! equality in the limit (`A⁻¹ → K_ℱℱ⁻¹ ⊕ 0` as `min E_ℬ → ∞`),
//!
//! and K's bottom Ritz vector, spread over ℬ, is a poor start for it: on the folder's
//! membranes the `constant` rows' bottom runs (solves with A's factor, the costly end) took
//! 12–16 steps at ε ≥ 1e4 from K's vector, against 4 from K_ℱℱ's. [`free_block_bottom`] computes K_ℱℱ's
//! bottom Ritz vector once per scene, with ℬ the exact (lagrange) contact set: shift-invert
//! Lanczos with the Cholesky factor of K_ℱℱ (stored as K with ℬ's rows and columns replaced
//! by the identity, the saddle-point route's `free_block_factor`) and ℬ's
//! components projected out after every solve, started from K's bottom vector. Each
//! penalized row starts from whichever of it and K's bottom vector has the smaller Rayleigh
//! quotient on A (for a unit v, `ρ_A(v) − λ_min ≥ (λ₂ − λ_min)·sin²∠(v, u_min)`): rows at
//! small penalties keep K's. Like the top start it decides only how many steps the bottom
//! run takes and where inside the certified bracket the value lands; it is a function of K,
//! K's bottom Ritz vector and the contact set alone, so `solve --exact-start` (which solves
//! lagrange first, as a sweep does) forms the same start and reports the same rows bit for
//! bit. Its run is not counted in any row's `lanczos_steps`.

use super::lanczos::{dot, inverse_lanczos, lanczos, Keep, STAGNATION, TOP_STAGNATION};
use super::sparse::{MAX_LANCZOS_STEPS, PLAIN_LANCZOS_STEPS};
use crate::linalg::{symmetric_matvec, DiagonalPattern};
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

/// The Rayleigh quotients on `a` of a candidate start and of K's vector it would replace.
fn quotients(a: &SparseColMat<usize, f64>, candidate: &[f64], k_vector: &[f64]) -> (f64, f64) {
    let mut scratch = vec![0.0; a.nrows()];
    (
        rayleigh(a, candidate, &mut scratch),
        rayleigh(a, k_vector, &mut scratch),
    )
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
    let (mine, ks) = quotients(a, &padded, k_top);
    (mine.is_finite() && mine > ks).then_some(padded)
}

/// K_ℱℱ's bottom Ritz vector, padded with zeros on the DOFs `constrained` (ℬ; see the module
/// docs): shift-invert Lanczos with the Cholesky factor of K_ℱℱ, ℬ projected out after every
/// solve, from `k_bottom` (K's bottom Ritz vector) with ℬ zeroed; the vector is normalized
/// and exactly zero on ℬ. `k` in compressed columns, both triangles stored. None where ℬ is
/// empty, holds every DOF or a DOF out of range or twice, `k_bottom` has the wrong length or
/// vanishes off ℬ, K_ℱℱ does not factor, or the run fails.
pub fn free_block_bottom(
    k: &SparseColMat<usize, f64>,
    constrained: &[usize],
    k_bottom: &[f64],
) -> Option<Vec<f64>> {
    let n = k.nrows();
    if constrained.is_empty() || constrained.len() >= n || k_bottom.len() != n {
        return None;
    }
    let in_b = super::saddle::dof_mask(n, constrained).ok()?;
    let project = |y: &mut [f64]| {
        for (yi, &b) in y.iter_mut().zip(&in_b) {
            if b {
                *yi = 0.0;
            }
        }
    };
    let mut start = k_bottom.to_vec();
    project(&mut start);
    if start.iter().all(|&x| x == 0.0) {
        return None;
    }
    let pattern = DiagonalPattern::new(k).ok()?;
    let kff = super::saddle::free_block_factor(&pattern, &in_b).ok()?;
    let run = inverse_lanczos(n, MAX_LANCZOS_STEPS, STAGNATION, Some(&start), |y| {
        kff.solve_vec_in_place(y);
        project(y);
    })
    .ok()?;
    // The start's seeded generic part reaches ℬ; the operator's range does not.
    let mut v = run.vector?;
    project(&mut v);
    let norm = dot(&v, &v).sqrt();
    (norm > 0.0 && norm.is_finite()).then(|| v.iter().map(|x| x / norm).collect())
}

/// Of K's bottom Ritz vector `k_bottom` and the free block's `free` ([`free_block_bottom`]),
/// the one with the smaller Rayleigh quotient on `a`: Some(free) where that is `free`, None
/// where K's is as good (or `free` has the wrong length or a non-finite quotient).
pub fn penalty_bottom_start(
    a: &SparseColMat<usize, f64>,
    k_bottom: &[f64],
    free: &[f64],
) -> Option<Vec<f64>> {
    let n = a.nrows();
    if free.len() != n || k_bottom.len() != n {
        return None;
    }
    let (mine, ks) = quotients(a, free, k_bottom);
    (mine.is_finite() && mine < ks).then(|| free.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conditioning::sparse::RitzStarts;

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

    /// The second-difference matrix of order 60 (K, λ_min ≈ 0.0026) and its free block with
    /// ℬ = {20, …, 31}: the padded vector is K_ℱℱ's bottom eigenvector (angle to the dense one
    /// below 1e-7, K's own bottom vector more than 0.1 rad away), exactly zero on ℬ; the
    /// bottom start of `K + εP_ℬ` at ε = 1e8 (A's bottom eigenvector is then K_ℱℱ's to
    /// O(1/ε)), not at ε = 1e-3 (A ≈ K); and no vector for an empty ℬ, every DOF, a DOF twice
    /// or out of range, or a start of the wrong length.
    #[test]
    fn the_free_block_bottom_is_the_free_blocks_eigenvector() {
        let n = 60;
        let b: Vec<usize> = (20..32).collect();
        let second_difference = |eps: f64| {
            let mut t = Vec::new();
            for i in 0..n {
                let e = if b.contains(&i) { eps } else { 0.0 };
                t.push(faer::sparse::Triplet::new(i, i, 2.0 + e));
                if i + 1 < n {
                    t.push(faer::sparse::Triplet::new(i, i + 1, -1.0));
                    t.push(faer::sparse::Triplet::new(i + 1, i, -1.0));
                }
            }
            SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
        };
        let k = second_difference(0.0);
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        let k_bottom: Vec<f64> = (1..=n).map(|i| (i as f64 * th).sin()).collect();
        let v = free_block_bottom(&k, &b, &k_bottom).expect("a free-block vector");
        assert!(b.iter().all(|&d| v[d] == 0.0), "not zero on ℬ");
        // The dense K_ℱℱ (ℬ's rows and columns removed) and its bottom eigenvector.
        let free: Vec<usize> = (0..n).filter(|i| !b.contains(i)).collect();
        let kd = k.to_dense();
        let kff = faer::Mat::<f64>::from_fn(free.len(), free.len(), |i, j| kd[(free[i], free[j])]);
        let evd = kff.self_adjoint_eigen(faer::Side::Lower).unwrap();
        let (u, s) = (evd.U(), evd.S().column_vector());
        let bottom = (0..free.len())
            .min_by(|&i, &j| s[i].total_cmp(&s[j]))
            .unwrap();
        let angle = |x: &[f64]| {
            let c: f64 = free
                .iter()
                .enumerate()
                .map(|(i, &d)| x[d] * u[(i, bottom)])
                .sum();
            (c.abs() / dot(x, x).sqrt()).min(1.0).acos()
        };
        assert!(angle(&v) < 1e-7, "angle {}", angle(&v));
        assert!(angle(&k_bottom) > 0.1, "K's vector would pass");
        assert!(penalty_bottom_start(&second_difference(1e8), &k_bottom, &v).is_some());
        assert!(penalty_bottom_start(&second_difference(1e-3), &k_bottom, &v).is_none());
        for bad in [vec![], (0..n).collect(), vec![3, 3], vec![n]] {
            assert!(free_block_bottom(&k, &bad, &k_bottom).is_none(), "{bad:?}");
        }
        assert!(free_block_bottom(&k, &b, &k_bottom[1..]).is_none());
    }

    /// The five-point membrane of side `side` with `eps` added on the diagonal at `active`.
    fn membrane(side: usize, active: &[usize], eps: f64) -> SparseColMat<usize, f64> {
        let n = side * side;
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
    }

    /// The certified cond₂ of `a` from `better` takes fewer Lanczos steps than from `plain`,
    /// and each bracket holds the other's value.
    fn saves_steps(a: SparseColMat<usize, f64>, plain: &RitzStarts, better: &RitzStarts) {
        use crate::conditioning::{cond2_warm, Reuse};
        let system = crate::system::Stiffness::Sparse(a);
        let run = |starts| {
            let reuse = Reuse {
                starts: Some(starts),
                ..Reuse::default()
            };
            cond2_warm(&system, reuse).unwrap().0
        };
        let (plain, better) = (run(plain), run(better));
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

    /// K's Ritz vectors of the 12 × 12 membrane.
    fn membrane_ritz(active: &[usize]) -> RitzStarts {
        let k = crate::system::Stiffness::Sparse(membrane(12, active, 0.0));
        let keep = crate::conditioning::Reuse::keeping_ritz();
        crate::conditioning::cond2_warm(&k, keep)
            .unwrap()
            .1
            .expect("K's Ritz vectors")
    }

    /// On a five-point membrane (12 × 12, 29 DOFs penalized at ε = 1e6), the certified cond₂
    /// of A started from the padded top vector takes fewer Lanczos steps than from K's
    /// vectors alone, and both brackets hold the same value (each within the other's bracket).
    #[test]
    fn the_padded_start_saves_steps_on_a_membrane() {
        let active: Vec<usize> = (0..144).step_by(5).collect();
        let (a, ritz) = (membrane(12, &active, 1e6), membrane_ritz(&active));
        let top = penalty_top_start(&a, &ritz.top, &active).expect("the padded start wins");
        let padded = RitzStarts {
            top,
            bottom: ritz.bottom.clone(),
        };
        saves_steps(a, &ritz, &padded);
    }

    /// On the same membrane with every fifth DOF penalized at ε = 1e8, the certified cond₂ of A
    /// with its bottom run started from the free block's vector takes fewer Lanczos steps
    /// than from K's vectors alone, and both brackets hold the same value.
    #[test]
    fn the_free_block_start_saves_steps_on_a_membrane() {
        let active: Vec<usize> = (0..144).step_by(5).collect();
        let (k, a) = (membrane(12, &active, 0.0), membrane(12, &active, 1e8));
        let ritz = membrane_ritz(&active);
        let free = free_block_bottom(&k, &active, &ritz.bottom).expect("a free-block vector");
        let bottom = penalty_bottom_start(&a, &ritz.bottom, &free).expect("the better start");
        let started = RitzStarts {
            top: ritz.top.clone(),
            bottom,
        };
        saves_steps(a, &ritz, &started);
    }
}
