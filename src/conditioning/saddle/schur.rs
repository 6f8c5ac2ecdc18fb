//! |λ⁻_max| of the saddle point through the Schur complement of K onto the constrained DOFs:
//! a proven bracket a few units of rounding wide, however clustered the negative eigenvalues
//! are (the elasticity scenes: gaps of 0.1 %, where Temple's inertia tests cannot isolate one
//! eigenvalue and a Cholesky test's margin is first order).
//!
//! # The congruence
//! For s ≥ 0 (with K_FF ≻ 0), eliminating the multiplier block `sI` and then `K_FF + sI` from
//! `A + sI = [K_FF + sI, K_FB, 0; K_BF, K_BB + sI, I; 0, I, sI]` is a congruence
//! (for s = 0 the multiplier block is eliminated against `I`, the same count):
//!
//! `#{λ < −s} = #{eigenvalues of S_B(s) below 1/s}`, `S_B(s) = K_BB + sI − K_BF (K_FF + sI)⁻¹ K_FB`.
//!
//! `S_B(s)` grows with s (`d/ds S_B = I + X_sᵀX_s ⪰ I`, `X_s = (K_FF + sI)⁻¹K_FB`), so
//! `ν(s) = λ_max(S_B(s))` is increasing and `|λ⁻_max|` is the one root s* of `s·ν(s) = 1`.
//!
//! **Lemma S1.** If `ν(s) ∈ [ν_lo, ν_hi]` (ν_lo > 0) at some s ≥ 0, then
//! `|λ⁻_max| ∈ [min(s, 1/ν_hi), max(s, 1/ν_lo)]`.
//! *Proof.* For `t < min(s, 1/ν_hi)`: `ν(t) ≤ ν(s) ≤ ν_hi < 1/t`, so all m eigenvalues of
//! `S_B(t)` lie below 1/t and all m negative eigenvalues of A below −t. For
//! `t ≥ max(s, 1/ν_lo)`: `ν(t) ≥ ν(s) ≥ ν_lo ≥ 1/t`, so at most m − 1 lie below −t: one lies
//! in [−t, 0). ∎ The width is `|s − 1/ν(s)|` plus ν's own. Each next s is the root of
//! `t·(ν(s) + ν'(s)(t − s)) = 1`, ν linearized with `ν'(s) = vᵀ(I + X_sᵀX_s)v` (v the top
//! eigenvector; exact where K_BF = 0): Newton's method on `s·ν(s) − 1`, which places s at s*
//! to rounding in one or two steps from the Lanczos estimate.
//!
//! # ν(s) enclosed (Lemma S2)
//! With X̂ any matrix (the m solves with the Cholesky factor of `K_FF + sI`),
//! `R = K_FB − (K_FF + sI)X̂` and `S' = K_BB + sI − K_BF X̂ − X̂ᵀR` (symmetric: it equals
//! `K_BB + sI − K_BF X̂ − X̂ᵀK_FB + X̂ᵀ(K_FF + sI)X̂`), exact algebra gives
//! `S_B(s) = S' − Rᵀ(K_FF + sI)⁻¹R`, so `S' − ‖R‖²/(λ_min(K_FF) + s)·I ⪯ S_B(s) ⪯ S'`: the
//! solves' error enters to second order. R̂ and Ŝ ≈ S' are computed in f64 with entrywise
//! bounds of their rounding (Higham's dot-product bound `γ_k Σ|terms|`); `e ≥ ‖Ŝ_sym − S'‖₂`
//! by the Frobenius norm of the entrywise bound. Then
//! `ν_lo = ρ_lo(v) − e − ‖R‖²_F / (λ_min(K_FF) + s)` (ρ_lo the Rayleigh quotient of Ŝ_sym's
//! top eigenvector, its rounding bounded) and `ν_hi = t + γ_{m+1}·ρ(|L̂||L̂ᵀ|) + u·max_i T̂_ii + e`
//! once the dense Cholesky of `T̂ = fl(tI − Ŝ_sym)` succeeds (`L̂L̂ᵀ = T̂ + ΔT`,
//! `|ΔT| ≤ γ_{m+1}|L̂||L̂ᵀ|`, Higham's Theorem 10.3 for any order of the inner products;
//! ρ(|L̂||L̂ᵀ|) bounded by Collatz–Wielandt with the vector of ones).
//!
//! λ_min(K_FF) enters only this second-order term; the caller supplies a proven lower bound
//! (0 is allowed: then `λ_min(K_FF) + s ≥ s`, valid once K_FF ⪰ 0 is proven, which every
//! positive lower bound of λ⁺_min proves: `H(σ) ≻ 0` contains `K_FF − σI ≻ 0`).
//!
//! Cost per evaluation: one numeric factorization of `K_FF + sI` (none at s = 0: K_FF's own),
//! m solves, O(m·nnz(K) + N·m²) for R̂ and Ŝ, and an m×m eigendecomposition and Cholesky;
//! memory 3·N·m. Used for m ≤ [`MAX_M`] and N·m ≤ [`MAX_ENTRIES`], where Temple's bound of
//! the negative side is not had.

