//! Eigenvalues of the symmetric tridiagonal matrices a Lanczos run builds (diagonal `a`,
//! off-diagonal `b`): the largest by Laguerre's method with Sturm-count safeguards, the second
//! largest by bisection, Gershgorin's interval, and the dense copy for faer's eigensolvers.
//! Split from [`lanczos`](super::lanczos), whose recurrence and Ritz vectors use them.

/// Largest eigenvalue of the symmetric tridiagonal matrix (diagonal `a`, off-diagonal `b`),
/// given an upper bound `upper ≥ λ_max` and a lower bound `lower ≤ λ_max`.
///
/// Laguerre's method on the characteristic polynomial p(x) = det(T − xI) = Π d_i(x), with the
/// LDLᵀ pivots `d_i = a_i − x − b_{i−1}²/d_{i−1}` and their derivatives giving
/// `G = p'/p = Σ d_i'/d_i` and `H = G² − p''/p`: p has only real roots, so Laguerre started
/// above the largest one decreases monotonically onto it (every iterate stays an upper bound,
/// checked by the signs of the pivots) and converges cubically — in a few steps even from the
/// loose start Lanczos passes (`max(θ_prev, α_k) + β_{k−1}`, which with θ_prev brackets the new
/// value by interlacing), where Newton crawls at rate 1 − 1/k. Sturm counts finish the cases
/// where a step lands at or just below λ_max by rounding (about half of the sweep's calls:
/// a gallop up from that lower bound), a pivot vanishes or 40 steps are not enough (bisection).
/// O(k) per step instead of the O(60 k) of a bisection from the Gershgorin interval.
///
/// `guess`, where given inside (lower, upper), is tried first as the start: Laguerre from a
/// start just above λ_max settles in one or two steps, from the loose `upper` in three or
/// four. A guess below λ_max (a pivot ≥ 0) only raises `lower`, and Laguerre starts from
/// `upper` as without it.
pub(crate) fn tridiagonal_max_eigenvalue(
    a: &[f64],
    b: &[f64],
    mut lower: f64,
    upper: f64,
    guess: Option<f64>,
) -> f64 {
    let k = a.len();
    // Number of eigenvalues < x (LDLᵀ of T − xI).
    let count = |x: f64| {
        let mut c = 0;
        let mut d = 1.0;
        for i in 0..k {
            let off = if i > 0 { b[i - 1] * b[i - 1] } else { 0.0 };
            d = a[i] - x - if i > 0 { off / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::EPSILON * (a[i].abs() + x.abs()).max(f64::MIN_POSITIVE);
            }
            if d < 0.0 {
                c += 1;
            }
        }
        c
    };
    // Laguerre from above. `above` is the last iterate proven above λ_max (every pivot of
    // T − xI negative: T − xI ≺ 0).
    let mut above = upper;
    let mut x = upper;
    let mut trying_guess = false;
    if let Some(g) = guess.filter(|&g| g > lower && g < upper) {
        x = g;
        trying_guess = true;
    }
    let kf = k as f64;
    for _ in 0..40 {
        // G = p'/p = Σ d_i'/d_i and H = G² − p''/p = −Σ (d_i''/d_i − (d_i'/d_i)²).
        // One division per pivot: with q = 1/d_{i−1}, d_i = a_i − x − b²q,
        // d_i' = −1 + b² d_{i−1}' q², d_i'' = b² (d_{i−1}'' q² − 2 d_{i−1}'² q³).
        let (mut d1, mut d2) = (0.0f64, 0.0f64);
        let (mut g, mut h) = (0.0f64, 0.0f64);
        let mut negative_definite = true;
        let mut q = 0.0f64;
        for i in 0..k {
            let d = if i == 0 {
                (d1, d2) = (-1.0, 0.0);
                a[0] - x
            } else {
                let b2 = b[i - 1] * b[i - 1];
                let q2 = q * q;
                d2 = b2 * (d2 * q2 - 2.0 * d1 * d1 * q2 * q);
                d1 = -1.0 + b2 * d1 * q2;
                a[i] - x - b2 * q
            };
            if !(d < 0.0 && d.is_finite()) {
                negative_definite = false;
                break;
            }
            q = d.recip();
            let r = d1 * q;
            g += r;
            h -= d2 * q - r * r;
        }
        if !negative_definite {
            // T − xI has a pivot ≥ 0, so λ_max ≥ x: a lower bound (rounding put the last
            // step at or just below λ_max, or the guess was low).
            lower = lower.max(x);
            if std::mem::take(&mut trying_guess) {
                x = upper;
                continue;
            }
            break;
        }
        trying_guess = false;
        if !(g.is_finite() && g > 0.0 && h.is_finite()) {
            break;
        }
        above = x;
        let disc = ((kf - 1.0) * (kf * h - g * g)).max(0.0);
        let next = x - kf / (g + disc.sqrt());
        if next.is_nan() || next >= x || x - next <= 2.0 * f64::EPSILON * x.abs() {
            return x; // settled to rounding
        }
        x = next;
    }
    // Sturm counts in [lower, above] to the last bits. After a Laguerre step landed at or
    // just below λ_max (half of the calls in the sweep), `lower` is within a few ulps of it:
    // gallop up from there (steps ×16 from 4 ulps) before bisecting, 1–3 counts instead of
    // ≈ 20 bisection steps.
    let mut hi = above;
    let mut lo = lower.min(hi);
    let mut h = 4.0 * f64::EPSILON * hi.abs();
    while lo + h < hi {
        let t = lo + h;
        if count(t) < k {
            lo = t;
            h *= 16.0;
        } else {
            hi = t;
            break;
        }
    }
    while hi - lo > 4.0 * f64::EPSILON * hi.abs() {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if count(mid) < k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// The second largest eigenvalue of the symmetric tridiagonal T (diagonal `a`, off-diagonal
/// `b`, at least `a.len() − 1` entries) below its largest `theta`, by bisection on Sturm
/// counts to 1e-6 relative (an estimate that places an inertia test, not a result). None for
/// k < 2 or where it is not below θ by more than that.
pub(crate) fn tridiagonal_second_eigenvalue(a: &[f64], b: &[f64], theta: f64) -> Option<f64> {
    let k = a.len();
    if k < 2 {
        return None;
    }
    let count = |x: f64| {
        let (mut c, mut d) = (0usize, 1.0f64);
        for i in 0..k {
            d = a[i] - x - if i > 0 { b[i - 1] * b[i - 1] / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::EPSILON * (a[i].abs() + x.abs()).max(f64::MIN_POSITIVE);
            }
            c += usize::from(d < 0.0);
        }
        c
    };
    // ν₂ = sup{x : count(x) ≤ k − 2}, in (lo, θ).
    let (mut lo, _) = gershgorin(a, &b[..k - 1]);
    let mut hi = theta;
    if count(hi) < k - 1 {
        return None;
    }
    for _ in 0..200 {
        if hi - lo <= 1e-6 * hi.abs() {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if count(mid) <= k - 2 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo < theta * (1.0 - 1e-6)).then_some(lo)
}

/// Gershgorin interval of the symmetric tridiagonal (diagonal `a`, off-diagonal `b`).
pub(crate) fn gershgorin(a: &[f64], b: &[f64]) -> (f64, f64) {
    let k = a.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..k {
        let r = if i > 0 { b[i - 1].abs() } else { 0.0 } + if i + 1 < k { b[i].abs() } else { 0.0 };
        lo = lo.min(a[i] - r);
        hi = hi.max(a[i] + r);
    }
    (lo, hi)
}

/// The k×k symmetric tridiagonal matrix with diagonal `a` and off-diagonal `b`, dense.
pub(crate) fn tridiagonal_dense(a: &[f64], b: &[f64]) -> faer::Mat<f64> {
    let k = a.len();
    faer::Mat::from_fn(k, k, |i, j| {
        if i == j {
            a[i]
        } else if i == j + 1 {
            b[j]
        } else if j == i + 1 {
            b[i]
        } else {
            0.0
        }
    })
}

#[cfg(test)]
mod tests {
    use super::{gershgorin, tridiagonal_max_eigenvalue, tridiagonal_second_eigenvalue};
    use rand::{Rng, SeedableRng};

    /// λ_max of T from faer's dense symmetric eigenvalues (the independent reference).
    fn dense_max(a: &[f64], b: &[f64]) -> f64 {
        let ev = super::tridiagonal_dense(a, b)
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .expect("eigenvalues");
        ev.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    }

    /// Newton-with-bisection agrees with the dense eigenvalues to rounding (8·k·ε·‖T‖), from
    /// the Gershgorin bounds and from the interlacing bracket Lanczos passes; clustered and
    /// repeated top eigenvalues (b = 0 blocks, Wilkinson's W₂₁⁺) included.
    #[test]
    fn top_eigenvalue_matches_dense_eigenvalues() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut cases: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
        for k in [1usize, 2, 3, 5, 17, 60, 200] {
            let a: Vec<f64> = (0..k).map(|_| rng.random_range(-1.0..3.0)).collect();
            let b: Vec<f64> = (1..k).map(|_| rng.random_range(0.0..1.0)).collect();
            cases.push((a, b));
        }
        cases.push((vec![2.0, 2.0, 2.0, 1.0], vec![0.0, 0.0, 0.0]));
        let w: Vec<f64> = (0..21).map(|i| (10.0f64 - i as f64).abs()).collect();
        cases.push((w, vec![1.0; 20]));
        for (a, b) in &cases {
            let k = a.len();
            let norm = a.iter().map(|x| x.abs()).fold(0.0, f64::max)
                + 2.0 * b.iter().map(|x| x.abs()).fold(0.0, f64::max);
            let tol = 8.0 * k as f64 * f64::EPSILON * norm.max(1.0);
            let exact = dense_max(a, b);
            let (lo, hi) = gershgorin(a, b);
            let got = tridiagonal_max_eigenvalue(a, b, lo, hi, None);
            assert!((got - exact).abs() <= tol, "k={k}: {got} vs {exact}");
            if k > 1 {
                let prev = dense_max(&a[..k - 1], &b[..k - 2]);
                let upper = prev.max(a[k - 1]) + b[k - 2].abs();
                let got = tridiagonal_max_eigenvalue(a, b, prev, upper, None);
                assert!(
                    (got - exact).abs() <= tol,
                    "k={k} (bracket): {got} vs {exact}"
                );
                // Guesses above λ_max, below it, at it, and outside the bracket.
                for g in [
                    exact + 1e-3 * (upper - exact),
                    exact + 0.5 * (upper - exact),
                    0.5 * (prev + exact),
                    exact,
                    upper + 1.0,
                ] {
                    let got = tridiagonal_max_eigenvalue(a, b, prev, upper, Some(g));
                    assert!(
                        (got - exact).abs() <= tol,
                        "k={k} (guess {g}): {got} vs {exact}"
                    );
                }
            }
        }
    }

    /// The second eigenvalue of tridiag(−1, 2, −1) (closed form `4sin²((k−1)π/(2(k+1)))`)
    /// to the bisection's 1e-6, from below; none for a 1×1 matrix.
    #[test]
    fn second_eigenvalue_of_the_second_difference() {
        let k = 30;
        let a = vec![2.0; k];
        let b = vec![-1.0; k - 1];
        let th = std::f64::consts::PI / (k as f64 + 1.0);
        let l = |j: usize| 4.0 * (0.5 * j as f64 * th).sin().powi(2);
        let second = tridiagonal_second_eigenvalue(&a, &b, l(k)).unwrap();
        assert!(
            second <= l(k - 1) && second >= l(k - 1) * (1.0 - 2e-6),
            "{second}"
        );
        assert!(tridiagonal_second_eigenvalue(&[2.0], &[], 2.0).is_none());
    }
}
