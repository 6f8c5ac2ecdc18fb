//! Penalty and augmented-Lagrangian friction: Newton on u with a return mapping per contact.
//!
//! Per contact, at u (g = d_Nᵀu − û, s = d_Tᵀu), with shifts λ̄ (0 for a penalty, the
//! multipliers for `augmented`) and a reference slip s_ref (the plastic slip s_p for a
//! penalty, the slip at the end of the previous increment for `augmented`):
//!
//! ```text
//!   λ_N = max(0, λ̄_N − ε_N g)                       bound b = μ λ_N   (Tresca: μ λ̂_N)
//!   ε_T rule:  λ_T = clamp(λ̄_T − ε_T (s − s_ref), −b, b)
//!   δ_T rule:  λ_T = −b · clamp((s − s_ref)/δ_T, −1, 1)   (ε_T = b/δ_T)
//! ```
//!
//! stick where the clamp is inactive, slip where it is active. Newton solves
//! `R(u) = K u − q − Σ (λ_N d_N + λ_T d_T) = 0` with the consistent tangent
//! `J = K − Σ (d_N ∂λ_Nᵀ + d_T ∂λ_Tᵀ)`: a slipping contact under Coulomb adds
//! `−d_T (±μ ∂λ_N)ᵀ = ±μ ε_N d_T d_Nᵀ`, the unsymmetric part. R is piecewise linear (ε_T
//! rule) or piecewise bilinear (δ_T rule) in u, so Newton ends once the statuses are right.
//! An increment converges, after at least one Newton step, when `‖R‖∞ ≤ 10⁻⁸·F`, F the
//! largest force in play (`‖q‖∞`, `‖Ku‖∞`, `|λ_N|`, `|λ_T|`): a test on the physics' scale, not
//! on ‖J‖‖u‖, which a stiff penalty inflates — a penalty so stiff that its rounding
//! (≈ ε_mach·ε·|s|, ε·|s| ≫ λ) exceeds 10⁻⁸·F cannot meet it and is reported unconverged
//! rather than accepted. Then the plastic slip becomes
//! `s_p = s + λ_T/ε_T` (s where ε_T = 0).
//!
//! With Tresca's bound b = μλ̂_N fixed, R is the gradient of the convex energy
//! `½uᵀKu − qᵀu + Σ_c [max(0, λ̄_N − ε_N g)²/(2ε_N) + ψ_T]`, `ψ_T = H_b(λ̄_T − ε_T Δs)/ε_T`
//! (Huber: `H_b(t) = t²/2` for |t| ≤ b, `b|t| − b²/2` beyond) or `b·δ_T·H_1(Δs/δ_T)` for the
//! δ_T rule: Newton with an exact line search along its direction always converges. Under
//! Coulomb's law no such energy exists: an increment tries the consistent Newton first and
//! falls back on lagged Tresca passes (`increment` in the source).
//!
//! `augmented` repeats the Newton solve with λ̄ ← λ until no multiplier moves more than
//! `tol·ε` (λ_N by `tol·ε_N`, λ_T by `tol·ε_T`), at most [`super::MAX_UZAWA`] times; at that
//! fixed point the Coulomb law holds exactly.

use super::{ContactStatus, FrictionProblem, FrictionSolution, Increment, Law, MAX_NEWTON};
use crate::error::Result;
use crate::linalg::refine::inf_norm;
use crate::linalg::Factorization;
use crate::system::Stiffness;

/// The tangential part of a penalty method.
#[derive(Clone, Debug)]
pub(super) enum Tangential {
    /// ε_T per contact.
    Penalty(Vec<f64>, Law),
    /// An allowed elastic slip δ_T.
    Delta(f64, Law),
    /// Augmented Lagrangian: ε_T and the tolerance (Coulomb).
    Augmented(f64, f64),
}

