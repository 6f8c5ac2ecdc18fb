//! Krylov solvers as a user runs them on a final system `A x = b`, for the solver-cost
//! metrics (`metrics::solver`): preconditioned conjugate gradients with the Lanczos
//! coefficients of the run, preconditioned MINRES for the symmetric indefinite saddle
//! point, and restarted GMRES for the unsymmetric (frictional) tangent. All start from x₀ = 0.
//!
//! **CG** (Hestenes & Stiefel 1952) with the recurrences and the stopping test of SciPy's
//! `scipy.sparse.linalg.cg` (1.12+): stop before an iteration when the recursively updated
//! residual has `‖r_k‖₂ ≤ τ·‖b‖₂`; the iteration count is the number of updates of x done.
//! Its step lengths `α_j` and `β_j` are the Lanczos tridiagonal of `M⁻¹A` (Saad, *Iterative
//! Methods*, §6.7.3): `T_jj = 1/α_j + β_{j−1}/α_{j−1}`, `T_{j,j+1} = √β_j / α_j`, whose
//! extreme eigenvalues (Sturm bisection) estimate the preconditioned spectrum's ends: the
//! *effective* condition number `λ_max(T)/λ_min(T)`, an estimate (a lower bound on
//! cond(M⁻¹A) in exact arithmetic, tight once the ends have converged).
//!
//! **MINRES** (Paige & Saunders 1975) with an SPD preconditioner M, the recurrences of SciPy's
//! `minres`: stop when the preconditioned residual estimate `φ_k = ‖r_k‖_{M⁻¹}` has
//! `φ_k ≤ τ·‖b‖_{M⁻¹}`.
//!
//! **Two stopping tests** ([`Stop`]): the residual tests above, or a fixed error of u against a
//! reference solution u* of the same system, `‖x_k[..n_u] − u*‖∞ ≤ target·‖u*‖∞`, checked
//! before every iteration (the count is the first k that meets it; SciPy's `callback` sees the
//! same iterates). Only the second makes counts comparable across penalty rules: the
//! penalized right-hand side `b = q + D E û` grows with ε wherever û ≠ 0, so `‖r‖ ≤ τ‖b‖`
//! loosens as ε grows and a stiffer rule "needs fewer iterations" while stopping further from
//! u (on a Hertz scene, 613 → 7 Jacobi-CG iterations across ε with the error at the stop
//! rising from 2e-8 to 1). [`cg_each`] and [`minres_each`] report several tests from one run
//! (the iterates do not depend on the test): the metrics' pair of counts costs one run.
//!
//! Inner products are compensated (Dot2, see `dot`): the counts of a run on a raw penalized
//! system should not depend on the summation order.
//!
//! Why hand-written: faer 0.24's `conjugate_gradient` reports neither the step lengths nor
//! stops on SciPy's test (its iteration counts are what `tests/data/solver_cost` compares
//! against SciPy's), and faer has neither MINRES nor GMRES. [`super::pcg`] stays faer's, for the active-set
//! solves. The preconditioners ([`super::precond::Jacobi`], [`super::precond::Ic0`]) are in
//! [`super::precond`].

use crate::dd::{two_prod, two_sum};
use faer::sparse::SparseColMatRef;

/// `z = M⁻¹ r` for an SPD preconditioner M.
pub trait Preconditioner {
    /// Writes `M⁻¹ r` into `z`.
    fn apply(&self, r: &[f64], z: &mut [f64]);
}

/// `y = A x` for a square sparse A stored with both triangles (a gather per column of Aᵀ =
/// A for symmetric A).
pub fn matvec(a: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    super::symmetric_matvec(a.symbolic(), a.val(), x, y);
}

/// Dot2 (Ogita, Rump & Oishi 2005): every product exact by `two_prod`, the sum compensated
/// by `two_sum`: as accurate as a dot product in twice the working precision, then rounded.
#[inline(always)]
fn dot2_kernel(x: &[f64], y: &[f64]) -> f64 {
    let (mut s, mut c) = (0.0, 0.0);
    for (&a, &b) in x.iter().zip(y) {
        let (p, e) = two_prod(a, b);
        let (t, f) = two_sum(s, p);
        s = t;
        c += e + f;
    }
    s + c
}

