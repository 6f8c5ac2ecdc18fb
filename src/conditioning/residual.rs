//! The a-posteriori margins of a Cholesky test that succeeded ([`super::certify`], Lemmas 7
//! and 7a): how far the factor's own rounding can have moved the test matrix, measured on the
//! factor instead of bounded in the worst case.
//!
//! Why hand-written: the residual `L̂L̂ᵀ − B` must be formed over the factor's sparse pattern
//! with every product exact (two_prod) and compensated sums; no crate in the stack offers a
//! sparse product in extended precision (faer's `fx128` matrices are dense).

use super::certify::{gamma, up, U};
use crate::dd::{two_prod, two_sum};
use faer::sparse::SymbolicSparseColMatRef;

/// Lemma 7a (the factor's own a-priori margin): `m` with `xᵀBx ≥ −m Σ_i b̃_ii x_i²` for
/// `B = αA + σI` from a factor `PB̃Pᵀ ≈ L̂L̂ᵀ` that succeeded. Lemma 1's entrywise bound
/// `|L̂L̂ᵀ − PB̃Pᵀ| ≤ γ_{r+1}|L̂||L̂ᵀ|` with the Perron root of `D⁻¹|L̂||L̂ᵀ|D⁻¹` (`d_i = √b̃_ii`,
/// permuted) in place of Lemma 1's Cauchy–Schwarz factor c: by Collatz–Wielandt,
/// `ρ ≤ max_i (D⁻¹|L̂||L̂ᵀ|D⁻¹𝟙)_i`, two triangular products with |L̂|, no extra precision.
/// The diagonal's rounding adds 2u as in Lemma 1. None where a `b̃_ii ≤ 0`.
pub fn factor_margin(factor: &crate::linalg::LowerFactor, stored_diagonal: &[f64]) -> Option<f64> {
    // Entry (p, q) of L̂L̂ᵀ sums at most min(r_p, r_q) ≤ √(r_p r_q)-weighted terms: its
    // γ_{N+1} ≤ g_p g_q with g_i = √γ_{r_i+1} (r_i: the entries in row i of L̂).
    let weight = |p: usize| {
        let b = stored_diagonal[factor.fwd.as_ref().map_or(p, |f| f[p])];
        (b > 0.0 && b.is_finite()).then(|| b.sqrt())
    };
    let rho = perron_bound(
        &factor.col_ptr,
        &factor.row_idx,
        &factor.values,
        1,
        weight,
        false,
    )?;
    let m = up(rho + 2.0 * U);
    m.is_finite().then_some(m)
}

/// The Collatz–Wielandt bound shared by Lemma 7a ([`factor_margin`]) and Lemma 8
/// (`temple::ldlt_margin`): `max_p s_p (|L̂||D̂||L̂ᵀ| s)_p ≥ ρ(S|L̂||D̂||L̂ᵀ|S)`, with
/// `s_p = √γ_{r_p+extra} / weight(p)` (r_p: the entries of row p of L̂; `weight(p)` the
/// scaling at permuted position p, None where there is none) and D̂ = I (`unit_diagonal`
/// false: L̂L̂ᵀ, the diagonal of L̂ stored) or the stored diagonal of a unit L̂ (true: L̂D̂L̂ᵀ).
/// L̂ in compressed columns, the diagonal first. Two triangular products with |L̂|, every term
/// non-negative; the f64 sums (≤ widest column, ≤ r terms), square roots and quotients are
/// covered by `1 + γ`. None where a weight is missing.
pub(crate) fn perron_bound(
    lcp: &[usize],
    lri: &[usize],
    lv: &[f64],
    extra: usize,
    weight: impl Fn(usize) -> Option<f64>,
    unit_diagonal: bool,
) -> Option<f64> {
    let n = lcp.len() - 1;
    perron_bound_by(
        n,
        |visit| {
            for k in 0..n {
                let (a, b) = (lcp[k], lcp[k + 1]);
                visit(k, lv[a], &lri[a + 1..b], &lv[a + 1..b]);
            }
        },
        extra,
        weight,
        unit_diagonal,
    )
}

