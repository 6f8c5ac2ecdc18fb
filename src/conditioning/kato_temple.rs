//! Second-order bounds for the dense eigen and SVD routes: the Kato–Temple inequality on the
//! extreme pairs, with the neighbours' Kahan enclosures as the gap.
//!
//! For a symmetric J, a vector x ≠ 0 with Rayleigh quotient `ρ = xᵀJx / xᵀx` and residual
//! `η = ‖Jx − ρx‖ / ‖x‖`:
//!
//! * **Lower bound.** If `ρ < β` and λ is the largest eigenvalue of J below β, then
//!   `λ ≥ ρ − η² / (β − ρ)`.
//! * **Upper bound.** If `ρ > α` and λ is the smallest eigenvalue of J above α, then
//!   `λ ≤ ρ + η² / (ρ − α)`.
//!
//! *Proof* (Kato 1949; Temple 1928). `(J − λI)(J − βI)` is positive semidefinite, since every
//! eigenvalue μ of J has `(μ − λ)(μ − β) ≥ 0` (none lies strictly between λ and β). So
//! `0 ≤ xᵀ(J − λ)(J − β)x / xᵀx = η² + ρ² − (λ + β)ρ + λβ = η² − (β − ρ)(ρ − λ)`, whence
//! `ρ − λ ≤ η² / (β − ρ)`. The upper bound is the same argument with `(J − λ)(J − α)`. ∎
//!
//! **Use here.** The dense routes know every eigenvalue (or singular value) to Kahan's radius R
//! ([`super::residual_radius`]): sorted, `|λ_(i) − θ_(i)| ≤ R`. For the eigenvalue λ_(j) that
//! sets σ_max or σ_min, `β = θ_(j+1) − R ≤ λ_(j+1)` and `α = θ_(j−1) + R ≥ λ_(j−1)`, and the
//! computed eigenvector x_j gives `λ_(j) ∈ [ρ − η²/(β − ρ), ρ + η²/(ρ − α)]` (if λ_(j) ≥ β, it is
//! above ρ anyway; if λ_(j) ≤ α, below ρ). η is of the order of the dense routine's backward
//! error (≈ ε_mach·‖A‖), so the bracket is second order, `(ε_mach‖A‖)² / gap`, where Kahan's is
//! first order, `R ≈ n·ε_mach·‖A‖`: on a matrix with cond₂ = 1e8 and n = 64, ≈ 1e-15 relative
//! against ≈ 1e-6. For the SVD `A ≈ ÛΣ̂V̂ᵀ`, J is the Jordan–Wielandt matrix `[0 A; Aᵀ 0]`
//! (eigenvalues ±σ_i) and `x = [û_j; v̂_j]`; the neighbour of σ_min below is −σ_min.
//!
//! **Rounding.** `Jx − cx` (c the f64 Rayleigh quotient) is formed by compensated dot products
//! with a bound on each entry's error ([`super::certify`]'s `residual_dot2`), `xᵀx` and
//! `xᵀ(cx − Jx)` in double-double as intervals, so `ρ` is enclosed to ≈ u² and
//! `η² ≤ ‖Jx − cx‖² / xᵀx` (ρ minimizes the residual over c) is an upper bound; every final
//! operation is rounded outwards. What is proven: the returned σ brackets hold for the stored
//! matrix, given Kahan's radius R (itself proven, [`super::residual_radius`]).
//!
//! When the gap is not resolved (`ρ` not inside (α, β): σ_min below R, clustered extreme
//! values) the bracket is not returned and the route keeps Kahan's.

use super::certify::{dot_interval, gamma, residual_dot2};
use faer::sparse::SparseColMat;
use faer::MatRef;

/// One symmetric matrix J, applied blockwise: `(cx − Jx)` for a vector x of J's dimension,
/// each entry with a bound on its rounding error.
enum Jordan<'a> {
    /// J = A (symmetric), both triangles stored.
    Symmetric(&'a SparseColMat<usize, f64>),
    /// J = `[0 A; Aᵀ 0]`: A and Aᵀ in compressed columns (A's columns are Aᵀ's rows).
    Wielandt {
        a: &'a SparseColMat<usize, f64>,
        at: &'a SparseColMat<usize, f64>,
    },
}

