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

/// `F = t⁻¹ ln Σ_{top} λ_k^t + t⁻¹ ln Σ_{bottom} λ_k^(−t)` and, per penalized row j,
/// `∂F/∂ε_j = Σ_top w⁺_k (d_jᵀv_k)²/λ_k − Σ_bottom w⁻_k (d_jᵀv_k)²/λ_k` (softmax weights;
/// ∂λ_k/∂ε_j = (d_jᵀv_k)² since ∂A/∂ε_j = d_j d_jᵀ).
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
        let Some(lin) = self.spectrum.linearize(p, &self.set, &eps)? else {
            return Ok(None);
        };
        let mut rhs = p.q.clone();
        for (&c, &e) in self.set.iter().zip(&eps) {
            let con = &p.constraints[c];
            con.scatter(&mut rhs, e * con.limit);
        }
        let u = lin.solve(rhs);
        let gaps: Vec<f64> = p.constraints.iter().map(|con| con.gap(&u)).collect();
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
        // dΦ/dg_i from the barrier, and its adjoint z = A⁻¹ Σ_i (dΦ/dg_i) d_i:
        // ∂g_i/∂ε_j = −d_iᵀA⁻¹d_j g_j, so the barrier's ∂/∂ε_j is −g_j d_jᵀz.
        let mut w = vec![0.0; p.n()];
        for &(i, h, dh) in &terms {
            p.constraints[i].scatter(&mut w, -mu * dh / h);
        }
        let z = lin.solve(w);
        let grad = self
            .set
            .iter()
            .zip(&eps)
            .zip(&df)
            .map(|((&j, &e), &dfj)| e * (dfj - gaps[j] * p.constraints[j].value(&z)))
            .collect();
        Ok(Some(Eval { phi, grad }))
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `M v` for the small dense matrices of the direction rules (d ≤ [`super::MAX_M`]).
fn mat_vec(m: &Mat<f64>, v: &[f64]) -> Vec<f64> {
    (0..m.nrows())
        .map(|i| (0..v.len()).map(|j| m[(i, j)] * v[j]).sum())
        .collect()
}

/// Armijo backtracking along `dir` from x (slope = ∇Φ·dir < 0), the first trial step capped
/// at 2 in ln ε; infeasible trial points are rejected like rising ones. None after 40 halvings.
fn line_search(
    model: &Model,
    (x, cur): (&[f64], &Eval),
    dir: &[f64],
    slope: f64,
    (t, mu): (f64, f64),
    evals: &mut usize,
) -> Result<Option<(Vec<f64>, Eval)>> {
    let cap = inf_norm(dir);
    let mut step = if cap > 2.0 { 2.0 / cap } else { 1.0 };
    for _ in 0..40 {
        let xt: Vec<f64> = x.iter().zip(dir).map(|(a, b)| a + step * b).collect();
        *evals += 1;
        if let Some(e) = model.eval(&xt, t, mu)? {
            if e.phi <= cur.phi + 1e-4 * step * slope {
                return Ok(Some((xt, e)));
            }
        }
        step *= 0.5;
    }
    Ok(None)
}

/// A rule for the search direction of [`descend`].
pub(super) trait Direction {
    /// The direction at x (Φ and ∇Φ in `cur`; `last` = the previous step s and gradient
    /// change y) and whether to stop after the step along it; None to stop now.
    fn next(
        &mut self,
        model: &Model,
        at: (&[f64], &Eval),
        last: Option<(&[f64], &[f64])>,
        tm: (f64, f64),
        evals: &mut usize,
    ) -> Result<Option<(Vec<f64>, bool)>>;
}

/// Minimises Φ(·; t, μ) from a strictly feasible x by `rule`'s directions and
/// [`line_search`]'s steps, at most [`MAX_INNER`] of them; stops when ‖∇Φ‖∞ < 10⁻¹⁰, a step
/// leaves Φ unchanged (relative 10⁻¹⁵), or the rule says so. Returns the final x and ‖∇Φ‖∞.
pub(super) fn descend(
    model: &Model,
    x0: Vec<f64>,
    (t, mu): (f64, f64),
    rule: &mut impl Direction,
    evals: &mut usize,
) -> Result<(Vec<f64>, f64)> {
    let mut x = x0;
    *evals += 1;
    let Some(mut cur) = model.eval(&x, t, mu)? else {
        return Ok((x, f64::NAN));
    };
    let mut last: Option<(Vec<f64>, Vec<f64>)> = None;
    for _ in 0..MAX_INNER {
        if inf_norm(&cur.grad) < 1e-10 {
            break;
        }
        let sy = last.as_ref().map(|(s, y)| (s.as_slice(), y.as_slice()));
        let Some((dir, last_step)) = rule.next(model, (&x, &cur), sy, (t, mu), evals)? else {
            break;
        };
        let slope = dot(&dir, &cur.grad);
        if slope.is_nan() || slope >= 0.0 {
            break;
        }
        let Some((xn, en)) = line_search(model, (&x, &cur), &dir, slope, (t, mu), evals)? else {
            break;
        };
        let stalled = (cur.phi - en.phi).abs() <= 1e-15 * cur.phi.abs().max(1.0);
        last = Some((
            xn.iter().zip(&x).map(|(a, b)| a - b).collect(),
            en.grad.iter().zip(&cur.grad).map(|(a, b)| a - b).collect(),
        ));
        x = xn;
        cur = en;
        if stalled || last_step {
            break;
        }
    }
    Ok((x, inf_norm(&cur.grad)))
}