impl Tangential {
    pub(super) fn law(&self) -> Law {
        match self {
            Tangential::Penalty(_, l) | Tangential::Delta(_, l) => *l,
            Tangential::Augmented(..) => Law::Coulomb,
        }
    }
}

/// What the Newton iterations of one increment hold fixed.
struct Fixed<'a> {
    eps_n: &'a [f64],
    tangential: &'a Tangential,
    /// λ̄_N, λ̄_T (zeros for a penalty).
    shift_n: Vec<f64>,
    shift_t: Vec<f64>,
    /// s_ref per contact.
    s_ref: Vec<f64>,
    /// λ̂_N (Tresca's bound over μ).
    hat_n: Vec<f64>,
    /// The bound this Newton solve meets (a Coulomb method's lagged passes use Tresca's).
    law: Law,
}

/// The contact forces at u, their derivatives as coefficients on (d_N, d_T), statuses, ε_T.
struct Forces {
    lam_n: Vec<f64>,
    lam_t: Vec<f64>,
    dn: Vec<(f64, f64)>,
    dt: Vec<(f64, f64)>,
    status: Vec<ContactStatus>,
    eps_t: Vec<f64>,
}

fn forces(p: &FrictionProblem, u: &[f64], f: &Fixed) -> Forces {
    let m = p.m();
    let mut out = Forces {
        lam_n: vec![0.0; m],
        lam_t: vec![0.0; m],
        dn: vec![(0.0, 0.0); m],
        dt: vec![(0.0, 0.0); m],
        status: vec![ContactStatus::Open; m],
        eps_t: vec![0.0; m],
    };
    for c in 0..m {
        let (g, s) = (p.gap(c, u), p.slip(c, u));
        let en = f.eps_n[c];
        let sn = f.shift_n[c] - en * g;
        if sn > 0.0 {
            out.lam_n[c] = sn;
            out.dn[c] = (-en, 0.0);
        }
        // Coulomb's bound acts in contact; Tresca's wherever it is > 0 (a given bound: the
        // problem is then a convex minimization, see the module doc).
        let (b, db) = match f.law {
            Law::Coulomb if sn > 0.0 => (p.mu * sn, (-p.mu * en, 0.0)),
            Law::Tresca if f.hat_n[c] > 0.0 => (p.mu * f.hat_n[c], (0.0, 0.0)),
            _ => continue,
        };
        let ds = s - f.s_ref[c];
        let (lam_t, dt, stick, et) = match f.tangential {
            Tangential::Penalty(e, _) => clamp_rule(f.shift_t[c], e[c], ds, b, db),
            Tangential::Augmented(e, _) => clamp_rule(f.shift_t[c], *e, ds, b, db),
            Tangential::Delta(delta, _) => {
                let phi = ds / delta;
                if phi.abs() <= 1.0 {
                    let dt = (-phi * db.0, -phi * db.1 - b / delta);
                    (-b * phi, dt, true, b / delta)
                } else {
                    let sg = phi.signum();
                    (-b * sg, (-sg * db.0, -sg * db.1), false, b / delta)
                }
            }
        };
        out.lam_t[c] = lam_t;
        out.dt[c] = dt;
        out.eps_t[c] = et;
        out.status[c] = if sn <= 0.0 {
            ContactStatus::Open
        } else if stick {
            ContactStatus::Stick
        } else {
            ContactStatus::Slip
        };
    }
    out
}

/// `λ_T = clamp(λ̄_T − ε_T Δs, −b, b)` with its derivative, stick flag and ε_T.
fn clamp_rule(shift: f64, e: f64, ds: f64, b: f64, db: (f64, f64)) -> (f64, (f64, f64), bool, f64) {
    let trial = shift - e * ds;
    if trial.abs() <= b {
        (trial, (0.0, -e), true, e)
    } else {
        let sg = trial.signum();
        (sg * b, (sg * db.0, sg * db.1), false, e)
    }
}