use super::shifts::Shifts;
use crate::conditioning::certify::{gamma, residual_dot2, up, U};
use crate::linalg::{DiagonalPattern, SparseLlt};
use faer::{Mat, Side};

/// Largest m for which the negative side is bracketed through S_B.
pub const MAX_M: usize = 400;
/// Largest N·m (the dense N×m blocks X̂, R̂ and their bounds).
pub const MAX_ENTRIES: usize = 4_000_000;
/// Evaluations of ν(s) per bracket (the first from the Lanczos estimate or s = 0).
const MAX_EVALUATIONS: usize = 6;

/// A proven bracket of |λ⁻_max| and the Newton value inside it.
#[derive(Clone, Copy, Debug)]
pub(super) struct NegativeBracket {
    pub lo: f64,
    pub hi: f64,
    pub value: f64,
}

/// ν(s) enclosed, its f64 value and the slope of `s·ν(s)`'s Newton step.
struct Nu {
    lo: f64,
    hi: f64,
    value: f64,
    slope: f64,
}

fn down(x: f64) -> f64 {
    x * (1.0 - 8.0 * U)
}

/// |λ⁻_max| bracketed by Lemmas S1–S2 from `start` (an estimate; 0 or None: from s = 0 with
/// K_FF's factor `kff`), stopping once `hi/lo − 1 ≤ tol` or after [`MAX_EVALUATIONS`].
/// `kff_lo ≥ 0`: a lower bound of λ_min(K_FF) (0: the caller proves K_FF ⪰ 0). None where the
/// sizes exceed the limits or no evaluation encloses ν.
pub(super) fn negative_bracket(
    shifts: &mut Shifts,
    kff: &SparseLlt,
    dofs: &[usize],
    start: Option<f64>,
    kff_lo: f64,
    tol: f64,
) -> Option<NegativeBracket> {
    let (n, m) = (shifts.pattern.n(), dofs.len());
    if m == 0 || m > MAX_M || n.saturating_mul(m) > MAX_ENTRIES {
        return None;
    }
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    let mut s = start.filter(|v| v.is_finite() && *v > 0.0).unwrap_or(0.0);
    let mut value = None;
    for _ in 0..MAX_EVALUATIONS {
        let nu = evaluate(shifts, kff, dofs, s, kff_lo)?;
        if nu.hi > 0.0 {
            lo = lo.max(s.min(down(1.0 / nu.hi)));
        }
        if nu.lo > 0.0 {
            hi = hi.min(s.max(up(1.0 / nu.lo)));
        }
        // The root of t·(ν + slope·(t − s)) = 1: ν(t) linearized at s (exact where K_BF = 0).
        let b = nu.value - nu.slope * s;
        let next = 2.0 / (b + (b * b + 4.0 * nu.slope).sqrt());
        value = Some(next);
        if lo > 0.0 && hi.is_finite() && hi / lo - 1.0 <= tol {
            break;
        }
        if !(next.is_finite() && next > 0.0) || next == s {
            break;
        }
        s = next;
    }
    (lo > 0.0 && hi.is_finite() && lo <= hi).then(|| NegativeBracket {
        lo,
        hi,
        value: value.unwrap_or(lo).clamp(lo, hi),
    })
}

