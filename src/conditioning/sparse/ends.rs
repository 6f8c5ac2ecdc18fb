//! Phase 2 of the sparse SPD route ([`super::extreme_eigenvalues`]): the proven brackets of
//! both ends around the estimates, and the refined values inside them.

use super::{
    lanczos, rayleigh_interval, Estimates, MAX_LANCZOS_STEPS, PLAIN_LANCZOS_STEPS, STAGNATION,
    TOP_STAGNATION,
};
use crate::conditioning::certify::{self, Margin};
use crate::conditioning::lanczos::{inverse_lanczos, Keep, LanczosRun};
use crate::conditioning::shifts::{graded_estimate, graded_floor, ShiftFamily};
use crate::conditioning::temple;
use crate::linalg::SparseLlt;

/// Phase 2 of [`extreme_eigenvalues`]: the proven brackets around the estimates
/// ([`certify`]) and the refined values inside them.
pub(super) struct Ends {
    pub(super) max_lo: f64,
    pub(super) max_hi: f64,
    pub(super) min_lo: f64,
    pub(super) min_hi: f64,
    /// λ_max from a shift-invert run where the first upper test failed or the estimate was
    /// rough (a warm plain run stopped at its budget, `Estimates::top_rough`).
    pub(super) refined_max: Option<f64>,
    /// λ_min as the inverse-Rayleigh value of Lemma 6, where it is positive.
    pub(super) refined_min: Option<f64>,
    /// Lanczos steps of the λ_max refinement.
    pub(super) steps: usize,
    /// The relative width aimed at ([`width_target`]).
    pub(super) target: f64,
}

/// The relative width a certified cond₂ bracket aims at:
/// `max(1e-12, min(8·ε_mach·cond₂(Ŝ⁻¹AŜ⁻¹), 3.5·ε_mach·cond₂))` (`cond_eq`, `cond`; the route
/// uses estimates), or the tolerance asked for where that is wider. The equilibrated term is
/// the rounding floor of the graded matrices (far below the contract there); the second keeps
/// every bracket that meets its target within the contract `max(1e-12, 4·ε_mach·cond₂)`, so
/// that the point is *proven* within it ([`crate::conditioning::CondReport::within_contract`]). The top end
/// takes a fifth, the bottom end the rest.
pub fn width_target(tol: Option<f64>, cond_eq: f64, cond: f64) -> f64 {
    tol.unwrap_or(0.0)
        .max(1e-12)
        .max((8.0 * f64::EPSILON * cond_eq).min(3.5 * f64::EPSILON * cond))
}

/// A proven lower end of ρ(y) for a top vector, from its plain interval `plain`
/// ([`rayleigh_interval`], which carries γ_N of rounding: ≈ N·u, 1e-12 relative at 10⁴
/// unknowns, 1e-10 at 10⁶): where that is wider than `need`, raised by ρ to the u² level
/// ([`certify::rayleigh_interval_dot2`]).
fn sharpen_top(
    pat: faer::sparse::SymbolicSparseColMatRef<'_, usize>,
    vals: &[f64],
    y: &[f64],
    plain: (f64, f64),
    need: f64,
) -> f64 {
    if plain.1 / plain.0 - 1.0 <= need {
        plain.0
    } else {
        certify::rayleigh_interval_dot2(pat, vals, y).map_or(plain.0, |(lo, _)| lo.max(plain.0))
    }
}

/// The shift-invert Lanczos run of a refinement: the top eigenvalue ν of `B⁻¹`, `f` the
/// Cholesky factor of a passing test `B = ±(A − sI)` of order `n`, from `start`; then λ = s ∓ 1/ν. Converged
/// further than the estimates (a rare path): a near-double end needs the vector resolved, not
/// only the value, for its Rayleigh quotient to tighten the bracket (a proptest
/// counterexample, committed).
fn shift_invert(
    n: usize,
    f: &SparseLlt,
    start: Option<&[f64]>,
) -> crate::error::Result<LanczosRun> {
    inverse_lanczos(n, MAX_LANCZOS_STEPS, 1e-2 * STAGNATION, start, |y| {
        f.solve_vec_in_place(y)
    })
}

