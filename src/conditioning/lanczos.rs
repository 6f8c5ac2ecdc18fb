//! Lanczos for the extreme eigenvalue of a symmetric operator, as the certified routes use it
//! ([`super::sparse`], [`super::saddle`]): plain three-term recurrence without
//! reorthogonalization (only the top Ritz value is wanted, and its convergence is monotone),
//! the top eigenvalue of the tridiagonal by Laguerre's method with Sturm counts, its Ritz
//! vector from the stored basis or a second pass, and the stopping rule. Written here rather
//! than taken from a crate: no maintained Rust crate offers a matrix-free Lanczos with a
//! caller-supplied operator (a closure over a sparse Cholesky solve), warm starts and this
//! stopping rule.

use super::tridiagonal::{gershgorin, tridiagonal_max_eigenvalue, tridiagonal_second_eigenvalue};
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
    const CAP: usize = 512 << 20;
    mem_available().map_or(64 << 20, |b| (b / 4).min(CAP))
}

/// The bytes of memory the system reports available (`MemAvailable`, Linux; `None`
/// elsewhere), read once per process.
pub fn mem_available() -> Option<usize> {
    static AVAILABLE: std::sync::OnceLock<Option<usize>> = std::sync::OnceLock::new();
    *AVAILABLE.get_or_init(|| {
        std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
            m.lines()
                .find_map(|l| l.strip_prefix("MemAvailable:"))
                .and_then(|v| v.split_whitespace().next()?.parse::<usize>().ok())
                .map(|kb| kb * 1024)
        })
    })
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
    /// Where the Ritz vector was left to [`LanczosRun::deferred_vector`]
    /// ([`Keep::IfConverged`]): the run's start vector q₀, for its second pass.
    deferred_start: Option<Vec<f64>>,
    /// The change of θ between the run's last two checks (+∞ with fewer than two): of an
    /// unconverged run, a rough measure of how far θ still is from the eigenvalue.
    pub last_change: f64,
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

    /// The Ritz vector an unconverged run left undone ([`Keep::IfConverged`]), by the second
    /// pass [`lanczos`] would have made from the run's own start vector: with the same
    /// operator (`apply`), the same vector bit for bit. `None` where the run formed its vector
    /// (it is in `vector`) or was not asked for one.
    pub fn deferred_vector(&self, apply: &mut dyn FnMut(&[f64], &mut [f64])) -> Option<Vec<f64>> {
        let q0 = self.deferred_start.as_ref()?;
        let k = self.alphas.len();
        let s = tridiagonal_eigenvector(&self.alphas, &self.betas[..k - 1], self.theta);
        Some(second_pass(&s, &self.alphas, &self.betas, q0, apply))
    }
}

/// Weight of the generic start vector mixed into a warm start: keeps every eigenvector's
/// component nonzero, so a start orthogonal to the new top eigenvector still finds it. Small,
/// since what the mix must supply is a component above rounding, not a large one: its size
/// only sets how fast a missing eigenvector surfaces (c ≈ mix/√n; the warm start's own error
/// against this matrix — a nearby matrix's Ritz vector — usually supplies far more), while
/// every component it adds is one the run must converge away (1e-2: about five decades,
/// 1e-6: one; the folder's beams at small ε: 86–100 products → 4–6). Nothing certified depends
/// on it: a run that settles short fails its inertia test and is refined, and a bracket that
/// misses its target is recomputed from the generic start (`sparse::extreme_eigenvalues`).
/// (A window of several eigenpairs, started from the sum of the last window's vectors, needs
/// more of the generic start: [`WINDOW_MIX`].)
pub(crate) const WARM_MIX: f64 = 1e-6;

/// The generic start's weight in a warm-started window run (`conditioning::window`): the sum
/// of the last window's vectors leaves new directions to the random part, and `optimal`'s
/// Newton stages need the window's vectors converged (its canonical Hertz sample stalls
/// with 1e-6).
pub(crate) const WINDOW_MIX: f64 = 1e-2;

/// Largest eigenvalue of a symmetric operator by plain Lanczos: stops when the top Ritz value
/// θ stagnates to `stagnation(θ)` relative over [`CHECK_EVERY`] steps, on an invariant
/// subspace, or after `max_steps`. With an optional warm start (a unit vector near the wanted
/// eigenvector, e.g. the Ritz vector of a nearby matrix; the Ritz value is then checked every
/// [`CHECK_EVERY_WARM`] steps, since few are needed) and, as `keep` asks ([`Keep`]), the Ritz vector
/// `y = Q_k s` of θ (`s` by inverse iteration on `T_k`): from the k stored Lanczos vectors up
/// to [`RITZ_VECTOR_MAX_N`] unknowns, and above it while they fit [`ritz_basis_budget`]
/// (memory k·n), else by a second pass of the recurrence above (k more applications, memory
/// O(n)).
pub(crate) fn lanczos(
    n: usize,
    max_steps: usize,
    stagnation: impl Fn(f64) -> f64,
    start: Option<&[f64]>,
    keep: Keep,
    apply: impl FnMut(&[f64], &mut [f64]),
) -> Result<LanczosRun> {
    let budget_words = if n <= RITZ_VECTOR_MAX_N {
        usize::MAX
    } else {
        ritz_basis_budget() / std::mem::size_of::<f64>()
    };
    lanczos_within(budget_words, n, max_steps, stagnation, start, keep, apply)
}