crate::dd::fma_dispatch! {
    /// `xᵀy` by Dot2 ([`dot2_kernel`]). The iteration counts of CG on a raw penalized system
    /// depend on how its inner products round: on `flat-punch-0001` scaled by f = 1e8, plain
    /// sequential sums give 65 iterations where exact sums (Python's `math.fsum`) and NumPy's
    /// give 69. Accurate inner products make the count the algorithm's, not the summation
    /// order's.
    fn dot(x: &[f64], y: &[f64]) -> f64 => dot2_kernel
}

fn norm(x: &[f64]) -> f64 {
    dot(x, x).sqrt()
}

/// When a Krylov run stops (module doc).
#[derive(Clone, Copy, Debug)]
pub enum Stop<'a> {
    /// The residual test with relative tolerance τ (CG: `‖r_k‖₂ ≤ τ‖b‖₂`; MINRES:
    /// `φ_k ≤ τ·φ_0`).
    Residual(f64),
    /// A fixed relative error of u: `‖x_k[..u*.len()] − u*‖∞ ≤ target·‖u*‖∞`, with u* the
    /// reference (the leading block of x: the displacements of a saddle point).
    ErrorOfU {
        /// u*.
        reference: &'a [f64],
        /// The relative error asked for.
        target: f64,
    },
}

impl<'a> Stop<'a> {
    /// The absolute threshold of the error test (`target·‖u*‖∞`), or `None` for the residual
    /// test.
    fn error_threshold(&self) -> Option<(&'a [f64], f64)> {
        match *self {
            Stop::Residual(_) => None,
            Stop::ErrorOfU { reference, target } => {
                let top = reference.iter().fold(0.0f64, |t, v| t.max(v.abs()));
                Some((reference, target * top))
            }
        }
    }

    /// τ of the residual test (0 under the error test: the residual never stops the run).
    fn tol(&self) -> f64 {
        match *self {
            Stop::Residual(t) => t,
            Stop::ErrorOfU { .. } => 0.0,
        }
    }
}

/// `‖x[..u*.len()] − u*‖∞`, NaN if any difference is NaN (so that a NaN iterate never meets
/// the error test: `f64::max` would drop the NaN).
fn error_of_u(x: &[f64], reference: &[f64]) -> f64 {
    x.iter().zip(reference).fold(0.0f64, |t, (a, b)| {
        let d = (a - b).abs();
        if d.is_nan() || d > t {
            d
        } else {
            t
        }
    })
}

/// The relative error `‖x[..u*.len()] − u*‖∞ / ‖u*‖∞` of an iterate, the quantity the error
/// test bounds (where u* = 0: 0 for x = u*, +∞ otherwise, as the test `e ≤ target·0` reads).
pub fn relative_error_of_u(x: &[f64], reference: &[f64]) -> f64 {
    let top = reference.iter().fold(0.0f64, |t, v| t.max(v.abs()));
    let e = error_of_u(x, reference);
    match (top > 0.0, e == 0.0) {
        (true, _) => e / top,
        (false, true) => 0.0,
        (false, false) => f64::INFINITY,
    }
}

/// A Krylov run's statistics.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct KrylovRun {
    /// Iterations done (updates of x).
    pub iterations: usize,
    /// The stopping test was met within the iteration limit.
    pub converged: bool,
    /// The residual measure of the stopping test at the end, relative to its value at x₀ = 0
    /// (CG: `‖r‖₂/‖b‖₂`, recursively updated; MINRES: `φ_k/φ_0`, the estimate).
    pub relative_residual: f64,
    /// CG: the estimated extreme eigenvalues `(λ_min, λ_max)` of `M⁻¹A` from the Lanczos
    /// tridiagonal of the run (`None` for MINRES and for runs of no iteration).
    pub spectrum: Option<(f64, f64)>,
}

impl KrylovRun {
    /// A run of no iteration that has met its test (b = 0).
    const DONE: KrylovRun = KrylovRun {
        iterations: 0,
        converged: true,
        relative_residual: 0.0,
        spectrum: None,
    };

    /// The effective condition number `λ_max/λ_min` of the preconditioned operator as the run
    /// saw it (an estimate; `None` without a spectrum).
    pub fn effective_cond(&self) -> Option<f64> {
        self.spectrum.map(|(lo, hi)| hi / lo)
    }
}