impl Jordan<'_> {
    /// `cx − Jx` entrywise, with error bounds.
    fn residual(&self, x: &[f64], c: f64) -> Vec<(f64, f64)> {
        match self {
            Jordan::Symmetric(a) => residual_dot2(a.symbolic(), a.val(), x, c, x),
            Jordan::Wielandt { a, at } => {
                let n = a.nrows();
                let (u, v) = x.split_at(n);
                // (cu − Av)_i: columns of Aᵀ dotted with v; (cv − Aᵀu)_j: columns of A with u.
                let mut r = residual_dot2(at.symbolic(), at.val(), v, c, u);
                r.extend(residual_dot2(a.symbolic(), a.val(), u, c, v));
                r
            }
        }
    }
}

/// `x` moved outwards by two ulps: a bound for one correctly rounded operation, with margin.
fn lower(x: f64) -> f64 {
    x.next_down().next_down()
}

fn upper(x: f64) -> f64 {
    x.next_up().next_up()
}

/// `[n_lo, n_hi] / [d_lo, d_hi]` for `0 < d_lo ≤ d_hi`, rounded outwards.
fn divide(n_lo: f64, n_hi: f64, d_lo: f64, d_hi: f64) -> (f64, f64) {
    let lo = if n_lo >= 0.0 {
        n_lo / d_hi
    } else {
        n_lo / d_lo
    };
    let hi = if n_hi >= 0.0 {
        n_hi / d_lo
    } else {
        n_hi / d_hi
    };
    (lower(lo), upper(hi))
}

/// The rigorous Rayleigh quotient `[ρ_lo, ρ_hi]` of x and an upper bound of `η²`.
fn rayleigh_residual(j: &Jordan<'_>, x: &[f64]) -> Option<(f64, f64, f64)> {
    let (xx_lo, xx_hi) = dot_interval(x, x);
    if !(xx_lo > 0.0 && xx_hi.is_finite()) {
        return None;
    }
    // c: a first f64 Rayleigh quotient (any c works; the closer to ρ, the smaller ‖Jx − cx‖).
    let c = {
        let r0 = j.residual(x, 0.0);
        -r0.iter().zip(x).map(|((r, _), xi)| r * xi).sum::<f64>() / (xx_lo + xx_hi) * 2.0
    };
    if !c.is_finite() {
        return None;
    }
    let res = j.residual(x, c);
    let r: Vec<f64> = res.iter().map(|(r, _)| *r).collect();
    // xᵀ(cx − Jx) ∈ xᵀr̂ ± Σ|x_i| e_i.
    let n = x.len();
    let slack = res
        .iter()
        .zip(x)
        .map(|((_, e), xi)| xi.abs() * e)
        .sum::<f64>()
        * (1.0 + gamma(n + 2));
    let (d_lo, d_hi) = dot_interval(x, &r);
    let (t_lo, t_hi) = divide(lower(d_lo - slack), upper(d_hi + slack), xx_lo, xx_hi);
    // ρ = c − xᵀ(cx − Jx)/xᵀx.
    let (rho_lo, rho_hi) = (lower(c - t_hi), upper(c - t_lo));
    // ‖cx − Jx‖ ≤ ‖r̂‖ + ‖e‖.
    let (mut sq, mut err2) = (0.0f64, 0.0f64);
    for (ri, ei) in &res {
        sq += ri * ri;
        err2 += ei * ei;
    }
    let g = 1.0 + gamma(n + 4);
    let norm = upper(upper((sq * g).sqrt()) + upper((err2 * g).sqrt()));
    let eta2 = upper(upper(norm * norm) / xx_lo);
    (rho_lo.is_finite() && rho_hi.is_finite() && eta2.is_finite()).then_some((rho_lo, rho_hi, eta2))
}

/// A proven bracket `[lo, hi]` of the eigenvalue λ_(j) of J whose neighbours satisfy
/// `λ_(j−1) ≤ alpha` and `λ_(j+1) ≥ beta` (±∞ where there is none), from the vector x, and
/// the enclosed Rayleigh quotient's midpoint. None where ρ is not inside (α, β).
fn bracket(j: &Jordan<'_>, x: &[f64], alpha: f64, beta: f64) -> Option<Refined> {
    let (rho_lo, rho_hi, eta2) = rayleigh_residual(j, x)?;
    if !(rho_lo > alpha && rho_hi < beta) {
        return None;
    }
    let lo = if beta.is_finite() {
        lower(rho_lo - upper(eta2 / lower(beta - rho_hi)))
    } else {
        rho_lo
    };
    let hi = if alpha.is_finite() {
        upper(rho_hi + upper(eta2 / lower(rho_lo - alpha)))
    } else {
        rho_hi
    };
    Some(Refined {
        lo,
        hi,
        value: 0.5 * (rho_lo + rho_hi),
    })
}