/// `J = K − Σ (d_N ∂λ_Nᵀ + d_T ∂λ_Tᵀ)` (module doc).
fn tangent(p: &FrictionProblem, fr: &Forces) -> Stiffness {
    let mut adds = Vec::new();
    for c in 0..p.m() {
        let rows = [&p.normal.constraints[c].terms, &p.tangents[c]];
        for (r, d) in [fr.dn[c], fr.dt[c]].into_iter().enumerate() {
            for (col_row, coef) in [(rows[0], d.0), (rows[1], d.1)] {
                if coef == 0.0 {
                    continue;
                }
                for &(i, a) in rows[r] {
                    for &(j, b) in col_row.iter() {
                        adds.push((i, j, -a * b * coef));
                    }
                }
            }
        }
    }
    p.normal.k.with_entries_added(&adds)
}

/// The end of a Newton solve: forces, iterations, converged, factorizations, last tangent.
struct NewtonEnd {
    forces: Forces,
    iters: usize,
    converged: bool,
    solves: usize,
    tangent: Stiffness,
}

/// The residual an increment must reach, relative to its largest force (module doc).
pub const RESIDUAL_TOL: f64 = 1e-8;

/// Newton on u for increment k, at most `max_iters` steps, each globalized by
/// [`line_search`]; converged after at least one step when `‖R‖∞ ≤ RESIDUAL_TOL·F` (module
/// doc).
fn newton(
    p: &FrictionProblem,
    k: usize,
    u: &mut [f64],
    f: &Fixed,
    max_iters: usize,
) -> Result<NewtonEnd> {
    let qnorm = inf_norm(p.loads[k].iter().copied());
    let mut solves = 0;
    let mut it = 0;
    loop {
        let fr = forces(p, u, f);
        let r = p.residual(k, u, &fr.lam_n, &fr.lam_t);
        let j = tangent(p, &fr);
        let forces_scale = qnorm
            .max(inf_norm(p.normal.k.matvec(u).iter().copied()))
            .max(inf_norm(fr.lam_n.iter().copied()))
            .max(inf_norm(fr.lam_t.iter().copied()));
        let converged = it > 0 && inf_norm(r.iter().copied()) <= RESIDUAL_TOL * forces_scale;
        if converged || it == max_iters {
            return Ok(NewtonEnd {
                forces: fr,
                iters: it,
                converged,
                solves,
                tangent: j,
            });
        }
        let fac = Factorization::new(&j, j.is_symmetric())?;
        solves += 1;
        it += 1;
        let mut du: Vec<f64> = r.iter().map(|v| -v).collect();
        fac.solve_vec_in_place(&mut du);
        line_search(p, k, u, &du, f, &r);
    }
}

/// One increment under `f`'s law. Tresca: [`newton`]. Coulomb: the consistent Newton first
/// ([`COULOMB_TRY`] steps); where it has not converged (a full step can cycle between stick
/// and slip), lagged passes — Tresca's problem with the bound μλ̂_N, λ̂_N ← λ_N, a convex
/// minimization each (see the module doc), until λ_N moves by at most 10⁻¹²·max λ_N (at most
/// [`super::MAX_UZAWA`] passes) — then the consistent Newton again from there.
fn increment(p: &FrictionProblem, k: usize, u: &mut [f64], f: &Fixed) -> Result<NewtonEnd> {
    let first = newton(
        p,
        k,
        u,
        f,
        if f.law == Law::Coulomb {
            COULOMB_TRY
        } else {
            MAX_NEWTON
        },
    )?;
    if first.converged || f.law == Law::Tresca {
        return Ok(first);
    }
    let (mut iters, mut solves) = (first.iters, first.solves);
    let mut lagged = Fixed {
        law: Law::Tresca,
        hat_n: first.forces.lam_n.clone(),
        shift_n: f.shift_n.clone(),
        shift_t: f.shift_t.clone(),
        s_ref: f.s_ref.clone(),
        ..*f
    };
    for _ in 0..super::MAX_UZAWA {
        let pass = newton(p, k, u, &lagged, MAX_NEWTON)?;
        iters += pass.iters;
        solves += pass.solves;
        let top = inf_norm(pass.forces.lam_n.iter().copied());
        let moved = pass
            .forces
            .lam_n
            .iter()
            .zip(&lagged.hat_n)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        lagged.hat_n.clone_from(&pass.forces.lam_n);
        if !pass.converged || moved <= 1e-12 * top {
            break;
        }
    }
    let mut last = newton(p, k, u, f, COULOMB_TRY)?;
    last.iters += iters;
    last.solves += solves;
    Ok(last)
}