pub(super) fn certify_ends(
    fam: &mut ShiftFamily,
    est: &Estimates,
    margin: Margin,
    tol: Option<f64>,
) -> Ends {
    let (pat, vals) = (fam.pattern.pat(), fam.pattern.values.as_slice());
    // The bottom end's upper side through Lemma 6 with compensated sums (a plain ρ(y_bottom)
    // carries ε·cond₂ of rounding and is rarely sharper).
    let refined_min = certify::inverse_rayleigh_upper(pat, vals, &est.bottom, &est.x_hat);
    let top = certify_top(fam, est, margin, tol);
    let bottom = certify_bottom(fam, est, margin, &top, refined_min);
    Ends {
        max_lo: top.max_lo,
        max_hi: top.max_hi,
        min_lo: bottom.min_lo,
        min_hi: bottom.min_hi,
        refined_max: top.refined_max,
        refined_min: bottom.refined_min,
        steps: top.steps + bottom.steps,
        target: top.target,
    }
}

/// The λ_max end of [`certify_ends`] and the width target.
struct Top {
    max_lo: f64,
    max_hi: f64,
    refined_max: Option<f64>,
    steps: usize,
    target: f64,
}

/// The λ_min end of [`certify_ends`].
struct Bottom {
    min_lo: f64,
    min_hi: f64,
    refined_min: Option<f64>,
    steps: usize,
}

/// λ_max ∈ [ρ(y_top), Cor. 2]: the tests start just outside the estimate (by the bound's own
/// margin) and step out ×8 until the floating-point Cholesky succeeds.
fn certify_top(fam: &mut ShiftFamily, est: &Estimates, margin: Margin, tol: Option<f64>) -> Top {
    let max_diag = fam.pattern.max_diagonal();
    let (lmax_est, lmin_est) = (est.lmax, est.lmin);
    let (pat, vals) = (fam.pattern.pat(), fam.pattern.values.as_slice());
    // ρ(y_top) in f64 with its rounding bounded (`rayleigh_interval`: ≈ k·ε relative at the
    // top of the spectrum).
    let top_plain = est
        .top
        .as_deref()
        .and_then(|y| rayleigh_interval(pat, vals, y));
    // cond₂(Ĥ) from below: λ_max(Ĥ) ≥ max(1, ρ_Ĥ(Ŝy_top)), ρ_Ĥ(Ŝy) = ρ(y)·‖y‖²/Σ a_ii y_i².
    let hmax_lo = match (&est.top, top_plain) {
        (Some(t), Some((lo, _))) => {
            let tt: f64 = t.iter().map(|v| v * v).sum();
            let wt: f64 = t.iter().zip(&est.s_hat).map(|(v, s)| (v * s).powi(2)).sum();
            (lo * tt / wt).max(1.0)
        }
        _ => 1.0,
    };
    let target = width_target(
        tol,
        (est.inv_hmin_lo * hmax_lo).max(1.0),
        (lmax_est / lmin_est).max(1.0),
    );
    // The top end's share of the target: half, Temple's bound (a few ε_mach wide; an LDLᵀ
    // or, on supernodal factors, an interlacing test) being expected to serve the bottom end.
    let top_share = 0.5;
    let top_need = 0.25 * top_share * target;
    let mut max_lo = match (est.top.as_deref(), top_plain) {
        (Some(y), Some(plain)) => sharpen_top(pat, vals, y, plain, 2.0 * top_need).max(max_diag),
        _ => max_diag,
    };
    // A Ritz vector whose Rayleigh quotient lags the Ritz value beyond the lower side's share
    // (lost behind a large gap, the value not): a second, short run started from it.
    let mut restart_steps = 0;
    if let Some(y) = est
        .top
        .as_deref()
        .filter(|_| lmax_est / max_lo - 1.0 > 2.0 * top_need)
    {
        let (lo, k) = restart_top(fam, y, 2.0 * top_need);
        max_lo = max_lo.max(lo);
        restart_steps = k;
    }
    // A first test that fails means the plain Lanczos run stopped short of λ_max (a cluster
    // at the top creeps below the stagnation test): the factor of the test that succeeds,
    // σI − A with σ just above λ_max, drives a shift-invert run, λ_max = σ − 1/ν_max, accurate
    // to ε_mach·‖A‖.
    // Where Lemma 1's a-priori margin alone would miss the target width, the tests start
    // at a few ε and each success is judged by its own residual (Lemma 7).
    let base = lmax_est.max(max_lo);
    // Tests placed for their own margins where one can be had: Lemma 7's residual up to
    // POSTERIOR_MAX_PRODUCTS, Lemma 7a (the factor read in place) on supernodal factors above.
    let top_posterior = margin.m > top_need && (fam.posterior_ok || !fam.pattern.has_ldlt());
    let w0 = if top_posterior {
        (0.5 * top_share * target).max(4.0 * f64::EPSILON)
    } else {
        (4.0 * margin.m).max(4.0 * f64::EPSILON)
    };
    // A rough estimate (the plain run stopped at its budget, `top_estimate`): the first test
    // four of its last changes above it, where the refinement below takes over.
    let w0 = est.top_rough.map_or(w0, |r| w0.max(4.0 * r));
    // The margin of a successful top test at σ (its factor f, its largest stored b̃_ii).
    // (Lemma 1's margin alone where the placement does not aim at Lemma 7's: need = ∞.)
    let top_need = if top_posterior {
        top_need
    } else {
        f64::INFINITY
    };
    let top_bound = |fam: &ShiftFamily, f: &SparseLlt, s: f64, max_b: f64| {
        fam.margin_of(f, -1.0, s, margin, top_need)
            .upper_from_test(s, max_b)
    };
    let (mut max_hi, refined, steps) = certify::step_outwards(w0, |w, k| {
        let s = base * (1.0 + w);
        let (f, max_b) = fam.test_factor(-1.0, s)?;
        let refined = (k > 0 || est.top_rough.is_some())
            .then(|| shift_invert(fam.pattern.n(), &f, est.top.as_deref()));
        let steps = refined
            .as_ref()
            .map_or(0, |r| r.as_ref().map_or(0, |r| r.steps));
        let refined = refined
            .and_then(|r| r.ok())
            .filter(|r| r.theta > 0.0 && r.theta.is_finite())
            .map(|r| (s - 1.0 / r.theta, s, r.vector));
        Some((top_bound(fam, &f, s, max_b), refined, steps))
    })
    .unwrap_or((f64::INFINITY, None, 0));
    // After a shift-invert refinement (the plain run stopped short below a cluster), its Ritz
    // vector raises the lower end, and tests stepping out from the refined value — below the
    // test that succeeded — tighten the upper end.
    let refined_max = refined.map(|(r, s_ok, vector)| {
        if let Some(v) = vector {
            let share = 0.25 * top_share * target;
            let (lo, k) = refined_lower(fam, (r, &v), max_lo, 2.0 * top_need, share);
            (max_lo, restart_steps) = (lo, restart_steps + k);
        }
        if max_hi / r.max(max_lo) - 1.0 > top_share * target {
            let from = r.max(max_lo);
            if let Some(hi) = certify::step_outwards(4.0 * f64::EPSILON, |w, _| {
                let s = from * (1.0 + w);
                if s >= s_ok {
                    return Some(f64::INFINITY);
                }
                let (f, max_b) = fam.test_factor(-1.0, s)?;
                Some(top_bound(fam, &f, s, max_b))
            }) {
                max_hi = max_hi.min(hi);
            }
        }
        r
    });
    Top {
        max_lo,
        max_hi,
        refined_max,
        steps: steps + restart_steps,
        target,
    }
}