/// [`lanczos`] with the basis budget given (in f64 words).
fn lanczos_within(
    budget_words: usize,
    n: usize,
    max_steps: usize,
    stagnation: impl Fn(f64) -> f64,
    start: Option<&[f64]>,
    keep: Keep,
    mut apply: impl FnMut(&[f64], &mut [f64]),
) -> Result<LanczosRun> {
    let warm = start.filter(|v| v.len() == n && v.iter().all(|x| x.is_finite()));
    let check_every = if warm.is_some() {
        CHECK_EVERY_WARM
    } else {
        CHECK_EVERY
    };
    let q0 = start_vector(n, warm, WARM_MIX);
    let mut q = q0.clone();
    // Ritz vectors from the stored basis (memory k·n) up to RITZ_VECTOR_MAX_N unknowns and
    // above it within the budget, else by a second pass of the same recurrence (k more
    // operator applications, memory O(n)). A cheap operator's run (`Keep::IfConverged`)
    // keeps no basis it might have to drop: a basis grown to the budget and dropped costs
    // memory, its second pass little.
    let mut store = match keep {
        Keep::Never => false,
        Keep::Always => true,
        Keep::IfConverged => max_steps.min(n).saturating_mul(n) <= budget_words,
    };
    // Room for a typical run up front ([`TYPICAL_STEPS`]).
    let typical = max_steps.min(n).clamp(1, TYPICAL_STEPS);
    let reserve = if store { typical * n } else { 0 };
    let mut basis: Vec<f64> = Vec::with_capacity(reserve.min(BASIS_RESERVE_WORDS));
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::with_capacity(typical), Vec::with_capacity(typical));
    let mut beta_prev = 0.0;
    let mut history: Vec<f64> = Vec::with_capacity(typical / check_every + 1);
    let mut steps = 0;
    let mut upper = 0.0f64;
    // The top Ritz value where it settled (or the Krylov space became invariant).
    let mut settled = None;
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
                settled = Some(theta);
                break;
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
    // Out of steps: the top Ritz value of the last tridiagonal. Its Ritz vector is formed
    // now from the stored basis; without one (a second pass of `steps` more products) only
    // where `keep == Keep::Always` — a caller that may discard an unconverged run's vector
    // forms it later, on demand, with [`LanczosRun::deferred_vector`].
    let converged = settled.is_some();
    let theta = settled.unwrap_or_else(|| {
        let (lo, hi) = gershgorin(&alphas, &betas);
        tridiagonal_max_eigenvalue(&alphas, &betas, lo, hi, None)
    });
    let deferred = !converged && keep == Keep::IfConverged && !store;
    let vector = (keep != Keep::Never && !deferred).then(|| {
        let s = tridiagonal_eigenvector(&alphas, &betas[..alphas.len() - 1], theta);
        if store {
            combine(&s, &basis, n)
        } else {
            second_pass(&s, &alphas, &betas, &q0, &mut apply)
        }
    });
    Ok(LanczosRun {
        theta,
        steps,
        converged,
        vector,
        deferred_start: deferred.then_some(q0),
        last_change: last_change(&history),
        alphas,
        betas,
    })
}

/// [`lanczos`] on the inverse of a factored matrix, keeping the Ritz vector: the operator
/// `y = B⁻¹x` by `solve` (a factor's in-place solve), the stagnation tolerance constant. The
/// shift-invert runs of the certified routes (λ_min through A⁻¹, λ_max through (σI − A)⁻¹,
/// the refinements) are all this.
pub(crate) fn inverse_lanczos(
    n: usize,
    max_steps: usize,
    stagnation: f64,
    start: Option<&[f64]>,
    solve: impl Fn(&mut [f64]),
) -> Result<LanczosRun> {
    lanczos(
        n,
        max_steps,
        |_| stagnation,
        start,
        Keep::Always,
        |x, y| {
            y.copy_from_slice(x);
            solve(y);
        },
    )
}

/// Which Ritz vector a [`lanczos`] run forms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Keep {
    /// None.
    Never,
    /// The Ritz vector of θ, converged or not.
    Always,
    /// For a cheap operator (products with A): as `Always`, except that above
    /// [`RITZ_VECTOR_MAX_N`] unknowns the basis is kept only where `max_steps` vectors of it
    /// fit [`ritz_basis_budget`] (else the vector comes from a second pass), and that an
    /// unconverged run without its basis leaves the vector to [`LanczosRun::deferred_vector`].
    IfConverged,
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

