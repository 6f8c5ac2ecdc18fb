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
//! the current iterate (unsymmetric: sparse LU). The law is piecewise linear in x, so the
//! iteration ends when the statuses of a new iterate are those it was solved with: that
//! iterate satisfies every condition of [`super`]'s law exactly (λ_N > 0 on contact, g = 0;
//! open contacts have g ≥ 0; |λ_T| ≤ μλ_N; a slip opposes λ_T). The slip equation uses
//! λ_N where Alart–Curnier's uses σ_N; the two agree wherever g = 0, which the same
//! iteration's normal row imposes.

use super::{ContactStatus, FrictionProblem, FrictionSolution, Increment, MAX_NEWTON};
use crate::error::Result;
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

/// Every increment of `p` by the semismooth Newton method (module doc).
pub(super) fn solve(p: &FrictionProblem) -> Result<FrictionSolution> {
    let (n, m) = (p.n(), p.m());
    let c_pen = (0..n).map(|i| p.normal.k.diag(i)).sum::<f64>() / n as f64;
    let mut x = vec![0.0; n + 2 * m];
    let mut s_prev = vec![0.0; m];
    let mut out = FrictionSolution {
        method: "lagrange",
        eps_n: vec![0.0; m],
        increments: Vec::with_capacity(p.loads.len()),
        factorizations: 0,
        converged: true,
        tangent: None,
        warnings: Vec::new(),
    };
    // Whether an increment had a contact in stick: its system is the one kept.
    let mut stuck = false;
    for k in 0..p.loads.len() {
        let mut used: Option<Vec<Set>> = None;
        let mut iters = 0;
        let mut converged = false;
        let mut last = None;
        loop {
            let now = sets(p, &x, &s_prev, c_pen);
            if used.as_ref() == Some(&now) {
                converged = true;
                break;
            }
            if iters == MAX_NEWTON {
                break;
            }
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
        let final_sets = used.unwrap_or_else(|| sets(p, &x, &s_prev, c_pen));
        let u = x[..n].to_vec();
        for (c, s) in s_prev.iter_mut().enumerate() {
            *s = p.slip(c, &u);
        }
        let sticks = final_sets.contains(&Set::Stick);
        if sticks || !stuck {
            out.tangent = last;
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