/// [`perron_bound`] over any storage of L̂: `columns(visit)` calls `visit(k, l_kk, rows,
/// values)` for every column k in order, with the entries below the diagonal (twice: row
/// counts, then the products). The supernodal factors of 10⁵–10⁶ unknowns pass their
/// supernodes' columns in place ([`factor_margin_of`]), without a copy of L̂.
pub(crate) fn perron_bound_by(
    n: usize,
    columns: impl Fn(&mut dyn FnMut(usize, f64, &[usize], &[f64])),
    extra: usize,
    weight: impl Fn(usize) -> Option<f64>,
    unit_diagonal: bool,
) -> Option<f64> {
    let mut row_count = vec![0usize; n];
    columns(&mut |k, _, rows, _| {
        row_count[k] += 1;
        for &p in rows {
            row_count[p] += 1;
        }
    });
    let mut scale = vec![0.0f64; n];
    for (p, v) in scale.iter_mut().enumerate() {
        *v = gamma(row_count[p] + extra).sqrt() / weight(p)?;
    }
    // z = |D̂||L̂ᵀ| S𝟙, then w = |L̂| z.
    let (mut z, mut w) = (vec![0.0f64; n], vec![0.0f64; n]);
    let mut widest = 0usize;
    columns(&mut |k, diag, rows, vals| {
        widest = widest.max(rows.len() + 1);
        let (d, l_kk) = if unit_diagonal {
            (diag.abs(), 1.0)
        } else {
            (1.0, diag.abs())
        };
        let below: f64 = rows
            .iter()
            .zip(vals)
            .map(|(&p, &v)| v.abs() * scale[p])
            .sum();
        z[k] = d * (l_kk * scale[k] + below);
        w[k] += l_kk * z[k];
        for (&p, &v) in rows.iter().zip(vals) {
            w[p] += v.abs() * z[k];
        }
    });
    let r = row_count.into_iter().max().unwrap_or(0);
    let rho = w
        .iter()
        .zip(&scale)
        .map(|(wp, sp)| wp * sp)
        .fold(0.0f64, f64::max);
    Some(up(rho * (1.0 + gamma(widest + r + 12))))
}

/// Lemma 7a ([`factor_margin`]) of a factor in its own storage: a supernodal factor's
/// columns are read in place (no copy of L̂: 0.8 GB at 10⁶ unknowns), a simplicial one
/// through [`crate::linalg::SparseLlt::lower_factor`] (its columns sorted, the diagonal first).
pub fn factor_margin_of(factor: &crate::linalg::SparseLlt, stored_diagonal: &[f64]) -> Option<f64> {
    factor.with_columns(|n, fwd, columns| {
        let weight = |p: usize| {
            let b = stored_diagonal[fwd.map_or(p, |f| f[p])];
            (b > 0.0 && b.is_finite()).then(|| b.sqrt())
        };
        let rho = perron_bound_by(n, columns, 1, weight, false)?;
        let m = up(rho + 2.0 * U);
        m.is_finite().then_some(m)
    })
}