/// A refined eigenvalue: proven `[lo, hi]` and the Rayleigh quotient, the best estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refined {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// The Rayleigh quotient of the computed vector (inside `[lo, hi]`).
    pub value: f64,
}

/// σ_max and σ_min of a dense matrix refined by Kato–Temple, each where it applies.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extremes {
    /// σ_max's bracket and estimate.
    pub max: Option<Refined>,
    /// σ_min's bracket and estimate.
    pub min: Option<Refined>,
}

/// The permutation that sorts `values` ascending, and the sorted values (Kahan's pairing is
/// between sorted lists).
fn ascending(values: &[f64]) -> (Vec<usize>, Vec<f64>) {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&p, &q| values[p].total_cmp(&values[q]));
    let sorted = order.iter().map(|&p| values[p]).collect();
    (order, sorted)
}

/// Symmetric A with eigenvalues `lambda` (any order) and eigenvectors `vectors` (columns),
/// Kahan's radius `radius`: brackets of `max |λ|` and `min |λ|`.
pub fn symmetric_extremes(
    a: MatRef<'_, f64>,
    lambda: &[f64],
    vectors: MatRef<'_, f64>,
    radius: f64,
) -> Extremes {
    let n = lambda.len();
    if !radius.is_finite() || n == 0 {
        return Extremes::default();
    }
    let sparse = crate::system::sparse_of_dense(a);
    let j = Jordan::Symmetric(&sparse);
    let (order, sorted) = ascending(lambda);
    // λ_(k) of J, as a bracket of |λ_(k)|.
    let refine = |k: usize| -> Option<Refined> {
        let alpha = if k > 0 {
            upper(sorted[k - 1] + radius)
        } else {
            f64::NEG_INFINITY
        };
        let beta = if k + 1 < n {
            lower(sorted[k + 1] - radius)
        } else {
            f64::INFINITY
        };
        let x: Vec<f64> = (0..n).map(|i| vectors[(i, order[k])]).collect();
        let r = bracket(&j, &x, alpha, beta)?;
        if r.lo > 0.0 {
            Some(r)
        } else if r.hi < 0.0 {
            Some(Refined {
                lo: -r.hi,
                hi: -r.lo,
                value: -r.value,
            })
        } else {
            None
        }
    };
    // |λ| of the others, as Kahan knows them.
    let sorted = &sorted;
    let others = |k: usize| {
        (0..n)
            .filter(move |&i| i != k)
            .map(move |i| (sorted[i].abs() - radius, sorted[i].abs() + radius))
    };
    let kmax = if sorted[n - 1].abs() >= sorted[0].abs() {
        n - 1
    } else {
        0
    };
    let kmin = (0..n)
        .min_by(|&p, &q| sorted[p].abs().total_cmp(&sorted[q].abs()))
        .unwrap_or(0);
    let max = refine(kmax).map(|r| Refined {
        hi: others(kmax).fold(r.hi, |h, (_, o)| h.max(upper(o))),
        ..r
    });
    let min = refine(kmin).map(|r| Refined {
        lo: others(kmin)
            .fold(r.lo, |l, (o, _)| l.min(lower(o)))
            .max(0.0),
        ..r
    });
    Extremes { max, min }
}

