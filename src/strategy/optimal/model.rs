//! The smoothed, barrier-penalized objective Φ over a fixed penalized set and its BFGS
//! minimisation ([`super`] module docs: objective, constraints, continuation).

use super::spectrum::{Linearization, Spectrum};
use super::MAX_INNER;
use crate::error::Result;
use crate::system::{ConstraintKind, Problem};
use faer::Mat;

/// The smooth model over a fixed penalized set.
pub(super) struct Model<'a> {
    pub p: &'a Problem,
    pub spectrum: &'a Spectrum,
    /// Penalized constraint indices (the variables).
    pub set: Vec<usize>,
    pub delta: f64,
}

/// One evaluation: Φ and its gradient in x = ln ε.
pub(super) struct Eval {
    pub phi: f64,
    pub grad: Vec<f64>,
}

/// `F = t⁻¹ ln Σ_{top} λ_k^t + t⁻¹ ln Σ_{bottom} λ_k^(−t)` and, per penalized DOF j,
/// `∂F/∂ε_j = Σ_top w⁺_k v_k[d_j]²/λ_k − Σ_bottom w⁻_k v_k[d_j]²/λ_k` (softmax weights).
fn smoothed_log_cond(lin: &Linearization, t: f64, set_len: usize) -> (f64, Vec<f64>) {
    let ll: Vec<f64> = lin.pairs.iter().map(|p| p.lambda.ln()).collect();
    let hi = ll[lin.top.clone()]
        .iter()
        .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
    let lo = ll[lin.bottom.clone()]
        .iter()
        .fold(f64::INFINITY, |a, &b| a.min(b));
    let wp: Vec<f64> = lin.top.clone().map(|k| (t * (ll[k] - hi)).exp()).collect();
    let wm: Vec<f64> = lin
        .bottom
        .clone()
        .map(|k| (-t * (ll[k] - lo)).exp())
        .collect();
    let (sp, sm) = (wp.iter().sum::<f64>(), wm.iter().sum::<f64>());
    let f = hi + sp.ln() / t - lo + sm.ln() / t;
    let mut df = vec![0.0; set_len];
    for (k, w) in lin.top.clone().zip(&wp) {
        let pair = &lin.pairs[k];
        for (d, a) in df.iter_mut().zip(&pair.at) {
            *d += w / sp * a * a / pair.lambda;
        }
    }
    for (k, w) in lin.bottom.clone().zip(&wm) {
        let pair = &lin.pairs[k];
        for (d, a) in df.iter_mut().zip(&pair.at) {
            *d -= w / sm * a * a / pair.lambda;
        }
    }
    (f, df)
}