/// The margin a successful Cholesky test is judged by: the smallest of Lemma 1's `apriori`,
/// the factor's own (Lemma 7a, [`factor_margin_of`]) and, where that still exceeds `need` and
/// `posterior` names the exact test matrix `B = α·values + σI` (`values` on `pattern`), its
/// residual's (Lemma 7, [`posterior_margin`]; needs L in compressed columns, a copy on a
/// supernodal factor). `stored`: the test matrix's diagonal as factored (original order).
pub(crate) fn own_margin(
    f: &crate::linalg::SparseLlt,
    stored: &[f64],
    apriori: f64,
    need: f64,
    posterior: Option<(SymbolicSparseColMatRef<'_, usize>, &[f64], f64, f64)>,
) -> f64 {
    // Lemma 7a: a supernodal factor read in place, a simplicial one from its sorted copy
    // (kept for Lemma 7's residual).
    let (m7a, lower) = if f.is_supernodal() {
        (factor_margin_of(f, stored), None)
    } else {
        let lower = f.lower_factor();
        (factor_margin(&lower, stored), Some(lower))
    };
    let mut m = m7a.map_or(apriori, |m| m.min(apriori));
    if let Some((pattern, values, alpha, sigma)) = posterior.filter(|_| m > need) {
        let lower = lower.unwrap_or_else(|| f.lower_factor());
        if let Some(p) = posterior_margin(&lower, pattern, values, alpha, sigma) {
            m = m.min(p);
        }
    }
    m
}

crate::dd::fma_dispatch! {
    /// Lemma 7 (a-posteriori margin): `m` with `xᵀBx ≥ −m Σ_i b̃_ii x_i²` for the exact
    /// `B = αA + σI` (α = ±1; A: `values` on `pattern`, CSC, both triangles, its lower triangle
    /// being what the factorization read) from a factor `PB̃Pᵀ ≈ L̂L̂ᵀ` that succeeded, with
    /// `b̃_ii = fl(αa_ii + σ)` the stored diagonal of the test matrix. None where a `b̃_ii ≤ 0`.
    ///
    /// `E = L̂L̂ᵀ − PBPᵀ` is formed entry by entry over every position that L̂L̂ᵀ or B reaches,
    /// by compensated sums (Dot2, Ogita, Rump & Oishi 2005: every product exact by two_prod,
    /// B's diagonal `αa_ii + σ` exact by two_sum, `|ê_ij − e_ij| ≤ u|ê_ij| + γ_N²·Σ|terms|` for N
    /// terms), so `|E_ij| ≤ Ē_ij` is known to the u² level. Then for every x, with `y = Px` and
    /// `d_i = √b̃_ii` (permuted), `xᵀBx = ‖L̂ᵀy‖² − yᵀEy ≥ −|y|ᵀĒ|y| ≥ −ρ(D⁻¹ĒD⁻¹)·‖Dy‖²`,
    /// and the Perron root is at most the largest row sum. The margin is that row sum, rounded up
    /// for its own evaluation. It replaces Lemma 1's worst case `c·γ_{r+1}` (thousands of u on a
    /// factor with c, r ≈ 50) by the residual the factorization actually left: a few u to a few
    /// tens of u on this project's matrices.
    ///
    /// Compiled with FMA where the CPU has it (`dd::fma_dispatch`): 153 against 114 µs
    /// on the 400-DOF membrane without and with (docs/history/performance-log.md).
    pub fn posterior_margin(
        factor: &crate::linalg::LowerFactor,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        alpha: f64,
        sigma: f64,
    ) -> Option<f64> => posterior_kernel
}

/// B = αA + σI's lower triangle as the factorization read it (original i ≥ j), permuted by
/// `fwd`, bucketed by the smaller permuted index (`b_ptr`, `b_ent`: (larger index, αa_ij)),
/// and the weights d_i = √(αa_ii + σ) (a missing diagonal entry is σ); None unless every
/// αa_ii + σ is positive and finite ([`posterior_kernel`]).
#[inline(always)]
#[allow(clippy::type_complexity)]
fn permuted_lower(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    alpha: f64,
    sigma: f64,
    fwd: &[usize],
) -> Option<(Vec<usize>, Vec<(usize, f64)>, Vec<f64>)> {
    let n = fwd.len();
    let mut inv = vec![0usize; n];
    for (p, &i) in fwd.iter().enumerate() {
        inv[i] = p;
    }
    // B's lower triangle as the factorization read it (original i ≥ j), permuted, bucketed by
    // the smaller permuted index; the diagonal exactly as αa_ii + σ (a double-double).
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut b_ptr = vec![0usize; n + 1];
    let mut diag = vec![f64::NAN; n];
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i >= j {
                b_ptr[inv[i].min(inv[j]) + 1] += 1;
            }
            if i == j {
                diag[inv[j]] = alpha * values[p] + sigma;
            }
        }
    }
    for q in 0..n {
        b_ptr[q + 1] += b_ptr[q];
    }
    let mut b_ent = vec![(0usize, 0.0f64); b_ptr[n]];
    let mut next = b_ptr.clone();
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i >= j {
                let (pi, pj) = (inv[i], inv[j]);
                let q = pi.min(pj);
                b_ent[next[q]] = (pi.max(pj), alpha * values[p]);
                next[q] += 1;
            }
        }
    }
    // A diagonal entry missing from the pattern is σ; the weights must be positive.
    for d in diag.iter_mut().filter(|d| d.is_nan()) {
        *d = sigma;
    }
    if diag.iter().any(|&d| !(d > 0.0 && d.is_finite())) {
        return None;
    }
    let d: Vec<f64> = diag.iter().map(|&b| b.sqrt()).collect();
    Some((b_ptr, b_ent, d))
}