/// The change of θ between the last two checks in `history` (+∞ with fewer than two).
fn last_change(history: &[f64]) -> f64 {
    match history[..] {
        [.., p, q] => (q - p).abs(),
        _ => f64::INFINITY,
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

/// The deterministic start vector of [`lanczos`]: seeded random ([`random_start`], seed 0),
/// so that it cannot share a mesh's symmetry (a start symmetric under a mirror is orthogonal
/// to every antisymmetric mode, and Lanczos would return the lowest symmetric eigenvalue in
/// place of λ_min), mixed with weight `mix` into the warm start where there is one, normalized.
pub(crate) fn start_vector(n: usize, warm: Option<&[f64]>, mix: f64) -> Vec<f64> {
    let mut q = random_start(n, 0);
    if let Some(v) = warm {
        let nv = norm(v);
        if nv > 0.0 {
            for (qi, vi) in q.iter_mut().zip(v) {
                *qi = mix * *qi + vi / nv;
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
    // The same (n, seed) gives the same vector: this thread's last few are kept (a sweep
    // starts every run of a scene's systems from the same n).
    let cached = RANDOM_STARTS.with(|c| {
        c.borrow()
            .iter()
            .find(|(m, s, _)| *m == n && *s == seed)
            .map(|(_, _, v)| v.clone())
    });
    if let Some(v) = cached {
        return v;
    }
    let q = generate_random_start(n, seed);
    if n > RITZ_VECTOR_MAX_N {
        return q; // kept only where small: a sweep's scenes, not a 10⁶ run's vectors
    }
    RANDOM_STARTS.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() == RANDOM_STARTS_KEPT {
            c.remove(0);
        }
        c.push((n, seed, q.clone()));
    });
    q
}

/// How many [`random_start`] vectors each thread keeps.
const RANDOM_STARTS_KEPT: usize = 4;

/// Lanczos steps a run makes room for up front (it grows beyond them as needed): its vectors
/// grew by doubling, a reallocation and a copy each time, and a sweep makes hundreds of short
/// runs.
const TYPICAL_STEPS: usize = 32;

/// At most this many words of a kept basis are reserved up front (512 KiB).
const BASIS_RESERVE_WORDS: usize = 1 << 16;

thread_local! {
    /// This thread's last [`random_start`] vectors, `(n, seed, vector)`, oldest first (only
    /// up to [`RITZ_VECTOR_MAX_N`] unknowns).
    static RANDOM_STARTS: std::cell::RefCell<Vec<(usize, u64, Vec<f64>)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// [`random_start`] computed.
fn generate_random_start(n: usize, seed: u64) -> Vec<f64> {
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

pub(crate) fn norm(x: &[f64]) -> f64 {
    dot(x, x).sqrt()
}

#[cfg(test)]
mod tests {
    use super::{lanczos_within, Keep};

    /// An unconverged run without its basis forms its Ritz vector on demand, bit for bit the
    /// vector a run that kept its basis forms, and the one a run that dropped it forms by its
    /// own second pass.
    #[test]
    fn deferred_ritz_vector_is_the_kept_one() {
        let n = 300;
        // A clustered top (second difference): 40 steps do not settle it to 1e-15.
        let apply = |x: &[f64], y: &mut [f64]| {
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < n { x[i + 1] } else { 0.0 };
                y[i] = 2.0 * x[i] - left - right;
            }
        };
        // A warm start, and one that the run refuses (non-finite) for the generic start.
        let warm: Vec<f64> = (0..n).map(|i| ((i * 7 % 13) as f64).sin()).collect();
        let mut bad = warm.clone();
        bad[3] = f64::NAN;
        for start in [None, Some(warm.as_slice()), Some(bad.as_slice())] {
            check_deferred(n, start, apply);
        }
    }

    fn check_deferred(n: usize, start: Option<&[f64]>, apply: impl Fn(&[f64], &mut [f64]) + Copy) {
        let run = |budget, keep| {
            lanczos_within(budget, n, 40, |_| 1e-15, start, keep, apply).expect("finite")
        };
        let kept = run(usize::MAX, Keep::Always);
        assert!(!kept.converged, "the test needs an unconverged run");
        let second_pass = run(10 * n, Keep::Always);
        let deferred = run(10 * n, Keep::IfConverged);
        assert!(deferred.vector.is_none());
        let formed = deferred
            .deferred_vector(&mut |x, y| apply(x, y))
            .expect("deferred");
        let kept = kept.vector.expect("kept");
        assert_eq!(kept, formed);
        assert_eq!(second_pass.vector.expect("second pass"), formed);
        // A run that formed its vector defers nothing.
        assert!(run(usize::MAX, Keep::IfConverged)
            .deferred_vector(&mut |x, y| apply(x, y))
            .is_none());
    }
}