/// A ≈ U diag(σ) Vᵀ (σ any order, columns of `u`, `v` paired), Kahan's radius for the
/// Jordan–Wielandt matrix: brackets of σ_max and σ_min.
pub fn svd_extremes(
    a: MatRef<'_, f64>,
    sigma: &[f64],
    u: MatRef<'_, f64>,
    v: MatRef<'_, f64>,
    radius: f64,
) -> Extremes {
    let n = sigma.len();
    if !radius.is_finite() || n == 0 {
        return Extremes::default();
    }
    let (sa, sat) = (
        crate::system::sparse_of_dense(a),
        crate::system::sparse_of_dense(a.transpose()),
    );
    let j = Jordan::Wielandt { a: &sa, at: &sat };
    let (order, sorted) = ascending(sigma);
    let vector = |k: usize| -> Vec<f64> {
        let c = order[k];
        (0..n)
            .map(|i| u[(i, c)])
            .chain((0..n).map(|i| v[(i, c)]))
            .collect()
    };
    // σ_max: the top eigenvalue of J; below it σ_(n−1) (or −σ_max for n = 1).
    let alpha = if n > 1 {
        upper(sorted[n - 2] + radius)
    } else {
        upper(-(sorted[0] - radius))
    };
    let max = bracket(&j, &vector(n - 1), alpha, f64::INFINITY);
    // σ_min: below it −σ_min ≤ −(θ_1 − R), above it σ_(2) ≥ θ_2 − R.
    let beta = if n > 1 {
        lower(sorted[1] - radius)
    } else {
        f64::INFINITY
    };
    let min = bracket(&j, &vector(0), upper(radius - sorted[0]), beta).filter(|r| r.lo > 0.0);
    Extremes { max, min }
}

#[cfg(test)]
mod tests {
    use super::super::{cond2_dense, residual_radius};
    use faer::Mat;

    /// `H = ⊗ (I − ½·11ᵀ)` (4×4 blocks, `levels` times): symmetric, orthogonal, entries ±2^−levels,
    /// all exactly representable.
    fn householder(levels: u32) -> Mat<f64> {
        let mut h = Mat::from_fn(1, 1, |_, _| 1.0);
        for _ in 0..levels {
            let m = h.nrows();
            h = Mat::from_fn(4 * m, 4 * m, |i, j| {
                let b = if i % 4 == j % 4 { 0.5 } else { -0.5 };
                b * h[(i / 4, j / 4)]
            });
        }
        h
    }

    /// `H diag(d) P H` (P: the cyclic shift when `shift`), formed exactly: its singular values
    /// (and for P = I, its eigenvalues) are exactly the d (or |d|). The d carry ≤ 4 significant
    /// bits over ≤ 40 binades, so every sum of the products fits in 53 bits.
    fn exact_matrix(levels: u32, d: &[f64], shift: bool) -> Mat<f64> {
        let h = householder(levels);
        let n = h.nrows();
        assert_eq!(d.len(), n);
        let col = |j: usize| if shift { (j + 1) % n } else { j };
        let hd = Mat::from_fn(n, n, |i, j| h[(i, j)] * d[j]);
        // (H D P)[:, col(j)] = (H D)[:, j].
        let mut hdp = Mat::<f64>::zeros(n, n);
        for j in 0..n {
            for i in 0..n {
                hdp[(i, col(j))] = hd[(i, j)];
            }
        }
        &hdp * &h
    }