/// The lower end of λ_max after a shift-invert refinement (value `r`, Ritz vector `v`), from
/// `max_lo`: `v`'s sharpened Rayleigh quotient ([`sharpen_top`] to `need`), and where it
/// lags `r` by more than `share`, a plain run from `v` ([`restart_top`], up to
/// [`PLAIN_LANCZOS_STEPS`] products, a few where `v` is good; its steps returned): the
/// shift-invert run leaves the components of the far spectrum that its start carried, which
/// barely move its value but much the quotient on A.
fn refined_lower(
    fam: &ShiftFamily,
    (r, v): (f64, &[f64]),
    max_lo: f64,
    need: f64,
    share: f64,
) -> (f64, usize) {
    let (pat, vals) = (fam.pattern.pat(), fam.pattern.values.as_slice());
    let mut lo = max_lo;
    if let Some(plain) = rayleigh_interval(pat, vals, v) {
        lo = lo.max(sharpen_top(pat, vals, v, plain, need));
    }
    if r / lo - 1.0 <= share {
        return (lo, 0);
    }
    let (restarted, steps) = restart_top(fam, v, share);
    (lo.max(restarted), steps)
}

/// A second Lanczos run on A started from the Ritz vector `y` (up to
/// [`PLAIN_LANCZOS_STEPS`] products, a few from a good vector): the sharpened Rayleigh
/// quotient of its Ritz vector (a lower end of λ_max, [`sharpen_top`] to `need`; 0 where the
/// run fails) and its steps.
fn restart_top(fam: &ShiftFamily, y: &[f64], need: f64) -> (f64, usize) {
    let (pat, vals) = (fam.pattern.pat(), fam.pattern.values.as_slice());
    let Ok(run) = lanczos(
        fam.pattern.n(),
        PLAIN_LANCZOS_STEPS,
        |_| TOP_STAGNATION,
        Some(y),
        Keep::Always,
        |x, z| fam.pattern.matvec(x, z),
    ) else {
        return (0.0, 0);
    };
    let lo = run
        .vector
        .and_then(|v| rayleigh_interval(pat, vals, &v).map(|p| sharpen_top(pat, vals, &v, p, need)))
        .unwrap_or(0.0);
    (lo, run.steps)
}