/// Y, the F part of K's B columns `dofs` (the right-hand sides), and X̂ solved from it with
/// `factor` (of K_FF + sI), both column-major n × m with B rows 0 (any X̂ serves Lemma S2;
/// these are the solves' own).
fn solved_columns(
    pattern: &DiagonalPattern,
    in_b: &[bool],
    dofs: &[usize],
    factor: &SparseLlt,
) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (pattern.n(), dofs.len());
    let (cp, ri, vals) = (
        pattern.pattern.col_ptr(),
        pattern.pattern.row_idx(),
        pattern.values.as_slice(),
    );
    let mut y = vec![0.0; n * m];
    for (j, &d) in dofs.iter().enumerate() {
        for p in cp[d]..cp[d + 1] {
            if !in_b[ri[p]] {
                y[j * n + ri[p]] = vals[p];
            }
        }
    }
    let mut x = Mat::<f64>::zeros(n, m);
    for j in 0..m {
        for f in 0..n {
            x[(f, j)] = y[j * n + f];
        }
    }
    factor.solve_mat_in_place(x.as_mut());
    let mut xs = vec![0.0; n * m];
    for j in 0..m {
        for f in 0..n {
            if !in_b[f] {
                xs[j * n + f] = x[(f, j)];
            }
        }
    }
    (y, xs)
}

/// R̂ = Y − (K_FF + sI)X̂ by compensated dot products (`certify::residual_dot2`: its bound is
/// u|r̂| plus second-order terms), and ΔR ≥ |R̂ − R|, R with the exact K_FF + sI: the stored
/// diagonal fl(k_ff + s) (in `kfs`) is off by ≤ u|fl(k_ff + s)|, times |x̂_f|. B rows: 0.
fn residuals(
    pattern: &DiagonalPattern,
    in_b: &[bool],
    kfs: &[f64],
    xs: &[f64],
    y: &[f64],
    m: usize,
) -> (Vec<f64>, Vec<f64>) {
    let n = pattern.n();
    let kfs_pattern = pattern.pat();
    let mut r = vec![0.0; n * m];
    let mut dr = vec![0.0; n * m];
    for j in 0..m {
        let (xj, yj) = (&xs[j * n..(j + 1) * n], &y[j * n..(j + 1) * n]);
        let res = residual_dot2(kfs_pattern, kfs, xj, 1.0, yj);
        for (f, (rf, ef)) in res.into_iter().enumerate() {
            if in_b[f] {
                continue;
            }
            r[j * n + f] = rf;
            dr[j * n + f] = up(ef + U * (kfs[pattern.diag[f]] * xj[f]).abs());
        }
    }
    (r, dr)
}