    /// Graded values: (1 + k/8)·2^(−e_k), e_k from 0 to `binades`, signs alternating if `signed`.
    fn graded(n: usize, binades: i32, signed: bool) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let e = (k as i32 * binades) / (n as i32 - 1);
                let s = if signed && k % 2 == 1 { -1.0 } else { 1.0 };
                s * (1.0 + (k % 8) as f64 / 8.0) * 2f64.powi(-e)
            })
            .collect()
    }

    fn exact_cond(d: &[f64]) -> (f64, f64) {
        let a = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let b = d.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
        (a, b)
    }

    /// The SVD and symmetric eigen routes bracket the exact extreme values of exactly known
    /// matrices, to the contract's width (`8·ε_mach·cond₂`, or 1e-12), where Kahan's radius
    /// alone is first order (`n·ε_mach·cond₂` and wider); the reported cond₂ is within the
    /// value contract, `max(1e-12, 4·ε_mach·cond₂)`.
    #[test]
    fn dense_routes_bracket_exact_values_to_second_order() {
        for (levels, binades) in [(2, 10), (2, 30), (3, 20), (3, 40)] {
            let n = 4usize.pow(levels);
            for (symmetric, shift, signed) in [(false, true, false), (true, false, true)] {
                let d = graded(n, binades, signed);
                let a = exact_matrix(levels, &d, shift);
                let (smax, smin) = exact_cond(&d);
                let cond = smax / smin;
                let r = cond2_dense(a.as_ref(), symmetric).unwrap();
                let c = r.certificate.unwrap();
                let what = format!("n {n}, cond {cond:.1e}, symmetric {symmetric}");
                assert!(
                    c.lambda_max_lo <= smax && smax <= c.lambda_max_hi,
                    "{what}: {c:?}"
                );
                assert!(
                    c.lambda_min_lo <= smin && smin <= c.lambda_min_hi,
                    "{what}: {c:?}"
                );
                assert!(r.cond2_lo <= cond && cond <= r.cond2_hi, "{what}");
                let target = (8.0 * f64::EPSILON * cond).max(1e-12);
                assert!(
                    r.relative_width() <= target,
                    "{what}: width {:.1e} > {target:.1e}",
                    r.relative_width()
                );
                let value_tol = (4.0 * f64::EPSILON * cond).max(1e-12);
                assert!(
                    (r.cond2 / cond - 1.0).abs() <= value_tol,
                    "{what}: {} vs {cond}",
                    r.cond2
                );
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 96,
            ..proptest::prelude::ProptestConfig::default()
        })]
        /// On random exactly known matrices (n = 4, 16, 64; values over up to 40 binades,
        /// signed for the symmetric route; repeated values allowed) both brackets contain the
        /// exact extremes, and where the extremes are simple and separated (a factor 2 from
        /// their neighbours) they are second order: within the contract's width target.
        #[test]
        fn dense_brackets_contain_the_exact_extremes(
            levels in 1u32..=3,
            draws in proptest::collection::vec((0u8..8, 0i32..=40, proptest::bool::ANY), 64),
            symmetric in proptest::bool::ANY,
        ) {
            let n = 4usize.pow(levels);
            let d: Vec<f64> = draws[..n]
                .iter()
                .map(|&(m, e, neg)| {
                    let v = (1.0 + f64::from(m) / 8.0) * 2f64.powi(-e);
                    if neg { -v } else { v }
                })
                .collect();
            let a = exact_matrix(levels, &d, !symmetric);
            let (smax, smin) = exact_cond(&d);
            let r = cond2_dense(a.as_ref(), symmetric).unwrap();
            let c = r.certificate.unwrap();
            proptest::prop_assert!(c.lambda_max_lo <= smax && smax <= c.lambda_max_hi, "{:?}", c);
            proptest::prop_assert!(c.lambda_min_lo <= smin && smin <= c.lambda_min_hi, "{:?}", c);
            let mut abs: Vec<f64> = d.iter().map(|v| v.abs()).collect();
            abs.sort_by(f64::total_cmp);
            let separated = n > 1 && abs[1] >= 2.0 * abs[0] && abs[n - 1] >= 2.0 * abs[n - 2];
            if separated {
                let target = (8.0 * f64::EPSILON * smax / smin).max(1e-12);
                proptest::prop_assert!(
                    r.relative_width() <= target,
                    "width {:e} > {target:e}",
                    r.relative_width()
                );
            }
        }
    }

    /// Where the gap is not resolved (σ_min = σ_2 exactly, or σ_min below Kahan's radius) the
    /// bracket falls back to Kahan's and still holds.
    #[test]
    fn unresolved_gaps_keep_kahan_brackets() {
        let n = 16;
        let mut d = graded(n, 10, false);
        d[n - 1] = d[n - 2];
        let a = exact_matrix(2, &d, true);
        let svd = a.svd().unwrap();
        let sigma: Vec<f64> = (0..n).map(|i| svd.S()[i]).collect();
        let radius = residual_radius(a.as_ref(), svd.V(), &sigma, svd.U(), &sigma, true);
        let e = super::svd_extremes(a.as_ref(), &sigma, svd.U(), svd.V(), radius);
        assert!(e.max.is_some() && e.min.is_none(), "{e:?}");
        let r = cond2_dense(a.as_ref(), false).unwrap();
        let (smax, smin) = exact_cond(&d);
        let c = r.certificate.unwrap();
        assert!(c.lambda_min_lo <= smin && smin <= c.lambda_min_hi);
        assert!(c.lambda_max_lo <= smax && smax <= c.lambda_max_hi);
        // σ_min ≈ 2^−60 ≪ R ≈ n·ε·σ_max: no gap, and no positive lower bound either.
        let mut d = graded(n, 10, false);
        d[n - 1] = 2f64.powi(-60);
        let a = exact_matrix(2, &d, true);
        let r = cond2_dense(a.as_ref(), false).unwrap();
        assert_eq!(r.certificate.unwrap().lambda_min_lo, 0.0);
        assert!(r.cond2_hi.is_infinite());
    }
}
