//! Exact Coulomb friction: a semismooth Newton (primal–dual active set) method on the
//! Alart–Curnier functions, the reference of the frictional rows.
//!
//! Unknowns x = (u, λ_N, λ_T) (N + 2m). With `c = mean diag K` (force/length, so that
//! `σ_N = λ_N − c·g` and `σ_T = λ_T − c·Δs` add forces to forces):
//!
//! ```text
//!   open   (σ_N ≤ 0):                          λ_N = 0,            λ_T = 0
//!   stick  (σ_N > 0, |σ_T| ≤ μσ_N, μσ_N > 0):   c·(d_Nᵀu) = c·û,    c·(d_Tᵀu) = c·s_{k−1}
//!   slip   (otherwise):                         c·(d_Nᵀu) = c·û,    λ_T − μ·sign(σ_T)·λ_N = 0
//! ```
//!
//! beside `K u − Σ(λ_N d_N + λ_T d_T) = q`: a linear system per iteration for the statuses of
//! the current iterate (unsymmetric: sparse LU). The full step can cycle between status
//! patterns (a block pushed just short of sliding; an edge lifting under a large μ). Where an
//! increment meets a pattern it has met before: a contact that flips between open and stick
//! in a two-cycle (stick pulls it, open lets it penetrate) is tried in contact and slipping
//! against its slip; any other cycle divides c by ten (down to 10⁻⁶ of its start), which
//! weights the multipliers' own values over the gaps and slips in the status test. The law is piecewise linear in x, so the
//! iteration ends when the statuses of a new iterate are those it was solved with — or when the
//! law's residual (`law_residual`: the Alart–Curnier functions and equilibrium over the
//! largest force) is below 10⁻¹², which a grazing contact, flipping between open and stick on
//! rounding, meets while its statuses never settle: that iterate satisfies every condition
//! of [`super`]'s law exactly (λ_N > 0 on contact, g = 0;
//! open contacts have g ≥ 0; |λ_T| ≤ μλ_N; a slip opposes λ_T). The slip equation uses
//! λ_N where Alart–Curnier's uses σ_N; the two agree wherever g = 0, which the same
//! iteration's normal row imposes.

use super::{ContactStatus, FrictionProblem, FrictionSolution, Increment, MAX_NEWTON};
use crate::error::Result;
use crate::linalg::refine::inf_norm;
use crate::linalg::Factorization;
use crate::system::Stiffness;

/// A contact's status for one iteration: open, stick, or slip with the sign of σ_T.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Set {
    Open,
    Stick,
    Slip(bool),
}

fn sets(p: &FrictionProblem, x: &[f64], s_prev: &[f64], c_pen: f64) -> Vec<Set> {
    let (n, m) = (p.n(), p.m());
    let u = &x[..n];
    (0..m)
        .map(|c| {
            let sn = x[n + c] - c_pen * p.gap(c, u);
            if sn <= 0.0 {
                return Set::Open;
            }
            let st = x[n + m + c] - c_pen * (p.slip(c, u) - s_prev[c]);
            let b = p.mu * sn;
            if b > 0.0 && st.abs() <= b {
                Set::Stick
            } else {
                Set::Slip(st >= 0.0)
            }
        })
        .collect()
}

/// The relative residual `law_residual` accepts: an iterate whose statuses flip on rounding
/// (a grazing contact, g = 0 and λ_N = 0 both to rounding) meets the law to it.
pub const LAW_TOL: f64 = 1e-12;

/// `max |F|` over the Alart–Curnier functions of every contact at x — `λ_N − max(0, σ_N)`,
/// `λ_T − proj_[−μσ_N⁺, μσ_N⁺](σ_T)` — and the equilibrium residual, over the largest force
/// (`‖q‖∞`, `|λ|`): 0 exactly at a solution of the law, whatever the statuses' rounding.
fn law_residual(p: &FrictionProblem, k: usize, x: &[f64], s_prev: &[f64], c: f64) -> f64 {
    let (n, m) = (p.n(), p.m());
    let u = &x[..n];
    let (ln, lt) = (&x[n..n + m], &x[n + m..]);
    let mut worst = inf_norm(p.residual(k, u, ln, lt).into_iter());
    for i in 0..m {
        let sn = (ln[i] - c * p.gap(i, u)).max(0.0);
        let st = lt[i] - c * (p.slip(i, u) - s_prev[i]);
        let b = p.mu * sn;
        worst = worst
            .max((ln[i] - sn).abs())
            .max((lt[i] - st.clamp(-b, b)).abs());
    }
    let scale = inf_norm(p.loads[k].iter().chain(ln).chain(lt).copied());
    if scale == 0.0 {
        worst
    } else {
        worst / scale
    }
}

