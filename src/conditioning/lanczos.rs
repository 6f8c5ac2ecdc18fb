//! Lanczos for the extreme eigenvalue of a symmetric operator, as the certified routes use it
//! ([`super::sparse`], [`super::saddle`]): plain three-term recurrence without
//! reorthogonalization (only the top Ritz value is wanted, and its convergence is monotone),
//! the top eigenvalue of the tridiagonal by Laguerre's method with Sturm counts, its Ritz
//! vector from the stored basis or a second pass, and the stopping rule. Written here rather
//! than taken from a crate: no maintained Rust crate offers a matrix-free Lanczos with a
//! caller-supplied operator (a closure over a sparse Cholesky solve), warm starts and this
//! stopping rule.

use crate::error::{Error, Result};
use faer::sparse::SparseColMat;

/// Largest dimension for which [`extreme_eigenvalues`](super::sparse::extreme_eigenvalues)
/// keeps Lanczos vectors to return [`RitzStarts`](super::sparse::RitzStarts) (memory:
/// steps · n words, at most 400 · 20 000 · 8 B = 64 MB); up to it a run always stores its
/// basis.
pub const RITZ_VECTOR_MAX_N: usize = 20_000;

/// Most bytes one Lanczos run above [`RITZ_VECTOR_MAX_N`] unknowns keeps of its basis to form
/// its Ritz vector without a second pass: a quarter of the memory the system reports available
/// (`MemAvailable`, Linux), at most 512 MiB; 64 MiB where it says nothing. A run that would
/// pass it drops its basis and makes the second pass instead. Either way the Ritz vector is
/// the same bit for bit (the same vectors summed in the same order): the budget moves time
/// and memory, never a result. Read once per process.
pub fn ritz_basis_budget() -> usize {
    static BUDGET: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *BUDGET.get_or_init(|| {
        const CAP: usize = 512 << 20;
        let available = std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
            m.lines()
                .find_map(|l| l.strip_prefix("MemAvailable:"))
                .and_then(|v| v.split_whitespace().next()?.parse::<usize>().ok())
                .map(|kb| kb * 1024)
        });
        available.map_or(64 << 20, |b| (b / 4).min(CAP))
    })
}

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

/// What one Lanczos run found.
pub(crate) struct LanczosRun {
    /// The top Ritz value.
    pub theta: f64,
    /// Products with the operator.
    pub steps: usize,
    /// Whether θ stagnated (or the Krylov space became invariant) before `max_steps`.
    pub converged: bool,
    /// The unit Ritz vector of θ, where asked for.
    pub vector: Option<Vec<f64>>,
    /// The tridiagonal T's diagonal and off-diagonal (at least `alphas.len() − 1` entries),
    /// for [`LanczosRun::second`].
    alphas: Vec<f64>,
    betas: Vec<f64>,
}

impl LanczosRun {
    /// The second largest Ritz value (None where there is none): an estimate from below of
    /// the operator's second eigenvalue (interlacing). Computed on request (only the SPD
    /// route's λ_min run wants it): its bisection costs about as much as the run's own Ritz
    /// values.
    pub fn second(&self) -> Option<f64> {
        tridiagonal_second_eigenvalue(&self.alphas, &self.betas, self.theta)
    }
}

/// Weight of the generic start vector mixed into a warm start: keeps every eigenvector's
/// component nonzero, so a start orthogonal to the new top eigenvector still finds it.
pub(crate) const WARM_MIX: f64 = 1e-2;