/// The graded estimate Temple deferred (`est.deferred`), from a new factor of A: Theorem 4's
/// floor h and the solves it took; None where A does not factor or the estimate fails.
fn deferred_graded_floor(
    fam: &mut ShiftFamily,
    est: &Estimates,
    margin: Margin,
) -> Option<(Option<f64>, usize)> {
    let f = fam.factor(1.0, 0.0)?;
    let z: Vec<f64> = est
        .bottom
        .iter()
        .zip(&est.s_hat)
        .map(|(y, s)| y * s)
        .collect();
    let (h_est, k) = graded_estimate(&est.s_hat, &z, |y| f.solve_vec_in_place(y)).ok()?;
    drop(f);
    Some((graded_floor(fam, &est.s_hat, h_est, margin), k))
}

/// The inverse-Rayleigh value of `v` (Lemma 6, from a new factor of A): an upper end of
/// λ_min; None where A does not factor or the bound is not finite.
fn inverse_rayleigh_upper(fam: &mut ShiftFamily, v: &[f64]) -> Option<f64> {
    let f = fam.factor(1.0, 0.0)?;
    let mut x = v.to_vec();
    f.solve_vec_in_place(&mut x);
    let (pat, vals) = (fam.pattern.pat(), fam.pattern.values.as_slice());
    certify::inverse_rayleigh_upper(pat, vals, v, &x)
}

/// Temple's lower bound of λ_min from the inverse iterate x̂ (temple, Theorem 9: one LDLᵀ
/// inertia test, second order in x̂'s residual; its tests counted as factorizations); None
/// where it is not positive.
fn temple_floor(fam: &mut ShiftFamily, est: &Estimates, base: f64, h: Option<f64>) -> Option<f64> {
    let (lo, tests) =
        temple::lambda_min_lower(&fam.pattern, &est.x_hat, base, est.lambda2, &est.s_hat, h);
    fam.factorizations += tests;
    lo.filter(|&lo| lo > 0.0)
}

/// The first relative offset of λ_min's Cholesky tests and their growth per step:
/// a-posteriori tests aim at a fifth of the `share` (a test passes once the offset exceeds the
/// residual's own loss, a few u·scale) and grow ×4, the margin getting the rest; a-priori
/// ones start at Lemma 1's margin times `scale` and grow ×8. At least 4 ε.
fn first_offset(posterior: bool, share: f64, scale: f64, margin: Margin) -> (f64, f64) {
    let (w0, growth) = if posterior {
        (
            (0.2 * share).clamp(2.0 * certify::U * scale, margin.m * scale),
            4.0,
        )
    } else {
        (margin.m * scale, 8.0)
    };
    (w0.max(4.0 * f64::EPSILON), growth)
}