/// ν(s) = λ_max(S_B(s)) enclosed by Lemma S2.
fn evaluate(
    shifts: &mut Shifts,
    kff: &SparseLlt,
    dofs: &[usize],
    s: f64,
    kff_lo: f64,
) -> Option<Nu> {
    let pattern = shifts.pattern;
    let in_b = &shifts.blocks.in_b;
    let (n, m) = (pattern.n(), dofs.len());
    let (cp, ri, vals) = (
        pattern.pattern.col_ptr(),
        pattern.pattern.row_idx(),
        pattern.values.as_slice(),
    );
    // K_FF + sI with B's rows and columns the identity: the factored matrix (K_FF's own at
    // s = 0) and the one R̂ is formed with.
    let mut kfs = Vec::new();
    super::free_block_values(pattern, in_b, s, &mut kfs);
    let shifted;
    let factor = if s > 0.0 {
        shifts.factorizations += 1;
        shifted = pattern.factor(&kfs)?;
        &shifted
    } else {
        kff
    };
    let (y, xs) = solved_columns(pattern, in_b, dofs, factor);
    let max_col = (0..n).map(|j| cp[j + 1] - cp[j]).max().unwrap_or(0);
    let (r, dr) = residuals(pattern, in_b, &kfs, &xs, &y, m);
    // Ŝ ≈ S' = K_BB + sI − K_BF X̂ − X̂ᵀR and E ≥ |Ŝ − S'| entrywise.
    let mut pos = vec![usize::MAX; n];
    for (c, &d) in dofs.iter().enumerate() {
        pos[d] = c;
    }
    let (g_a, g_b, g3) = (gamma(max_col), gamma(n), gamma(3));
    let mut sh = Mat::<f64>::zeros(m, m);
    let mut e = Mat::<f64>::zeros(m, m);
    for i in 0..m {
        let d = dofs[i];
        let xi = &xs[i * n..(i + 1) * n];
        for j in 0..m {
            let xj = &xs[j * n..(j + 1) * n];
            let (mut a, mut abs_a, mut kbb) = (0.0, 0.0, 0.0);
            for p in cp[d]..cp[d + 1] {
                let row = ri[p];
                if in_b[row] {
                    if pos[row] == j {
                        kbb = vals[p];
                    }
                } else {
                    let t = vals[p] * xj[row];
                    a += t;
                    abs_a += t.abs();
                }
            }
            let rj = &r[j * n..(j + 1) * n];
            let drj = &dr[j * n..(j + 1) * n];
            let (mut b, mut abs_b, mut xdr) = (0.0, 0.0, 0.0);
            for f in 0..n {
                let t = xi[f] * rj[f];
                b += t;
                abs_b += t.abs();
                xdr += xi[f].abs() * drj[f];
            }
            let diag = if i == j { s } else { 0.0 };
            let v = kbb + diag - a - b;
            sh[(i, j)] = v;
            e[(i, j)] = up(g3 * (kbb.abs() + diag + a.abs() + b.abs())
                + (1.0 + g3) * (g_a * abs_a + g_b * abs_b + xdr * (1.0 + g_b)));
        }
    }
    // Symmetrized, with its rounding; e ≥ ‖Ŝ_sym − S'‖₂ by the Frobenius norm.
    let sym = Mat::from_fn(m, m, |i, j| 0.5 * (sh[(i, j)] + sh[(j, i)]));
    let mut fro = 0.0;
    for j in 0..m {
        for i in 0..m {
            let t = 0.5 * (e[(i, j)] + e[(j, i)]) + U * sym[(i, j)].abs();
            fro += t * t;
        }
    }
    let e_norm = fro.sqrt() * (1.0 + gamma(m * m + 2));
    // ‖R‖_F ≤ ‖R̂‖_F + ‖ΔR‖_F; the second-order term over λ_min(K_FF + sI) ≥ kff_lo + s.
    let norm = |v: &[f64]| v.iter().map(|t| t * t).sum::<f64>().sqrt() * (1.0 + gamma(n * m + 2));
    let r_norm = up(norm(&r) + norm(&dr));
    let second = if kff_lo + s > 0.0 {
        up(r_norm * r_norm / down(kff_lo + s))
    } else {
        f64::INFINITY
    };
    let eig = sym.self_adjoint_eigen(Side::Lower).ok()?;
    let top = eig.S()[m - 1];
    let v: Vec<f64> = (0..m).map(|i| eig.U()[(i, m - 1)]).collect();
    let (rho_lo, rho_hi) = rayleigh_dense(&sym, &v)?;
    let hat_hi = top_upper(&sym, rho_hi.max(top))?;
    // The slope of s·ν(s): ν + s·vᵀ(I + X̂ᵀX̂)v (Newton only, not part of any bound).
    let xv: f64 = (0..n)
        .map(|f| (0..m).map(|j| xs[j * n + f] * v[j]).sum::<f64>().powi(2))
        .sum();
    let vv: f64 = v.iter().map(|t| t * t).sum();
    Some(Nu {
        lo: down(rho_lo - e_norm - second),
        hi: up(hat_hi + e_norm),
        value: top,
        slope: 1.0 + xv / vv,
    })
}