/// Largest eigenvalue of a symmetric operator by plain Lanczos: stops when the top Ritz value
/// θ stagnates to `stagnation(θ)` relative over [`CHECK_EVERY`] steps, on an invariant
/// subspace, or after `max_steps`. With an optional warm start (a unit vector near the wanted
/// eigenvector, e.g. the Ritz vector of a nearby matrix; the Ritz value is then checked every
/// [`CHECK_EVERY_WARM`] steps, since few are needed) and, with `keep_vector`, the Ritz vector
/// `y = Q_k s` of θ (`s` by inverse iteration on `T_k`): from the k stored Lanczos vectors up
/// to [`RITZ_VECTOR_MAX_N`] unknowns, and above it while they fit [`ritz_basis_budget`]
/// (memory k·n), else by a second pass of the recurrence above (k more applications, memory
/// O(n)).
pub(crate) fn lanczos(
    n: usize,
    max_steps: usize,
    stagnation: impl Fn(f64) -> f64,
    start: Option<&[f64]>,
    keep_vector: bool,
    mut apply: impl FnMut(&[f64], &mut [f64]),
) -> Result<LanczosRun> {
    let warm = start.filter(|v| v.len() == n && v.iter().all(|x| x.is_finite()));
    let check_every = if warm.is_some() {
        CHECK_EVERY_WARM
    } else {
        CHECK_EVERY
    };
    let q0 = start_vector(n, warm);
    let mut q = q0.clone();
    // Ritz vectors from the stored basis (memory k·n) up to RITZ_VECTOR_MAX_N unknowns and
    // above it within the budget, else by a second pass of the same recurrence (k more
    // operator applications, memory O(n)).
    let mut store = keep_vector;
    let budget_words = if n <= RITZ_VECTOR_MAX_N {
        usize::MAX
    } else {
        ritz_basis_budget() / std::mem::size_of::<f64>()
    };
    let mut basis: Vec<f64> = Vec::new();
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta_prev = 0.0;
    let mut history: Vec<f64> = Vec::new();
    let mut steps = 0;
    let mut upper = 0.0f64;
    let ritz = |alphas: &[f64],
                betas: &[f64],
                basis: &[f64],
                store: bool,
                theta: f64,
                apply: &mut dyn FnMut(&[f64], &mut [f64])| {
        keep_vector.then(|| {
            let s = tridiagonal_eigenvector(alphas, &betas[..alphas.len() - 1], theta);
            if store {
                combine(&s, basis, n)
            } else {
                second_pass(&s, alphas, betas, &q0, apply)
            }
        })
    };
    for _ in 0..max_steps.min(n).max(1) {
        if store && basis.len() + n > budget_words {
            // Over the budget: the second pass will form the Ritz vector.
            store = false;
            basis = Vec::new();
        }
        if store {
            basis.extend_from_slice(&q);
        }
        apply(&q, &mut w);
        steps += 1;
        let alpha = dot(&w, &q);
        if !alpha.is_finite() {
            return Err(Error::Numerical(
                "Lanczos produced a non-finite value (matrix contains NaN/Inf?)".into(),
            ));
        }
        for ((wi, qi), pi) in w.iter_mut().zip(&q).zip(&q_prev) {
            *wi -= alpha * qi + beta_prev * pi;
        }
        alphas.push(alpha);
        let beta = norm(&w);
        // Weyl's bound, step by step from the last computed Ritz value:
        // λ_max(T_k) ≤ max(λ_max(T_{k−1}), α_k) + β_{k−1}; interlacing: λ_max(T_k) ≥ θ_last.
        upper = if steps == 1 {
            alpha
        } else {
            upper.max(alpha) + beta_prev
        };
        // The top Ritz value every `check_every` steps (its O(k) solve dominated small
        // problems when done at every step), and wherever the recurrence may stop.
        let may_stop = beta <= 1e-300 || beta <= f64::EPSILON * upper.abs() * 1e-2;
        if steps % check_every == 0 || may_stop {
            let theta = top_ritz_value(&alphas, &betas, &history, upper, steps);
            let stagnated = has_stagnated(&history, theta, stagnation(theta) * theta.abs());
            history.push(theta);
            upper = theta;
            if stagnated || beta <= 1e-300 || beta <= f64::EPSILON * theta.abs() * 1e-2 {
                let vector = ritz(&alphas, &betas, &basis, store, theta, &mut apply);
                return Ok(LanczosRun {
                    theta,
                    steps,
                    converged: true,
                    vector,
                    alphas,
                    betas,
                });
            }
        }
        betas.push(beta);
        std::mem::swap(&mut q_prev, &mut q);
        let inv_beta = beta.recip();
        for (qi, wi) in q.iter_mut().zip(&w) {
            *qi = wi * inv_beta;
        }
        beta_prev = beta;
    }
    // Out of steps: the top Ritz value of the last tridiagonal.
    let (lo, hi) = gershgorin(&alphas, &betas);
    let theta = tridiagonal_max_eigenvalue(&alphas, &betas, lo, hi, None);
    let vector = ritz(&alphas, &betas, &basis, store, theta, &mut apply);
    Ok(LanczosRun {
        theta,
        steps,
        converged: false,
        vector,
        alphas,
        betas,
    })
}