/// The linear system of one iteration for `sets` (module doc): matrix and right-hand side.
fn system(
    p: &FrictionProblem,
    k: usize,
    sets: &[Set],
    s_prev: &[f64],
    c_pen: f64,
) -> Result<(Stiffness, Vec<f64>)> {
    let (n, m) = (p.n(), p.m());
    let mut t = Vec::with_capacity(p.normal.k.nnz() + 8 * m);
    p.normal.k.for_each_entry(|i, j, v| t.push((i, j, v)));
    let mut b = vec![0.0; n + 2 * m];
    b[..n].copy_from_slice(&p.loads[k]);
    for c in 0..m {
        let (rn, rt) = (n + c, n + m + c);
        let normal = &p.normal.constraints[c];
        for &(d, a) in &normal.terms {
            t.push((d, rn, -a));
        }
        for &(d, a) in &p.tangents[c] {
            t.push((d, rt, -a));
        }
        match sets[c] {
            Set::Open => {
                t.push((rn, rn, 1.0));
                t.push((rt, rt, 1.0));
            }
            Set::Stick | Set::Slip(_) => {
                for &(d, a) in &normal.terms {
                    t.push((rn, d, c_pen * a));
                }
                b[rn] = c_pen * normal.limit;
                if let Set::Slip(positive) = sets[c] {
                    let sign = if positive { 1.0 } else { -1.0 };
                    t.push((rt, rt, 1.0));
                    t.push((rt, rn, -p.mu * sign));
                } else {
                    for &(d, a) in &p.tangents[c] {
                        t.push((rt, d, c_pen * a));
                    }
                    b[rt] = c_pen * s_prev[c];
                }
            }
        }
    }
    Ok((Stiffness::from_triplets(n + 2 * m, &t)?, b))
}

/// Every increment of `p` by the semismooth Newton method (module doc), from `start` (its u,
/// λ_N, λ_T and slips) or the unloaded state.
pub(super) fn solve(p: &FrictionProblem, start: Option<&Increment>) -> Result<FrictionSolution> {
    let (n, m) = (p.n(), p.m());
    let c_mean = (0..n).map(|i| p.normal.k.diag(i)).sum::<f64>() / n as f64;
    let mut x = vec![0.0; n + 2 * m];
    let mut s_prev = vec![0.0; m];
    if let Some(s) = start {
        x[..n].copy_from_slice(&s.u);
        x[n..n + m].copy_from_slice(&s.lam_n);
        x[n + m..].copy_from_slice(&s.lam_t);
        for (c, sp) in s_prev.iter_mut().enumerate() {
            *sp = p.slip(c, &s.u);
        }
    }
    let mut out = FrictionSolution::start("lagrange", vec![0.0; m]);
    // Whether an increment had a contact in stick: its system is the one kept.
    let mut stuck = false;
    for k in 0..p.loads.len() {
        let mut used: Option<Vec<Set>> = None;
        let mut iters = 0;
        let mut converged = false;
        let mut last = None;
        // The statuses met in this increment: a pattern met again (not the last one) is a
        // cycle, broken by a tenfold smaller c (module doc).
        let mut c_pen = c_mean;
        let mut seen: Vec<Vec<Set>> = Vec::new();
        loop {
            let now = sets(p, &x, &s_prev, c_pen);
            if used.as_ref() == Some(&now)
                || (used.is_some() && law_residual(p, k, &x, &s_prev, c_mean) <= LAW_TOL)
            {
                converged = true;
                break;
            }
            if iters == MAX_NEWTON {
                break;
            }
            let mut now = now;
            if seen.contains(&now) {
                // A contact flipping open ↔ stick in a two-cycle: neither holds (stick pulls,
                // open penetrates); try it in contact and slipping, against its slip. Any
                // other cycle: a tenfold smaller c.
                let prev = seen.last().cloned().unwrap_or_default();
                let two_cycle = seen.len() >= 2 && seen[seen.len() - 2] == now;
                let flips: Vec<usize> = (0..m)
                    .filter(|&i| {
                        two_cycle
                            && matches!(
                                (now[i], prev[i]),
                                (Set::Open, Set::Stick) | (Set::Stick, Set::Open)
                            )
                    })
                    .collect();
                for &i in &flips {
                    let st = x[n + m + i] - c_pen * (p.slip(i, &x[..n]) - s_prev[i]);
                    now[i] = Set::Slip(st >= 0.0);
                }
                if flips.is_empty() && c_pen > 1e-6 * c_mean {
                    c_pen *= 0.1;
                    seen.clear();
                }
            }
            seen.push(now.clone());
            let (a, b) = system(p, k, &now, &s_prev, c_pen)?;
            let fac = Factorization::new(&a, false)?;
            out.factorizations += 1;
            x = fac.solve(&b);
            iters += 1;
            used = Some(now);
            last = Some(a);
        }
        if !converged {
            out.converged = false;
            out.warnings.push(format!(
                "friction lagrange: increment {k} did not converge in {iters} iterations"
            ));
        }
        let final_sets = used.unwrap_or_else(|| sets(p, &x, &s_prev, c_mean));
        let u = x[..n].to_vec();
        for (c, s) in s_prev.iter_mut().enumerate() {
            *s = p.slip(c, &u);
        }
        let sticks = final_sets.contains(&Set::Stick);
        if sticks || !stuck {
            out.tangent = last;
            out.tangent_increment = Some(k);
        }
        stuck |= sticks;
        out.increments.push(Increment {
            status: final_sets
                .iter()
                .map(|s| match s {
                    Set::Open => ContactStatus::Open,
                    Set::Stick => ContactStatus::Stick,
                    Set::Slip(_) => ContactStatus::Slip,
                })
                .collect(),
            lam_n: x[n..n + m].to_vec(),
            lam_t: x[n + m..].to_vec(),
            u,
            eps_t: vec![0.0; m],
            newton_iters: iters,
            converged,
        });
    }
    Ok(out)
}