/// A Krylov solver that reports several stopping tests from one run ([`cg_each`],
/// [`minres_each`]): `(A, M, b, stops, max_iters, at_stop) → the last iterate`.
pub type EachSolver = fn(
    SparseColMatRef<'_, usize, f64>,
    &dyn Preconditioner,
    &[f64],
    &[Stop<'_>],
    usize,
    &mut dyn FnMut(usize, &[f64], KrylovRun),
) -> Vec<f64>;

/// Preconditioned CG from x₀ = 0 on the SPD `A x = b`: returns x and the run. Stops when
/// `stop` is met (`Stop::Residual(τ)`: `‖r_k‖₂ ≤ τ·‖b‖₂`, SciPy's `cg` test and count, see the
/// module doc) or after `max_iters` iterations. A breakdown (`pᵀAp ≤ 0` or `rᵀz ≤ 0`: A or M
/// not positive definite) ends the run unconverged.
pub fn cg(
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stop: Stop<'_>,
    max_iters: usize,
) -> (Vec<f64>, KrylovRun) {
    one_stop(cg_each, a, pre, b, stop, max_iters)
}

/// One CG run that reports each of several stopping tests ([`cg`] for each `stops[i]`): it
/// runs until every test is met (or a breakdown, or `max_iters`) and calls
/// `at_stop(i, x_k, run)` where test i ends, with the iterate and the run as [`cg`] with that
/// test alone would return them (the iterates do not depend on the test). Returns the last
/// iterate. The metrics' pair of runs (to the error of u and to the residual test) shares
/// its iterations this way.
pub fn cg_each(
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stops: &[Stop<'_>],
    max_iters: usize,
    at_stop: &mut dyn FnMut(usize, &[f64], KrylovRun),
) -> Vec<f64> {
    let n = b.len();
    let mut x = vec![0.0; n];
    let bnorm = norm(b);
    let tests: Vec<Test<'_>> = stops.iter().map(|s| Test::new(s, bnorm)).collect();
    let mut pending: Vec<usize> = Vec::with_capacity(stops.len());
    for (i, t) in tests.iter().enumerate() {
        if bnorm == 0.0 || t.met_err(&x) {
            at_stop(i, &x, KrylovRun::DONE);
        } else {
            pending.push(i);
        }
    }
    if pending.is_empty() {
        return x;
    }
    let (mut r, mut z, mut p, mut q) = (b.to_vec(), vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut rho_prev = 0.0;
    let mut rnorm = bnorm;
    let mut iterations = 0;
    let mut finish = |i: usize,
                      x: &[f64],
                      converged: bool,
                      iterations: usize,
                      rnorm: f64,
                      alphas: &[f64],
                      betas: &[f64]| {
        let run = KrylovRun {
            iterations,
            converged,
            relative_residual: rnorm / bnorm,
            spectrum: lanczos_ends(alphas, betas),
        };
        at_stop(i, x, run);
    };
    for it in 0..max_iters {
        pending.retain(|&i| {
            let met = tests[i].met(&x, rnorm);
            if met {
                finish(i, &x, true, iterations, rnorm, &alphas, &betas);
            }
            !met
        });
        if pending.is_empty() {
            return x;
        }
        pre.apply(&r, &mut z);
        let rho = dot(&r, &z);
        if !(rho > 0.0 && rho.is_finite()) {
            break;
        }
        if it > 0 {
            let beta = rho / rho_prev;
            betas.push(beta);
            p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        } else {
            p.copy_from_slice(&z);
        }
        matvec(a, &p, &mut q);
        let pq = dot(&p, &q);
        if !(pq > 0.0 && pq.is_finite()) {
            break;
        }
        let alpha = rho / pq;
        alphas.push(alpha);
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&q).for_each(|(r, q)| *r -= alpha * q);
        rho_prev = rho;
        rnorm = norm(&r);
        iterations = it + 1;
    }
    for &i in &pending {
        let met = tests[i].met(&x, rnorm);
        finish(i, &x, met, iterations, rnorm, &alphas, &betas);
    }
    x
}

/// One stopping test of a run, its threshold resolved ([`Stop`]).
struct Test<'a> {
    /// u* and the absolute error threshold (the error test).
    err: Option<(&'a [f64], f64)>,
    /// The absolute residual threshold (the residual test; 0 under the error test).
    atol: f64,
}

impl<'a> Test<'a> {
    /// `stop` with its residual threshold relative to `scale` (CG: ‖b‖₂; MINRES: φ₀).
    fn new(stop: &Stop<'a>, scale: f64) -> Self {
        Test {
            err: stop.error_threshold(),
            atol: stop.tol() * scale,
        }
    }

    /// The error test holds at `x` (false for a residual test).
    fn met_err(&self, x: &[f64]) -> bool {
        self.err.is_some_and(|(u, t)| error_of_u(x, u) <= t)
    }

    /// The test holds at `x` with residual measure `res`.
    fn met(&self, x: &[f64], res: f64) -> bool {
        match self.err {
            Some(_) => self.met_err(x),
            None => res <= self.atol,
        }
    }
}

/// The extreme eigenvalues of CG's Lanczos tridiagonal (module doc) by Sturm bisection.
fn lanczos_ends(alphas: &[f64], betas: &[f64]) -> Option<(f64, f64)> {
    let k = alphas.len();
    if k == 0 {
        return None;
    }
    let diag: Vec<f64> = (0..k)
        .map(|j| {
            1.0 / alphas[j]
                + if j > 0 {
                    betas[j - 1] / alphas[j - 1]
                } else {
                    0.0
                }
        })
        .collect();
    let off: Vec<f64> = (0..k - 1).map(|j| betas[j].sqrt() / alphas[j]).collect();
    Some(tridiagonal_ends(&diag, &off))
}

/// Smallest and largest eigenvalue of the symmetric tridiagonal matrix (`diag`, `off`) by
/// bisection on the Sturm count (the number of negative pivots of `T − xI`), to a relative
/// width of 4·ε_mach of the larger end.
pub fn tridiagonal_ends(diag: &[f64], off: &[f64]) -> (f64, f64) {
    let k = diag.len();
    let below = |x: f64| -> usize {
        let mut count = 0;
        let mut d = 1.0;
        for i in 0..k {
            let o = if i > 0 { off[i - 1] * off[i - 1] } else { 0.0 };
            d = diag[i] - x - if i > 0 { o / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::MIN_POSITIVE;
            }
            if d < 0.0 {
                count += 1;
            }
        }
        count
    };
    // Gershgorin interval.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..k {
        let r = if i > 0 { off[i - 1].abs() } else { 0.0 } + off.get(i).map_or(0.0, |o| o.abs());
        lo = lo.min(diag[i] - r);
        hi = hi.max(diag[i] + r);
    }
    let width = 4.0 * f64::EPSILON * lo.abs().max(hi.abs());
    // The j-th smallest eigenvalue (0-based): the x where the count passes j.
    let nth = |j: usize| {
        let (mut a, mut b) = (lo, hi);
        while b - a > width {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if below(m) > j {
                b = m;
            } else {
                a = m;
            }
        }
        0.5 * (a + b)
    };
    (nth(0), nth(k - 1))
}

/// Preconditioned MINRES from x₀ = 0 on the symmetric (indefinite) `A x = b` with an SPD
/// preconditioner: returns x and the run. Stops when `stop` is met (`Stop::Residual(τ)`:
/// `φ_k ≤ τ·φ_0`, module doc) or after `max_iters`.
pub fn minres(
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stop: Stop<'_>,
    max_iters: usize,
) -> (Vec<f64>, KrylovRun) {
    one_stop(minres_each, a, pre, b, stop, max_iters)
}

/// The run of `each` with the one test `stop`: its last iterate and its statistics.
fn one_stop(
    each: EachSolver,
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stop: Stop<'_>,
    max_iters: usize,
) -> (Vec<f64>, KrylovRun) {
    let mut out = KrylovRun::DONE;
    let x = each(a, pre, b, &[stop], max_iters, &mut |_, _, run| out = run);
    (x, out)
}

/// One MINRES run that reports each of several stopping tests, as [`cg_each`] does for CG.
pub fn minres_each(
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    stops: &[Stop<'_>],
    max_iters: usize,
    at_stop: &mut dyn FnMut(usize, &[f64], KrylovRun),
) -> Vec<f64> {
    let n = b.len();
    let mut x = vec![0.0; n];
    let mut pending: Vec<usize> = Vec::with_capacity(stops.len());
    for (i, s) in stops.iter().enumerate() {
        if Test::new(s, 0.0).met_err(&x) {
            at_stop(i, &x, KrylovRun::DONE);
        } else {
            pending.push(i);
        }
    }
    if pending.is_empty() {
        return x;
    }
    let mut y = vec![0.0; n];
    pre.apply(b, &mut y);
    let beta1 = dot(b, &y);
    if beta1 == 0.0 {
        pending
            .iter()
            .for_each(|&i| at_stop(i, &x, KrylovRun::DONE));
        return x;
    }
    if !(beta1 > 0.0 && beta1.is_finite()) {
        let run = KrylovRun {
            converged: false,
            relative_residual: f64::NAN,
            ..KrylovRun::DONE
        };
        pending.iter().for_each(|&i| at_stop(i, &x, run));
        return x;
    }
    let beta1 = beta1.sqrt();
    let tests: Vec<Test<'_>> = stops.iter().map(|s| Test::new(s, beta1)).collect();
    let (mut r1, mut r2) = (b.to_vec(), b.to_vec());
    let (mut w, mut w1, mut w2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut v = vec![0.0; n];
    let (mut oldb, mut beta, mut dbar, mut epsln, mut phibar) = (0.0, beta1, 0.0, 0.0, beta1);
    let (mut cs, mut sn) = (-1.0f64, 0.0f64);
    let mut iterations = 0;
    let mut finish = |i: usize, x: &[f64], converged: bool, iterations: usize, phibar: f64| {
        let run = KrylovRun {
            iterations,
            converged,
            relative_residual: phibar / beta1,
            spectrum: None,
        };
        at_stop(i, x, run);
    };
    for it in 0..max_iters {
        pending.retain(|&i| {
            let met = tests[i].met(&x, phibar);
            if met {
                finish(i, &x, true, iterations, phibar);
            }
            !met
        });
        if pending.is_empty() {
            return x;
        }
        let s = 1.0 / beta;
        v.iter_mut().zip(&y).for_each(|(v, y)| *v = s * y);
        matvec(a, &v, &mut y);
        if it >= 1 {
            let c = beta / oldb;
            y.iter_mut().zip(&r1).for_each(|(y, r)| *y -= c * r);
        }
        let alfa = dot(&v, &y);
        let c = alfa / beta;
        y.iter_mut().zip(&r2).for_each(|(y, r)| *y -= c * r);
        std::mem::swap(&mut r1, &mut r2);
        r2.copy_from_slice(&y);
        pre.apply(&r2, &mut y);
        oldb = beta;
        let bb = dot(&r2, &y);
        if !(bb >= 0.0 && bb.is_finite()) {
            break;
        }
        beta = bb.sqrt();
        // The previous rotation on the new column, then the next rotation.
        let oldeps = epsln;
        let delta = cs * dbar + sn * alfa;
        let gbar = sn * dbar - cs * alfa;
        epsln = sn * beta;
        dbar = -cs * beta;
        let gamma = gbar.hypot(beta).max(f64::EPSILON);
        cs = gbar / gamma;
        sn = beta / gamma;
        let phi = cs * phibar;
        phibar *= sn;
        let denom = 1.0 / gamma;
        std::mem::swap(&mut w1, &mut w2);
        std::mem::swap(&mut w2, &mut w);
        for i in 0..n {
            w[i] = (v[i] - oldeps * w1[i] - delta * w2[i]) * denom;
            x[i] += phi * w[i];
        }
        iterations = it + 1;
        if beta == 0.0 {
            // An invariant subspace: x is exact (in exact arithmetic); the next step would
            // divide by β = 0. Stop here; the test below decides convergence.
            phibar = 0.0;
            break;
        }
    }
    for &i in &pending {
        let met = tests[i].met(&x, phibar);
        finish(i, &x, met, iterations, phibar);
    }
    x
}

/// `y = A x` for a general square sparse A (compressed columns: a scatter per column), for
/// unsymmetric matrices ([`matvec`] reads A's columns as its rows).
pub fn matvec_general(a: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    y.iter_mut().for_each(|v| *v = 0.0);
    for (j, &xj) in x.iter().enumerate() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            y[i] += v * xj;
        }
    }
}

/// Restarted GMRES(m) (Saad & Schultz 1986) from x₀ = 0 on a general square `A x = b`, right
/// preconditioned (`A M⁻¹ y = b`, x = M⁻¹y: the residual it minimizes is the true one), modified
/// Gram–Schmidt, Givens rotations; every inner step counts as one iteration (one product with
/// A), as SciPy's `gmres` callback with `callback_type='pr_norm'` counts them. Stops when `stop`
/// is met — `Stop::Residual(τ)`: `‖r_k‖₂ ≤ τ‖b‖₂` (the rotated estimate); `Stop::ErrorOfU`: the
/// iterate, formed at every step, within the target of u* — or after `max_iters`. A restart
/// recomputes the true residual.
pub fn gmres(
    a: SparseColMatRef<'_, usize, f64>,
    pre: &dyn Preconditioner,
    b: &[f64],
    restart: usize,
    stop: Stop<'_>,
    max_iters: usize,
) -> (Vec<f64>, KrylovRun) {
    let n = b.len();
    let m = restart.max(1);
    let mut x = vec![0.0; n];
    let bnorm = norm(b);
    let mut run = KrylovRun::DONE;
    let err = stop.error_threshold();
    let met_err = |x: &[f64]| err.is_some_and(|(u, t)| error_of_u(x, u) <= t);
    if bnorm == 0.0 || met_err(&x) {
        return (x, run);
    }
    run.converged = false;
    let atol = stop.tol() * bnorm;
    let mut r = b.to_vec();
    let mut w = vec![0.0; n];
    let mut rnorm = bnorm;
    // The iterate x + Z y for the first `k` columns of the current cycle.
    let form = |x: &[f64], z: &[Vec<f64>], h: &[Vec<f64>], g: &[f64], k: usize| -> Vec<f64> {
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let s: f64 = (i + 1..k).map(|j| h[j][i] * y[j]).sum();
            y[i] = (g[i] - s) / h[i][i];
        }
        let mut out = x.to_vec();
        for (zi, yi) in z.iter().zip(&y) {
            out.iter_mut().zip(zi).for_each(|(o, v)| *o += yi * v);
        }
        out
    };
    'cycles: while run.iterations < max_iters {
        let beta = rnorm;
        if beta == 0.0 {
            run.converged = true;
            break;
        }
        let mut v: Vec<Vec<f64>> = vec![r.iter().map(|ri| ri / beta).collect()];
        let mut z: Vec<Vec<f64>> = Vec::with_capacity(m);
        // h[j] is column j of the Hessenberg matrix (j + 2 entries), rotated in place.
        let mut h: Vec<Vec<f64>> = Vec::with_capacity(m);
        let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::with_capacity(m), Vec::with_capacity(m));
        let mut g = vec![beta];
        for j in 0..m {
            let mut zj = vec![0.0; n];
            pre.apply(&v[j], &mut zj);
            matvec_general(a, &zj, &mut w);
            let mut col = Vec::with_capacity(j + 2);
            for vi in v.iter() {
                let hij = dot(&w, vi);
                w.iter_mut().zip(vi).for_each(|(wk, vk)| *wk -= hij * vk);
                col.push(hij);
            }
            let hnext = norm(&w);
            col.push(hnext);
            for i in 0..j {
                let (a0, a1) = (col[i], col[i + 1]);
                col[i] = cs[i] * a0 + sn[i] * a1;
                col[i + 1] = -sn[i] * a0 + cs[i] * a1;
            }
            let d = col[j].hypot(col[j + 1]);
            let (c, s) = if d == 0.0 {
                (1.0, 0.0)
            } else {
                (col[j] / d, col[j + 1] / d)
            };
            col[j] = d;
            col[j + 1] = 0.0;
            cs.push(c);
            sn.push(s);
            g.push(-s * g[j]);
            g[j] *= c;
            h.push(col);
            z.push(zj);
            run.iterations += 1;
            rnorm = g[j + 1].abs();
            let done = match err {
                Some(_) => {
                    let xk = form(&x, &z, &h, &g, j + 1);
                    let ok = met_err(&xk);
                    if ok {
                        x = xk;
                    }
                    ok
                }
                None => rnorm <= atol,
            };
            if done {
                if err.is_none() {
                    x = form(&x, &z, &h, &g, j + 1);
                }
                run.converged = true;
                break 'cycles;
            }
            if hnext == 0.0 || run.iterations >= max_iters || !rnorm.is_finite() {
                x = form(&x, &z, &h, &g, j + 1);
                if hnext == 0.0 && rnorm.is_finite() {
                    // An invariant subspace: x solves the system (in exact arithmetic).
                    run.converged = met_err(&x) || (err.is_none() && rnorm <= atol);
                }
                break 'cycles;
            }
            v.push(w.iter().map(|wk| wk / hnext).collect());
        }
        x = form(&x, &z, &h, &g, m);
        matvec_general(a, &x, &mut w);
        r.iter_mut()
            .zip(b.iter().zip(&w))
            .for_each(|(ri, (bi, wi))| *ri = bi - wi);
        rnorm = norm(&r);
    }
    run.relative_residual = rnorm / bnorm;
    (x, run)
}

#[cfg(test)]
mod tests;