/// BFGS from the identity on the inverse Hessian H (update skipped unless sᵀy > 0; reset to
/// the identity where −H∇Φ does not descend).
pub(super) struct Bfgs {
    h: Mat<f64>,
}

impl Bfgs {
    pub fn new(d: usize) -> Self {
        Bfgs {
            h: Mat::identity(d, d),
        }
    }
}

impl Direction for Bfgs {
    fn next(
        &mut self,
        _: &Model,
        (_, cur): (&[f64], &Eval),
        last: Option<(&[f64], &[f64])>,
        _: (f64, f64),
        _: &mut usize,
    ) -> Result<Option<(Vec<f64>, bool)>> {
        let (d, h) = (cur.grad.len(), &mut self.h);
        if let Some((sv, yv)) = last {
            let sy = dot(sv, yv);
            if sy > 1e-300 {
                // H ← (I − ρ s yᵀ) H (I − ρ y sᵀ) + ρ s sᵀ.
                let rho = 1.0 / sy;
                let hy = mat_vec(h, yv);
                let yhy = dot(yv, &hy);
                *h = Mat::from_fn(d, d, |i, j| {
                    h[(i, j)] - rho * (hy[i] * sv[j] + sv[i] * hy[j])
                        + (rho * rho * yhy + rho) * sv[i] * sv[j]
                });
            }
        }
        let dir: Vec<f64> = mat_vec(h, &cur.grad).iter().map(|v| -v).collect();
        let slope = dot(&dir, &cur.grad);
        if slope.is_nan() || slope >= 0.0 {
            *h = Mat::identity(d, d);
            return Ok(Some((cur.grad.iter().map(|g| -g).collect(), false)));
        }
        Ok(Some((dir, false)))
    }
}

/// Step (in ln ε) of the forward differences of the gradient that make Newton's Hessian.
const FD_STEP: f64 = 1e-6;

/// The symmetric finite-difference Hessian of Φ at x (gradient `grad` there): column j from
/// one evaluation at x + [`FD_STEP`]·e_j, or at x − [`FD_STEP`]·e_j where that point is
/// infeasible. None if both are.
fn fd_hessian(
    model: &Model,
    x: &[f64],
    grad: &[f64],
    (t, mu): (f64, f64),
    evals: &mut usize,
) -> Result<Option<Mat<f64>>> {
    let d = x.len();
    let mut hess = Mat::<f64>::zeros(d, d);
    for j in 0..d {
        let mut column = None;
        for step in [FD_STEP, -FD_STEP] {
            let mut xt = x.to_vec();
            xt[j] += step;
            *evals += 1;
            if let Some(e) = model.eval(&xt, t, mu)? {
                column = Some((e.grad, step));
                break;
            }
        }
        let Some((g, step)) = column else {
            return Ok(None);
        };
        for i in 0..d {
            hess[(i, j)] = (g[i] - grad[i]) / step;
        }
    }
    Ok(Some(Mat::from_fn(d, d, |i, j| {
        0.5 * (hess[(i, j)] + hess[(j, i)])
    })))
}

/// Iterations between finite-difference Hessians in [`Newton`] (direct BFGS updates between).
const HESSIAN_EVERY: usize = 5;

/// Newton directions: every [`HESSIAN_EVERY`]th iteration the Hessian is [`fd_hessian`]'s
/// (d evaluations), in between its direct BFGS update `B ← B − B s sᵀ B/(sᵀB s) + y yᵀ/(yᵀs)`
/// (skipped unless sᵀy, sᵀBs > 0). Its eigenvalues are replaced by their absolute values
/// (floored at 10⁻¹⁰ of the largest) so that −B⁻¹∇Φ descends. This is the price of
/// convergence where BFGS from the identity crawls: at large t the smoothed objective is ~t
/// times more curved across an eigenvalue cluster than along it. Stops after the step when
/// the Newton decrement ∇Φᵀ|B|⁻¹∇Φ is below 10⁻¹⁴.
pub(super) struct Newton {
    hess: Mat<f64>,
    iteration: usize,
}