/// Row lists of the factor L (`lcp`, `lri`, n columns): for each row q, (column k, position
/// of the entry l_qk), in `rows[r_ptr[q]..r_ptr[q + 1]]` ([`posterior_kernel`]).
#[inline(always)]
fn row_lists(lcp: &[usize], lri: &[usize], n: usize) -> (Vec<usize>, Vec<(usize, usize)>) {
    let mut r_ptr = vec![0usize; n + 1];
    for &i in lri.iter() {
        r_ptr[i + 1] += 1;
    }
    for q in 0..n {
        r_ptr[q + 1] += r_ptr[q];
    }
    let mut rows = vec![(0usize, 0usize); r_ptr[n]];
    let mut next = r_ptr.clone();
    for k in 0..n {
        for (t, &i) in lri.iter().enumerate().take(lcp[k + 1]).skip(lcp[k]) {
            rows[next[i]] = (k, t);
            next[i] += 1;
        }
    }
    (r_ptr, rows)
}

/// The body of [`posterior_margin`], inlined into each target-feature build.
#[inline(always)]
fn posterior_kernel(
    factor: &crate::linalg::LowerFactor,
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    alpha: f64,
    sigma: f64,
) -> Option<f64> {
    let n = factor.col_ptr.len() - 1;
    let (lcp, lri, lv) = (&factor.col_ptr, &factor.row_idx, &factor.values);
    let ident: Vec<usize>;
    let fwd = match &factor.fwd {
        Some(f) => f.as_slice(),
        None => {
            ident = (0..n).collect();
            &ident
        }
    };
    let (b_ptr, b_ent, d) = permuted_lower(pattern, values, alpha, sigma, fwd)?;
    let (r_ptr, rows) = row_lists(lcp, lri, n);
    let terms = (0..n).map(|q| r_ptr[q + 1] - r_ptr[q]).max().unwrap_or(0) + 2;
    let g2 = gamma(terms).powi(2);
    // ‖l_p‖ rounded up: Σ_k |l_pk l_qk| ≤ ‖l_p‖‖l_q‖ bounds the products' part of Dot2's
    // Σ|terms| (Cauchy–Schwarz), so the loop below need not sum their magnitudes.
    let mut norm2 = vec![0.0f64; n];
    for (&i, &v) in lri.iter().zip(lv.iter()) {
        norm2[i] += v * v;
    }
    let norm: Vec<f64> = norm2
        .iter()
        .map(|&s| up(s * (1.0 + gamma(terms))).sqrt() * (1.0 + 2.0 * U))
        .collect();
    // Dot2 accumulators (leading sum, error sum) and |B's terms|, per row.
    let mut acc = vec![[0.0f64; 2]; n];
    let mut babs = vec![0.0f64; n];
    let mut mark = vec![usize::MAX; n];
    let mut touched = Vec::new();
    let mut rowsum = vec![0.0f64; n];
    let mut widest = 0usize;
    // One Dot2 step: the term h (with the exact error e of its product) into entry p.
    #[inline(always)]
    fn add(a: &mut [f64; 2], h: f64, e: f64) {
        let (s, q) = two_sum(a[0], h);
        a[0] = s;
        a[1] += q + e;
    }
    for q in 0..n {
        touched.clear();
        for &(k, pos) in &rows[r_ptr[q]..r_ptr[q + 1]] {
            let lqk = lv[pos];
            let end = lcp[k + 1];
            for (&p, &lpk) in lri[pos..end].iter().zip(&lv[pos..end]) {
                if mark[p] != q {
                    mark[p] = q;
                    touched.push(p);
                }
                let (h, e) = two_prod(lpk, lqk);
                add(&mut acc[p], h, e);
            }
        }
        let mut diagonal_seen = false;
        for &(p, v) in &b_ent[b_ptr[q]..b_ptr[q + 1]] {
            if mark[p] != q {
                mark[p] = q;
                touched.push(p);
            }
            if p == q {
                // −(αa_qq + σ) exactly: two terms.
                diagonal_seen = true;
                let (h, e) = two_sum(-v, -sigma);
                add(&mut acc[p], h, 0.0);
                add(&mut acc[p], e, 0.0);
                babs[p] += h.abs() + e.abs();
            } else {
                add(&mut acc[p], -v, 0.0);
                babs[p] += v.abs();
            }
        }
        if !diagonal_seen {
            // A structurally missing diagonal is σ.
            if mark[q] != q {
                mark[q] = q;
                touched.push(q);
            }
            add(&mut acc[q], -sigma, 0.0);
            babs[q] += sigma.abs();
        }
        widest = widest.max(touched.len());
        for &p in &touched {
            let [hi, lo] = acc[p];
            let e = hi + lo;
            // |E_pq| ≤ |ê|(1 + 2u) + 2γ_N²·Σ|terms| (Dot2's bound solved for |E_pq|), with
            // Σ|terms| ≤ ‖l_p‖‖l_q‖ + |B's terms|, doubled for the rounding of its own sums.
            let abs = up(norm[p] * norm[q]) + babs[p];
            let bound = up(up(e.abs() * (1.0 + 2.0 * U)) + up(4.0 * g2 * abs));
            let f = up(bound / (d[p] * d[q]));
            rowsum[p] += f;
            if p != q {
                rowsum[q] += f;
            }
            acc[p] = [0.0; 2];
            babs[p] = 0.0;
        }
    }
    let m = rowsum.iter().fold(0.0f64, |a, &b| a.max(b));
    // Each d_i = fl(√b̃_ii) and each quotient carry a rounding, each row sum up to 2·widest.
    let m = up(m * (1.0 + gamma(2 * widest + 8)));
    m.is_finite().then_some(m)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::conditioning::certify::tests::second_difference;
    use crate::conditioning::certify::Margin;
    use crate::dd::Dd;
    use faer::sparse::{SparseColMat, Triplet};

    /// The largest scaled row sum `max_p Σ_q |E_pq| / √(b̃_pp b̃_qq)` of the residual
    /// `E = L̂L̂ᵀ − PBPᵀ`, `B = A − σI`, formed densely in double-double from the factor's
    /// entries — independent of the sparse bookkeeping of [`posterior_margin`].
    fn dense_residual_rowsum(
        a: &SparseColMat<usize, f64>,
        sigma: f64,
        f: &crate::linalg::LowerFactor,
    ) -> f64 {
        let n = a.nrows();
        let fwd: Vec<usize> = f.fwd.clone().unwrap_or_else(|| (0..n).collect());
        let mut l = vec![vec![0.0f64; n]; n];
        for (k, w) in f.col_ptr.windows(2).enumerate() {
            for (&i, &v) in f.row_idx[w[0]..w[1]].iter().zip(&f.values[w[0]..w[1]]) {
                l[i][k] = v;
            }
        }
        let b = |i: usize, j: usize| {
            let v = (a.val_of_col(j).iter())
                .zip(a.symbolic().row_idx_of_col(j))
                .find(|(_, r)| *r == i)
                .map_or(0.0, |(v, _)| *v);
            Dd::from_f64(v) - Dd::from_f64(if i == j { sigma } else { 0.0 })
        };
        let d: Vec<f64> = (0..n)
            .map(|p| (b(fwd[p], fwd[p]).to_f64()).sqrt())
            .collect();
        let mut worst = 0.0f64;
        for p in 0..n {
            let mut sum = 0.0;
            for q in 0..n {
                let mut e = Dd::ZERO - b(fwd[p], fwd[q]);
                for (x, y) in l[p].iter().zip(&l[q]) {
                    e = e + Dd::prod(*x, *y);
                }
                sum += e.to_f64().abs() / (d[p] * d[q]);
            }
            worst = worst.max(sum);
        }
        worst
    }

    /// A 2-D Laplacian-like SPD matrix with a few stiff (penalized) diagonal entries.
    pub(crate) fn graded_grid(side: usize) -> SparseColMat<usize, f64> {
        let n = side * side;
        let mut t = Vec::new();
        for i in 0..n {
            let stiff = if i % 7 == 3 { 1e6 } else { 0.0 };
            t.push(Triplet::new(i, i, 4.0 + 0.01 * (i % 5) as f64 + stiff));
            for j in [i + 1, i + side] {
                if j < n && (j != i + 1 || (i + 1) % side != 0) {
                    t.push(Triplet::new(i, j, -1.0 - 0.001 * (i % 3) as f64));
                    t.push(Triplet::new(j, i, -1.0 - 0.001 * (i % 3) as f64));
                }
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    }

    /// Lemma 7's margin contains the residual's true scaled row sum and is no more than a
    /// rounding above it; Lemma 7a's is never below it; both are far below Lemma 1's worst
    /// case. Shifted (σ > 0) and unshifted, on a sparse grid (AMD-permuted, simplicial) and a
    /// second difference.
    #[test]
    fn margins_bound_the_true_residual() {
        use crate::linalg::DiagonalPattern;
        // A full 200×200 pattern: faer's supernodal factor.
        let full = {
            let n = 200;
            let mut t = Vec::new();
            for i in 0..n {
                for j in 0..n {
                    let v = if i == j {
                        n as f64 + (i % 4) as f64
                    } else {
                        ((i * 7 + j * 7) % 11) as f64 / 11.0 - 0.5
                    };
                    t.push(Triplet::new(i, j, v));
                }
            }
            SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
        };
        for a in [graded_grid(12), second_difference(60), full] {
            let pattern = DiagonalPattern::new(&a).unwrap();
            let supernodal = pattern.factor(&pattern.values).unwrap().is_supernodal();
            assert_eq!(
                supernodal,
                a.nrows() == 200,
                "the panel covers both factor kinds"
            );
            let n = a.nrows();
            for sigma in [0.0, 1e-3] {
                let mut v = pattern.values.clone();
                for &p in pattern.diag.iter() {
                    v[p] -= sigma;
                }
                let f = pattern.factor(&v).expect("positive definite");
                let lower = f.lower_factor();
                let truth = dense_residual_rowsum(&a, sigma, &lower);
                let post = posterior_margin(&lower, a.symbolic(), a.val(), 1.0, -sigma).unwrap();
                let stored: Vec<f64> = pattern.diag.iter().map(|&p| v[p]).collect();
                let mid = factor_margin(&lower, &stored).unwrap();
                let apriori = Margin::of(&pattern.symbolic).m;
                assert!(
                    truth <= post,
                    "n {n} σ {sigma}: {truth:e} > posterior {post:e}"
                );
                assert!(
                    post <= truth * (1.0 + 1e-6) + 1e-30,
                    "{post:e} vs {truth:e}"
                );
                assert!(
                    truth <= mid,
                    "n {n} σ {sigma}: {truth:e} > Lemma 7a {mid:e}"
                );
                assert!(mid <= apriori, "{mid:e} > Lemma 1 {apriori:e}");
                assert!(post <= 32.0 * U, "n {n}: posterior {:.1} u", post / U);
            }
        }
    }

    /// Lemma 7a read in place from a supernodal factor equals Lemma 7a of its copy in
    /// compressed columns (the same terms, summed in another order).
    #[test]
    fn supernodal_margin_in_place_equals_the_copy() {
        use crate::linalg::SparseLlt;
        // The 5-point Laplacian on a 200 × 200 grid.
        let side = 200usize;
        let mut t = Vec::new();
        for i in 0..side {
            for j in 0..side {
                let p = i * side + j;
                t.push(faer::sparse::Triplet::new(p, p, 4.0));
                for (q, ok) in [(p + 1, j + 1 < side), (p + side, i + 1 < side)] {
                    if ok {
                        t.push(faer::sparse::Triplet::new(p, q, -1.0));
                        t.push(faer::sparse::Triplet::new(q, p, -1.0));
                    }
                }
            }
        }
        let n = side * side;
        let k = faer::sparse::SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let sym = SparseLlt::analyze(&k).unwrap();
        let f = SparseLlt::factorize(sym, &k).unwrap();
        assert!(f.is_supernodal(), "a supernodal factor at 40 000 unknowns");
        let diag: Vec<f64> = (0..k.nrows())
            .map(|i| k.get(i, i).copied().unwrap_or(0.0))
            .collect();
        let copy = factor_margin(&f.lower_factor(), &diag).unwrap();
        let in_place = factor_margin_of(&f, &diag).unwrap();
        assert!(
            (in_place / copy - 1.0).abs() <= 1e-12,
            "{in_place:e} vs {copy:e}"
        );
    }
}