/// λ_min ∈ [Cor. 3, Thm 4 or Temple, Lemma 6]: the tests start just inside the estimate and
/// step out until the floating-point Cholesky succeeds; a first test that fails refines the
/// estimate by shift-invert (a near-double or clustered bottom).
fn certify_bottom(
    fam: &mut ShiftFamily,
    est: &Estimates,
    margin: Margin,
    top: &Top,
    refined_min: Option<f64>,
) -> Bottom {
    let (max_lo, max_hi, target) = (top.max_lo, top.max_hi, top.target);
    let max_diag = fam.pattern.max_diagonal();
    let lmin_est = est.lmin;
    let mut steps = 0;

    // e_iᵀAe_i = A_ii bounds λ_min from above too.
    let diag_min = fam.pattern.min_diagonal();
    let mut min_hi = refined_min.map_or(diag_min, |b| b.min(diag_min));
    let mut refined_min = refined_min;
    let base = lmin_est.min(min_hi);
    // What the top end left of the target: the bottom end's share (the top end's own width,
    // placed at `top_share` but also carrying the Ritz value's lag, is what it is; a twentieth
    // at least, which Temple's bound meets by orders of magnitude).
    let share = (target - (max_hi / max_lo - 1.0)).max(0.05 * target);
    let mut h = graded_floor(fam, &est.s_hat, est.h_est, margin);
    // The relative loss per unit of margin: 1/h (Theorem 4) or max_i a_ii / λ_min (Cor. 3).
    let scale_of = |h: Option<f64>| h.map_or(max_diag / base, |h| 1.0 / h);
    // Lemma 1 alone: the first test at an offset of m·scale, the bound as far again below.
    let short = |h: Option<f64>| 2.0 * margin.m * scale_of(h) > 0.9 * share;
    // Where Lemma 1 misses, Temple's bound from the inverse iterate x̂ (temple, Theorem 9:
    // one LDLᵀ inertia test, second order in x̂'s residual) before a Cholesky test judged by
    // its residual (Lemma 7, ≈ 5 factorizations).
    let temple = (short(h) && est.x_hat.len() == fam.pattern.n())
        .then(|| temple_floor(fam, est, base, h))
        .flatten();
    // Temple's bound where it meets the share; else the Cholesky tests (its bound kept where
    // it is the better one).
    let min_lo = match temple.filter(|&lo| min_hi / lo - 1.0 <= 0.95 * share) {
        Some(lo) => lo,
        None => {
            if est.deferred && short(h) {
                // Temple missed: the graded estimate it deferred, from a new factor of A.
                if let Some((h_new, k)) = deferred_graded_floor(fam, est, margin) {
                    steps += k;
                    h = h_new;
                }
            }
            let scale = scale_of(h);
            let posterior = short(h) && fam.posterior_ok;
            let (w0, growth) = first_offset(posterior, share, scale, margin);
            // The bound of a Cholesky test of A − sI that succeeded (its factor f), at offset w.
            let bound_of = |fam: &ShiftFamily, f: &SparseLlt, s: f64, max_b: f64, w: f64| {
                let need = if posterior {
                    (0.95 * share - w) / scale
                } else {
                    f64::INFINITY
                };
                let m = fam.margin_of(f, 1.0, -s, margin, need);
                m.lower_from_test(s, max_b, h)
            };
            // A first test that fails means the estimate sits above λ_min: a near-double or
            // clustered bottom that the run on A⁻¹ did not resolve (its Ritz value mixes the
            // cluster's eigenvectors). The factor of the test that succeeds, A − sI with s just
            // below λ_min, drives a shift-invert run on (A − sI)⁻¹, where λ_min − s is small
            // against λ₂ − s and the cluster comes apart: λ_min = s + 1/ν_max (as the top end).
            let (lo, refined) = certify::step_outwards_by(w0, growth, |w, k| {
                let s = base * (1.0 - w);
                if s <= 0.0 {
                    return None;
                }
                let (f, max_b) = fam.test_factor(1.0, -s)?;
                let bound = bound_of(fam, &f, s, max_b, w);
                let refined = (k > 0)
                    .then(|| shift_invert(fam.pattern.n(), &f, Some(&est.bottom)).ok())
                    .flatten()
                    .filter(|r| r.theta > 0.0 && r.theta.is_finite());
                if let Some(r) = &refined {
                    steps += r.steps;
                }
                Some((bound, refined.map(|r| (s + 1.0 / r.theta, s, r.vector))))
            })
            .unwrap_or((0.0, None));
            let mut lo = lo.max(temple.unwrap_or(0.0));
            if let Some((value, s_ok, vector)) = refined {
                // The refined vector's inverse-Rayleigh value (Lemma 6, a new factor of A)
                // lowers the upper end; tests stepping down from the refined value — above
                // the test that succeeded — raise the lower end.
                if let Some(hi) = vector.and_then(|v| inverse_rayleigh_upper(fam, &v)) {
                    if hi < min_hi {
                        min_hi = hi;
                        refined_min = Some(hi);
                    }
                }
                // The refined value is accurate to the solves' rounding: the tests start closer
                // (a twentieth of the share) and step out ×2.
                let from = value.min(min_hi);
                let w_fine = (0.05 * share).max(2.0 * certify::U * scale).min(w0);
                if let Some(better) = certify::step_outwards_by(w_fine, 2.0, |w, _| {
                    let s = from * (1.0 - w);
                    if s <= s_ok {
                        return Some(0.0);
                    }
                    let (f, max_b) = fam.test_factor(1.0, -s)?;
                    Some(bound_of(fam, &f, s, max_b, w))
                }) {
                    lo = lo.max(better);
                }
            }
            lo
        }
    };
    Bottom {
        min_lo,
        min_hi,
        refined_min,
        steps,
    }
}