/// The top eigenvalue of the Lanczos tridiagonal (`alphas`, `betas`) after `steps` steps:
/// searched above the previous check's value (`history`) and below Weyl's bound `upper`, with
/// the last change again, doubled, as the first guess (the changes shrink as θ converges).
fn top_ritz_value(alphas: &[f64], betas: &[f64], history: &[f64], upper: f64, steps: usize) -> f64 {
    let guess = match history[..] {
        [.., pp, p] => Some(p + 2.0 * (p - pp).abs() + 8.0 * f64::EPSILON * p.abs()),
        _ => None,
    };
    match history.last() {
        Some(&prev) => tridiagonal_max_eigenvalue(alphas, betas, prev, upper, guess),
        None if steps == 1 => alphas[0],
        None => {
            let (lo, hi) = gershgorin(alphas, betas);
            tridiagonal_max_eigenvalue(alphas, betas, lo, hi, None)
        }
    }
}

/// Whether θ has stagnated after the checks in `history`: the last change is below `tol`, or
/// the changes shrink at least 4× per check and the geometric tail of what is left,
/// d²/(d_prev − d), is (Lanczos converges superlinearly, so the tail overestimates what is
/// left).
fn has_stagnated(history: &[f64], theta: f64, tol: f64) -> bool {
    match history[..] {
        [.., pp, p] => {
            let (d, d_prev) = ((theta - p).abs(), (p - pp).abs());
            d <= tol || (4.0 * d <= d_prev && d * d <= tol * (d_prev - d))
        }
        [p] => (theta - p).abs() <= tol,
        [] => false,
    }
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

/// The deterministic start vector of [`lanczos`]: seeded random ([`random_start`], seed 0),
/// so that it cannot share a mesh's symmetry (a start symmetric under a mirror is orthogonal
/// to every antisymmetric mode, and Lanczos would return the lowest symmetric eigenvalue in
/// place of λ_min), mixed with the warm start where there is one, normalized.
pub(crate) fn start_vector(n: usize, warm: Option<&[f64]>) -> Vec<f64> {
    let mut q = random_start(n, 0);
    if let Some(v) = warm {
        let nv = norm(v);
        if nv > 0.0 {
            for (qi, vi) in q.iter_mut().zip(v) {
                *qi = WARM_MIX * *qi + vi / nv;
            }
            let nq = norm(&q);
            q.iter_mut().for_each(|x| *x /= nq);
        }
    }
    q
}

/// A unit vector of `n` components `±(0.5 + U[0, 1))` with random signs, from ChaCha8
/// seeded with `seed`: every component nonzero (no eigenvector is missed for lack of a
/// component, bar measure zero), no structure in common with any mesh, and the same on every
/// machine and thread count.
pub(crate) fn random_start(n: usize, seed: u64) -> Vec<f64> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0x4c41_4e43_5a4f_5300 ^ seed);
    let mut q: Vec<f64> = (0..n)
        .map(|_| {
            let v = 0.5 + rng.random::<f64>();
            if rng.random::<bool>() {
                v
            } else {
                -v
            }
        })
        .collect();
    let nq = norm(&q);
    q.iter_mut().for_each(|x| *x /= nq);
    q
}

/// The unit eigenvector `s` of the top eigenvalue θ of `T_k` (diagonal `a`, off-diagonal
/// `b`), by two steps of inverse iteration with `T_k − μI`, μ just above θ (θ is an upper
/// bound of `λ_max(T_k)` to rounding, so `T_k − μI ≺ 0` and its LDLᵀ needs no pivoting).
pub(crate) fn tridiagonal_eigenvector(a: &[f64], b: &[f64], theta: f64) -> Vec<f64> {
    let k = a.len();
    let scale = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs()));
    let mu = theta + 1e-12 * scale.max(f64::MIN_POSITIVE);
    // LDLᵀ of T − μI: pivots d, multipliers l.
    let mut d = vec![0.0; k];
    let mut l = vec![0.0; k];
    for i in 0..k {
        d[i] = a[i] - mu;
        if i > 0 {
            l[i] = b[i - 1] / d[i - 1];
            d[i] -= l[i] * b[i - 1];
        }
        if d[i] == 0.0 || !d[i].is_finite() {
            d[i] = -f64::EPSILON * scale.max(f64::MIN_POSITIVE);
        }
    }
    let mut s = vec![1.0; k];
    for _ in 0..2 {
        for i in 1..k {
            s[i] -= l[i] * s[i - 1];
        }
        for i in 0..k {
            s[i] /= d[i];
        }
        for i in (0..k.saturating_sub(1)).rev() {
            s[i] -= l[i + 1] * s[i + 1];
        }
        let ns = norm(&s);
        s.iter_mut().for_each(|x| *x /= ns);
    }
    s
}