/// The Rayleigh quotient of the symmetric `a` at v, as an interval: `vᵀAv` with
/// `γ_{2m}|v|ᵀ|A||v|` and `vᵀv` with `γ_m vᵀv` of rounding. None unless `vᵀAv` is positive.
fn rayleigh_dense(a: &Mat<f64>, v: &[f64]) -> Option<(f64, f64)> {
    let m = v.len();
    let (mut num, mut abs, mut den) = (0.0, 0.0, 0.0);
    for i in 0..m {
        let (mut w, mut wa) = (0.0, 0.0);
        for j in 0..m {
            w += a[(i, j)] * v[j];
            wa += (a[(i, j)] * v[j]).abs();
        }
        num += v[i] * w;
        abs += v[i].abs() * wa;
        den += v[i] * v[i];
    }
    let err = up(gamma(2 * m + 1) * abs);
    let (g, d) = (gamma(m + 1), den);
    (num - err > 0.0 && d > 0.0).then(|| {
        (
            down((num - err) / (d * (1.0 + g))),
            up((num + err) / (d * (1.0 - g))),
        )
    })
}

/// A proven upper bound of λ_max of the symmetric `a` near `t0`: the dense Cholesky of
/// `T̂ = fl(tI − A)` succeeds at `t = t0(1 + w)` (w from 8m·u, ×8 per failure), and then
/// `λ_max ≤ t + γ_{m+1}·ρ(|L̂||L̂ᵀ|) + u'·max_i T̂_ii` (Lemma S2).
fn top_upper(a: &Mat<f64>, t0: f64) -> Option<f64> {
    let m = a.nrows();
    let mut w = 8.0 * m as f64 * U;
    for _ in 0..12 {
        let t = t0 + w * t0.abs();
        let tm = Mat::from_fn(m, m, |i, j| if i == j { t - a[(i, j)] } else { -a[(i, j)] });
        if let Some(slack) = cholesky_slack(&tm) {
            return Some(up(t + slack));
        }
        w *= 8.0;
    }
    None
}