impl Model<'_> {
    /// Φ = F_t + μ·barrier at x, or None if x is infeasible (or A is not SPD).
    pub fn eval(&self, x: &[f64], t: f64, mu: f64) -> Result<Option<Eval>> {
        let p = self.p;
        let eps: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        let dofs: Vec<usize> = self.set.iter().map(|&c| p.constraints[c].dof).collect();
        let Some(lin) = self.spectrum.linearize(&dofs, &eps)? else {
            return Ok(None);
        };
        let mut rhs = p.q.clone();
        for (&c, &e) in self.set.iter().zip(&eps) {
            let con = p.constraints[c];
            rhs[con.dof] += e * con.limit;
        }
        let u = lin.solve(rhs);
        let gaps: Vec<f64> = p
            .constraints
            .iter()
            .map(|con| u[con.dof] - con.limit)
            .collect();
        // Barrier terms h(g_i) > 0 with dh/dg_i.
        let mut terms: Vec<(usize, f64, f64)> = Vec::new();
        for (i, con) in p.constraints.iter().enumerate() {
            let g = gaps[i];
            match con.kind {
                ConstraintKind::Bilateral => {
                    terms.push((i, self.delta - g, -1.0));
                    terms.push((i, self.delta + g, 1.0));
                }
                kind => {
                    let s = if kind == ConstraintKind::Upper {
                        1.0
                    } else {
                        -1.0
                    };
                    terms.push((i, self.delta - s * g, -s));
                    if self.set.contains(&i) {
                        terms.push((i, s * g, s));
                    }
                }
            }
        }
        if !terms.iter().all(|&(_, h, _)| h > 0.0) {
            return Ok(None);
        }
        let (f, df) = smoothed_log_cond(&lin, t, self.set.len());
        let barrier: f64 = terms.iter().map(|&(_, h, _)| -(h / self.delta).ln()).sum();
        let phi = f + mu * barrier;
        // dΦ/dg_i from the barrier, and its adjoint z = A⁻¹ Σ_i (dΦ/dg_i) e_{d_i}:
        // ∂g_i/∂ε_j = −(A⁻¹)_{d_i d_j} g_j, so the barrier's ∂/∂ε_j is −g_j z[d_j].
        let mut w = vec![0.0; p.n()];
        for &(i, h, dh) in &terms {
            w[p.constraints[i].dof] += -mu * dh / h;
        }
        let z = lin.solve(w);
        let grad = self
            .set
            .iter()
            .zip(&eps)
            .zip(&df)
            .map(|((&j, &e), &dfj)| e * (dfj - gaps[j] * z[p.constraints[j].dof]))
            .collect();
        Ok(Some(Eval { phi, grad }))
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// BFGS on Φ(·; t, μ) from a strictly feasible x; returns the final x and ‖∇Φ‖∞.
pub(super) fn bfgs(
    model: &Model,
    x0: Vec<f64>,
    t: f64,
    mu: f64,
    evals: &mut usize,
) -> Result<(Vec<f64>, f64)> {
    let d = x0.len();
    let mut x = x0;
    *evals += 1;
    let Some(mut cur) = model.eval(&x, t, mu)? else {
        return Ok((x, f64::NAN));
    };
    let mut h = Mat::<f64>::identity(d, d);
    for _ in 0..MAX_INNER {
        let gn = inf_norm(&cur.grad);
        if gn < 1e-10 {
            break;
        }
        let mut dir: Vec<f64> = (0..d)
            .map(|i| -(0..d).map(|j| h[(i, j)] * cur.grad[j]).sum::<f64>())
            .collect();
        let mut slope: f64 = dir.iter().zip(&cur.grad).map(|(a, b)| a * b).sum();
        if slope.is_nan() || slope >= 0.0 {
            h = Mat::identity(d, d);
            dir = cur.grad.iter().map(|g| -g).collect();
            slope = -cur.grad.iter().map(|g| g * g).sum::<f64>();
        }
        let cap = inf_norm(&dir);
        let mut step = if cap > 2.0 { 2.0 / cap } else { 1.0 };
        let mut accepted = None;
        for _ in 0..40 {
            let xt: Vec<f64> = x.iter().zip(&dir).map(|(a, b)| a + step * b).collect();
            *evals += 1;
            if let Some(e) = model.eval(&xt, t, mu)? {
                if e.phi <= cur.phi + 1e-4 * step * slope {
                    accepted = Some((xt, e));
                    break;
                }
            }
            step *= 0.5;
        }
        let Some((xn, en)) = accepted else { break };
        let sv: Vec<f64> = xn.iter().zip(&x).map(|(a, b)| a - b).collect();
        let yv: Vec<f64> = en.grad.iter().zip(&cur.grad).map(|(a, b)| a - b).collect();
        let sy: f64 = sv.iter().zip(&yv).map(|(a, b)| a * b).sum();
        let done = (cur.phi - en.phi).abs() <= 1e-15 * cur.phi.abs().max(1.0);
        x = xn;
        cur = en;
        if sy > 1e-300 {
            // H ← (I − ρ s yᵀ) H (I − ρ y sᵀ) + ρ s sᵀ.
            let rho = 1.0 / sy;
            let hy: Vec<f64> = (0..d)
                .map(|i| (0..d).map(|j| h[(i, j)] * yv[j]).sum())
                .collect();
            let yhy: f64 = yv.iter().zip(&hy).map(|(a, b)| a * b).sum();
            h = Mat::from_fn(d, d, |i, j| {
                h[(i, j)] - rho * (hy[i] * sv[j] + sv[i] * hy[j])
                    + (rho * rho * yhy + rho) * sv[i] * sv[j]
            });
        }
        if done {
            break;
        }
    }
    Ok((x, inf_norm(&cur.grad)))
}