impl Newton {
    pub fn new(d: usize) -> Self {
        Newton {
            hess: Mat::zeros(d, d),
            iteration: 0,
        }
    }
}

impl Direction for Newton {
    fn next(
        &mut self,
        model: &Model,
        (x, cur): (&[f64], &Eval),
        last: Option<(&[f64], &[f64])>,
        tm: (f64, f64),
        evals: &mut usize,
    ) -> Result<Option<(Vec<f64>, bool)>> {
        let d = x.len();
        if self.iteration.is_multiple_of(HESSIAN_EVERY) {
            let Some(h) = fd_hessian(model, x, &cur.grad, tm, evals)? else {
                return Ok(None);
            };
            self.hess = h;
        } else if let Some((sv, yv)) = last {
            let hess = &mut self.hess;
            let sy = dot(sv, yv);
            let bs = mat_vec(hess, sv);
            let sbs = dot(sv, &bs);
            if sy > 1e-300 && sbs > 1e-300 {
                *hess = Mat::from_fn(d, d, |i, j| {
                    hess[(i, j)] - bs[i] * bs[j] / sbs + yv[i] * yv[j] / sy
                });
            }
        }
        self.iteration += 1;
        let Ok(evd) = self.hess.as_ref().self_adjoint_eigen(faer::Side::Lower) else {
            return Ok(None);
        };
        let (u, s) = (evd.U(), evd.S().column_vector());
        let top = (0..d).map(|k| s[k].abs()).fold(0.0f64, f64::max);
        let floor = (1e-10 * top).max(f64::MIN_POSITIVE);
        let (mut dir, mut decrement) = (vec![0.0; d], 0.0);
        for k in 0..d {
            let c: f64 = (0..d).map(|i| u[(i, k)] * cur.grad[i]).sum();
            let l = s[k].abs().max(floor);
            decrement += c * c / l;
            for (i, v) in dir.iter_mut().enumerate() {
                *v -= u[(i, k)] * c / l;
            }
        }
        Ok(Some((dir, decrement < 1e-14)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strategy::optimal::spectrum::Route;
    use crate::system::{Constraint, Stiffness};

    /// A 40-DOF chain (K tridiagonal, SPD) under a load, with two bilateral rows that couple
    /// DOFs — one of them far apart, so the sparse route's pattern needs fill.
    fn coupled_chain() -> Problem {
        let n = 40;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0 + 0.01 * i as f64));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let k = Stiffness::from_triplets(n, &t).unwrap();
        let q: Vec<f64> = (0..n).map(|i| ((i as f64) * 0.7).sin()).collect();
        let b = ConstraintKind::Bilateral;
        let rows = vec![
            Constraint::row(vec![(3, 0.6), (4, 0.8)], 0.5, b),
            Constraint::row(vec![(10, 1.0), (30, -0.5), (31, 0.25)], -0.2, b),
        ];
        Problem::new(k, q, rows).unwrap()
    }

    /// The gradient of Φ in ln ε on coupled rows (∂λ_k/∂ε_j = (d_jᵀv_k)², the adjoint through
    /// the rows) against central differences of Φ itself, on the dense route; the sparse
    /// route evaluates the same rows on K + DDᵀ's widened pattern.
    #[test]
    fn gradient_on_coupled_rows_matches_differences() {
        let p = coupled_chain();
        let spectrum = Spectrum::new(&p, Route::Dense).unwrap();
        let model = Model {
            p: &p,
            spectrum: &spectrum,
            set: vec![0, 1],
            delta: 100.0,
        };
        let (t, mu) = (20.0, 1e-3);
        let x = [1.3f64, 0.4];
        let e = model.eval(&x, t, mu).unwrap().unwrap();
        for j in 0..2 {
            let h = 1e-5;
            let mut xp = x;
            let mut xm = x;
            xp[j] += h;
            xm[j] -= h;
            let fp = model.eval(&xp, t, mu).unwrap().unwrap().phi;
            let fm = model.eval(&xm, t, mu).unwrap().unwrap().phi;
            let fd = (fp - fm) / (2.0 * h);
            assert!(
                (fd - e.grad[j]).abs() <= 1e-6 * e.grad[j].abs().max(1e-3),
                "j = {j}: analytic {} vs differences {fd}",
                e.grad[j]
            );
        }
        let sparse = Spectrum::new(&p, Route::Sparse).unwrap();
        let sm = Model {
            spectrum: &sparse,
            set: vec![0, 1],
            ..model
        };
        let es = sm.eval(&x, t, mu).unwrap().unwrap();
        // The windows hold the extreme eigenvalues: the same ln cond₂ bound up to the
        // truncated sums (≤ 2 ln n / t apart).
        assert!(es.phi.is_finite() && (es.phi - e.phi).abs() <= 2.0 * 40f64.ln() / t);
    }
}