/// Where the dense Cholesky of the stored symmetric `tm` succeeds, `c` with `T ⪰ −c·I` for
/// every T that `tm` rounds (its diagonal formed by one subtraction):
/// `γ_{m+1}·ρ(|L̂||L̂ᵀ|) + 2u·max_i |t̂_ii|` (Higham's Theorem 10.3, ρ bounded by
/// Collatz–Wielandt with the vector of ones). None where the Cholesky fails.
pub(super) fn cholesky_slack(tm: &Mat<f64>) -> Option<f64> {
    let m = tm.nrows();
    let llt = tm.llt(Side::Lower).ok()?;
    let l = llt.L();
    // Collatz–Wielandt with the vector of ones: ρ(|L||Lᵀ|) ≤ max_i (|L|(|Lᵀ|1))_i.
    let col: Vec<f64> = (0..m)
        .map(|j| (j..m).map(|i| l[(i, j)].abs()).sum())
        .collect();
    let cw = (0..m)
        .map(|i| (0..=i).map(|j| l[(i, j)].abs() * col[j]).sum::<f64>())
        .fold(0.0, f64::max)
        * (1.0 + gamma(2 * m + 2));
    let tmax = (0..m).map(|i| tm[(i, i)].abs()).fold(0.0, f64::max);
    Some(gamma(m + 1) * cw + 2.0 * U * tmax)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::DiagonalPattern;
    use faer::sparse::{SparseColMat, Triplet};

    /// The width a bracket reaches on these tiny matrices: a few tens of rounding units (the
    /// Rayleigh quotient's `γ_{2m+1}`, the Cholesky test's `γ_{m+1}·ρ(|L̂||L̂ᵀ|)`, the outward
    /// roundings of both ends and of 1/ν).
    const WIDTH: f64 = 256.0 * U;

    /// The bracket of `A = [K D; Dᵀ 0]` for K given by triplets, B = `dofs`, from `start`.
    fn bracket_of(
        n: usize,
        entries: &[(usize, usize, f64)],
        dofs: &[usize],
        start: Option<f64>,
    ) -> NegativeBracket {
        let t: Vec<Triplet<usize, usize, f64>> = entries
            .iter()
            .map(|&(i, j, v)| Triplet::new(i, j, v))
            .collect();
        let k = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let pattern = DiagonalPattern::new(&k).unwrap();
        let in_b = super::super::dof_mask(n, dofs).unwrap();
        let kff = super::super::free_block_factor(&pattern, &in_b).unwrap();
        let blocks = super::super::Blocks::selection(dofs, in_b);
        let mut shifts = Shifts {
            pattern: &pattern,
            blocks: &blocks,
            factorizations: 1,
            work: Vec::new(),
        };
        negative_bracket(&mut shifts, &kff, dofs, start, 0.0, 1e-15).expect("a bracket")
    }

    /// Decoupled constrained DOFs of equal stiffness k: |λ⁻_max| is an m-fold eigenvalue (the
    /// cluster Temple's bound cannot isolate), `2/(k + √(k² + 4))` of each block `[k 1; 1 0]`.
    #[test]
    fn a_multiple_negative_eigenvalue_is_bracketed_to_rounding() {
        for k in [1e-3, 1.0, 1e5] {
            let n = 10;
            let mut e: Vec<(usize, usize, f64)> = (0..n)
                .map(|i| (i, i, if i < 5 { k } else { 2.0 + i as f64 }))
                .collect();
            e.push((7, 8, -0.5));
            e.push((8, 7, -0.5));
            let b = bracket_of(n, &e, &[0, 1, 2, 3, 4], None);
            let exact = 2.0 / (k + (k * k + 4.0).sqrt());
            let slack = 4.0 * f64::EPSILON * exact;
            assert!(
                b.lo - slack <= exact && exact <= b.hi + slack,
                "k {k}: {exact:e} ∉ [{:e}, {:e}]",
                b.lo,
                b.hi
            );
            assert!(
                b.hi / b.lo - 1.0 <= WIDTH,
                "k {k}: width {:e}",
                b.hi / b.lo - 1.0
            );
            assert!(
                (b.value / exact - 1.0).abs() <= 1e-14,
                "k {k}: value {:e}",
                b.value
            );
        }
    }

    /// A coupled K (the second difference, 20 DOFs, B = 0, 2, 4, 6) against nalgebra's
    /// symmetric eigensolver on the dense saddle point (error ≲ n·ε·‖A‖ = 2e-14 absolute, on
    /// |λ⁻_max| ≈ 0.4), from the Lanczos-like start and from s = 0.
    #[test]
    fn a_coupled_saddle_point_agrees_with_a_dense_eigensolver() {
        let n = 20;
        let dofs = [0usize, 2, 4, 6];
        let mut e = Vec::new();
        for i in 0..n {
            e.push((i, i, 2.0));
            if i + 1 < n {
                e.push((i, i + 1, -1.0));
                e.push((i + 1, i, -1.0));
            }
        }
        let size = n + dofs.len();
        let mut a = nalgebra::DMatrix::<f64>::zeros(size, size);
        for &(i, j, v) in &e {
            a[(i, j)] = v;
        }
        for (c, &d) in dofs.iter().enumerate() {
            a[(d, n + c)] = 1.0;
            a[(n + c, d)] = 1.0;
        }
        let eig = nalgebra::SymmetricEigen::new(a);
        let exact = eig
            .eigenvalues
            .iter()
            .filter(|&&l| l < 0.0)
            .map(|l| -l)
            .fold(f64::INFINITY, f64::min);
        for start in [None, Some(exact * (1.0 + 1e-6))] {
            let b = bracket_of(n, &e, &dofs, start);
            let slack = 1e-13 * exact;
            assert!(
                b.lo - slack <= exact && exact <= b.hi + slack,
                "{exact:e} ∉ [{:e}, {:e}]",
                b.lo,
                b.hi
            );
            assert!(b.hi / b.lo - 1.0 <= WIDTH, "width {:e}", b.hi / b.lo - 1.0);
        }
    }
}