/// The unit Ritz vector `y = Q_k s` from the stored Lanczos vectors (`basis`, one after the
/// other).
pub(crate) fn combine(s: &[f64], basis: &[f64], n: usize) -> Vec<f64> {
    let mut y = vec![0.0; n];
    for (j, sj) in s.iter().enumerate() {
        for (yi, qi) in y.iter_mut().zip(&basis[j * n..(j + 1) * n]) {
            *yi += sj * qi;
        }
    }
    let ny = norm(&y);
    y.iter_mut().for_each(|x| *x /= ny);
    y
}

/// The unit Ritz vector `y = Q_k s` without stored Lanczos vectors: the recurrence of
/// [`lanczos`] run again from the same start `q0` with the recorded α and β (the same
/// operations in the same order, so the same vectors bit for bit), `y` accumulated on the way.
pub(crate) fn second_pass(
    s: &[f64],
    alphas: &[f64],
    betas: &[f64],
    q0: &[f64],
    apply: &mut dyn FnMut(&[f64], &mut [f64]),
) -> Vec<f64> {
    let n = q0.len();
    let k = s.len();
    let mut y = vec![0.0; n];
    let mut q = q0.to_vec();
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    for j in 0..k {
        for (yi, qi) in y.iter_mut().zip(&q) {
            *yi += s[j] * qi;
        }
        if j + 1 == k {
            break;
        }
        apply(&q, &mut w);
        let (alpha, beta_prev) = (alphas[j], if j > 0 { betas[j - 1] } else { 0.0 });
        for ((wi, qi), pi) in w.iter_mut().zip(&q).zip(&q_prev) {
            *wi -= alpha * qi + beta_prev * pi;
        }
        std::mem::swap(&mut q_prev, &mut q);
        let inv_beta = betas[j].recip();
        for (qi, wi) in q.iter_mut().zip(&w) {
            *qi = wi * inv_beta;
        }
    }
    let ny = norm(&y);
    y.iter_mut().for_each(|x| *x /= ny);
    y
}

/// Smallest relative stagnation of the top Ritz value at which the Lanczos runs stop (the
/// estimate wanted to rounding).
pub const STAGNATION: f64 = 1e-14;

/// The stagnation tolerances (λ_min run, λ_max run): a tolerance asked for loosens both
/// runs' stopping rule, never below the defaults; `scale` tightens them.
pub(crate) fn stagnation_tolerances(tol: Option<f64>, scale: f64) -> (f64, f64) {
    let (bottom, top) = match tol {
        Some(t) => ((t / 8.0).max(STAGNATION), (t / 8.0).max(TOP_STAGNATION)),
        None => (STAGNATION, TOP_STAGNATION),
    };
    (bottom * scale, top * scale)
}

/// The stagnation at which plain Lanczos on A stops for λ_max: the top of the spectrum
/// converges fastest, and a change below 1e-13 over a few steps leaves an error far
/// below the 1e-12 floor of the cond₂ contract (its share of that budget).
pub const TOP_STAGNATION: f64 = 1e-13;

/// Steps between two Ritz-value evaluations of [`lanczos`]; the stagnation test compares
/// values this many steps apart.
pub(crate) const CHECK_EVERY: usize = 5;

/// [`CHECK_EVERY`] of a warm-started [`lanczos`] run.
pub(crate) const CHECK_EVERY_WARM: usize = 2;

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

/// Gershgorin upper bound of the spectrum: `max_j (a_jj + Σ_{i≠j} |a_ij|)` (columns of a
/// symmetric matrix).
pub(crate) fn gershgorin_max(a: &SparseColMat<usize, f64>) -> f64 {
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let av = a.val();
    (0..a.ncols())
        .map(|j| {
            (cp[j]..cp[j + 1])
                .map(|p| if ri[p] == j { av[p] } else { av[p].abs() })
                .sum::<f64>()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `xᵀy` summed in four interleaved partial sums (`i mod 4`), added at the end: a plain
/// left-to-right sum waits one floating-point add latency per entry, and the Lanczos runs'
/// two reductions per step were ≈ 10 % of a dense-folder sweep. Any summation order obeys the
/// same error bound `γ_n Σ|x_i y_i|` ([`rayleigh_interval`] relies on it), and the order is
/// fixed, so results stay deterministic.
pub(crate) fn dot(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (xc, yc) = (x[..n].chunks_exact(4), y[..n].chunks_exact(4));
    let (xr, yr) = (xc.remainder(), yc.remainder());
    let mut acc = [0.0f64; 4];
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    for (k, (a, b)) in xr.iter().zip(yr).enumerate() {
        acc[k] += a * b;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
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

pub(crate) fn norm(x: &[f64]) -> f64 {
    dot(x, x).sqrt()
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