/// Consistent-Newton steps a Coulomb increment tries before (and after) the lagged passes.
const COULOMB_TRY: usize = 12;

/// Steps `u ← u + α·du`. Tresca (a convex minimization, R the energy's gradient): the full
/// step where the energy still descends at α = 1 (`R(u + du)ᵀdu ≤ 0`), else the minimizer
/// along the line by bisection on the slope `R(u + α·du)ᵀdu`, which grows with α — a test on
/// slopes, not on energy values, whose differences near the solution fall below their
/// rounding. Coulomb: the first α of 1, ½, ¼, … (at most [`HALVINGS`]) that passes Armijo's
/// test (factor 10⁻⁴) on ½‖R‖² (the semismooth Newton direction descends it where R is
/// differentiable); the full step if none does.
fn line_search(p: &FrictionProblem, k: usize, u: &mut [f64], du: &[f64], f: &Fixed, r: &[f64]) {
    let at = |alpha: f64| -> (Vec<f64>, Vec<f64>) {
        let v: Vec<f64> = u.iter().zip(du).map(|(x, d)| x + alpha * d).collect();
        let fr = forces(p, &v, f);
        let r = p.residual(k, &v, &fr.lam_n, &fr.lam_t);
        (v, r)
    };
    let slope = |r: &[f64]| r.iter().zip(du).map(|(a, b)| a * b).sum::<f64>();
    let alpha = match f.law {
        Law::Tresca => {
            if slope(&at(1.0).1) <= 0.0 {
                1.0
            } else {
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..HALVINGS {
                    let mid = 0.5 * (lo + hi);
                    if slope(&at(mid).1) <= 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                hi
            }
        }
        Law::Coulomb => {
            let m0 = norm2(r).powi(2);
            let mut alpha = 1.0;
            for _ in 0..=HALVINGS {
                if norm2(&at(alpha).1).powi(2) <= (1.0 - 2e-4 * alpha) * m0 {
                    break;
                }
                alpha /= 2.0;
            }
            if alpha < 0.5f64.powi(HALVINGS as i32) {
                1.0
            } else {
                alpha
            }
        }
    };
    for (ui, d) in u.iter_mut().zip(du) {
        *ui += alpha * d;
    }
}

/// The slip history a contact carries into the next increment: augmented keeps the slip s
/// itself, a penalty the plastic slip `s + λ_T/ε_T` (s where ε_T = 0).
fn plastic_slip(s: f64, lam_t: f64, eps_t: f64, t: &Tangential) -> f64 {
    match t {
        Tangential::Augmented(..) => s,
        _ if eps_t > 0.0 => s + lam_t / eps_t,
        _ => s,
    }
}

/// Halvings of the line search's step.
const HALVINGS: usize = 30;

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Every increment of `p` by a penalty (`eps_n` per contact, `t`) or `augmented`, from
/// `start` (its u, λ_N, λ_T and slip history) or the unloaded state.
pub(super) fn solve(
    p: &FrictionProblem,
    eps_n: Vec<f64>,
    t: Tangential,
    start: Option<&Increment>,
) -> Result<FrictionSolution> {
    let (n, m) = (p.n(), p.m());
    let mut u = vec![0.0; n];
    let mut s_hist = vec![0.0; m];
    let (mut lam_n, mut lam_t) = (vec![0.0; m], vec![0.0; m]);
    if let Some(s) = start {
        u.clone_from(&s.u);
        lam_n.clone_from(&s.lam_n);
        lam_t.clone_from(&s.lam_t);
        for (c, h) in s_hist.iter_mut().enumerate() {
            *h = plastic_slip(p.slip(c, &u), s.lam_t[c], s.eps_t[c], &t);
        }
    }
    let method = if matches!(t, Tangential::Augmented(..)) {
        "augmented"
    } else {
        "penalty"
    };
    let mut out = FrictionSolution::start(method, eps_n.clone());
    // Whether an increment had a contact in stick: its system is the one kept.
    let mut stuck = false;
    for k in 0..p.loads.len() {
        let mut fixed = Fixed {
            eps_n: &eps_n,
            tangential: &t,
            shift_n: vec![0.0; m],
            shift_t: vec![0.0; m],
            s_ref: s_hist.clone(),
            hat_n: lam_n.clone(),
            law: t.law(),
        };
        let (fr, iters, converged, j) = match &t {
            Tangential::Augmented(et, tol) => {
                fixed.shift_n = lam_n.clone();
                fixed.shift_t = lam_t.clone();
                uzawa(
                    p,
                    k,
                    &mut u,
                    &mut fixed,
                    (*et, *tol),
                    &mut out.factorizations,
                )?
            }
            _ => {
                let end = increment(p, k, &mut u, &fixed)?;
                out.factorizations += end.solves;
                (end.forces, end.iters, end.converged, Some(end.tangent))
            }
        };
        if !converged {
            out.converged = false;
            out.warnings.push(format!(
                "friction {}: increment {k} did not converge in {iters} iterations",
                out.method
            ));
        }
        for (c, h) in s_hist.iter_mut().enumerate() {
            *h = plastic_slip(p.slip(c, &u), fr.lam_t[c], fr.eps_t[c], &t);
        }
        lam_n.clone_from(&fr.lam_n);
        lam_t.clone_from(&fr.lam_t);
        let sticks = fr.status.contains(&ContactStatus::Stick);
        if sticks || !stuck {
            out.tangent = j;
            out.tangent_increment = Some(k);
        }
        stuck |= sticks;
        out.increments.push(Increment {
            u: u.clone(),
            lam_n: fr.lam_n,
            lam_t: fr.lam_t,
            status: fr.status,
            eps_t: fr.eps_t,
            newton_iters: iters,
            converged,
        });
    }
    Ok(out)
}

/// Uzawa updates λ̄ ← λ around [`increment`] until no multiplier moves more than tol·ε.
fn uzawa(
    p: &FrictionProblem,
    k: usize,
    u: &mut [f64],
    f: &mut Fixed,
    (eps_t, tol): (f64, f64),
    factorizations: &mut usize,
) -> Result<(Forces, usize, bool, Option<Stiffness>)> {
    let mut iters = 0;
    let mut end = increment(p, k, u, f)?;
    for pass in 1.. {
        iters += end.iters;
        *factorizations += end.solves;
        let moved = (0..p.m())
            .map(|c| {
                let dn = (end.forces.lam_n[c] - f.shift_n[c]).abs() / f.eps_n[c];
                let dt = (end.forces.lam_t[c] - f.shift_t[c]).abs() / eps_t;
                dn.max(dt)
            })
            .fold(0.0f64, f64::max);
        let done = moved <= tol;
        if !end.converged || done || pass == super::MAX_UZAWA {
            return Ok((end.forces, iters, end.converged && done, Some(end.tangent)));
        }
        f.shift_n.clone_from(&end.forces.lam_n);
        f.shift_t.clone_from(&end.forces.lam_t);
        end = increment(p, k, u, f)?;
    }
    unreachable!("the passes return at MAX_UZAWA")
}
