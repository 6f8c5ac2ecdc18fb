//! `cattaneo-mindlin`: two elastically similar bodies pressed together by P, then loaded
//! tangentially by Q < μP — a central stick zone inside an annulus of slip, with a closed-form
//! answer (Cattaneo 1938, Mindlin 1949; Johnson, *Contact Mechanics*, 1985, §7.1).
//!
//! **Analytic answer** (plane strain, cylinders of composite radius R, one material: Dundurs'
//! β = 0, so the tangential tractions do not change the normal ones): the Hertz half-width
//! `a = √(4PR/(πE*))` with `1/E* = 2(1 − ν²)/E`, `p0 = 2P/(πa)`, the stick half-width
//!
//! ```text
//!   c = a·√(1 − Q/(μP))
//!   q(x) = μ p0 [√(1 − x²/a²) − (c/a)·√(1 − x²/c²)·1(|x| < c)]      (|x| ≤ a; 0 beyond)
//! ```
//!
//! **Model.** Half-space theory, so both bodies are flat blocks and the curvature is the
//! initial gap `g0(x) = x²/(2R)` (as in the Hertz cases). The lower block A is
//! `[−L, L] × [0, L]` (L = [`BLOCK_OVER_A`]·a), Q4, plane strain, meshed with elements of size
//! h within [`FINE_OVER_A`]·a of the contact point and growing by [`GROWTH`] beyond — the
//! same mesh mirrored about x = 0. The upper block B is A turned by 180° about the contact
//! point (0, L): its node k lies at (−x_k, 2L − y_k), and since the rotation is −I on
//! displacements, B's stiffness in global components is A's, entry for entry. A's base is
//! held (u = v = 0); B's top face is moved rigidly by (s, −w): first w alone (increment 0,
//! the squeeze that carries P), then s (increment 1: displacement control, s found by a
//! bracketed secant so that Q/(μP) is the target within [`RATIO_TOL`]).
//!
//! **Rows.** The meshes match at the interface, so each top node i of A (at x_i) faces the
//! node of B at the same x (the image of A's top node at −x_i): node-to-node rows (one-pass
//! node-to-segment on matching meshes), normal `v_B − v_A ≥ −g0(x_i)` and tangential
//! `s_i = u_B − u_A` (the slip of B over A). A row's multiplier is the nodal force: λ_N,i the
//! compression, λ_T,i the friction force on B along +x (so on A it is −λ_T,i); the tractions
//! on A are `p_i = λ_N,i/w_i`, `q_i = −λ_T,i/w_i` with w_i the tributary length of the node.
//!
//! **Why the discrete problem uncouples exactly.** Mirror symmetry about x = 0 splits every
//! field into an even part (v even, u odd in x) and an odd part. The squeeze is even; s is odd.
//! The 180° image makes the pair's gap `−v_A(−x) − v_A(x) + g0` see only the even part of A's
//! field, and its slip `−u_A(−x) − u_A(x)` only the odd part; a normal multiplier loads A
//! evenly, a tangential one oddly. So the tangential load leaves the normal forces as they
//! are (the unit tests check it to rounding): the finite-element counterpart of β = 0, on a
//! finite block, with no approximation beyond the mesh and the block's size.
//!
//! **Measures** (over the top nodes of A, the last increment):
//! - `c_num`: the stick zone's half-width — on each side, where `(1 − |q|/(μp))²` extrapolated
//!   linearly from the two outermost sticking nodes vanishes (near c, 1 − |q|/(μp) falls like
//!   √(c − |x|), as the pressure near a in `contact_width`), kept between the outermost
//!   sticking node and the next one; the mean of the two sides;
//! - `c_exact`: `a(P)·√(1 − Q/(μP))` with Hertz's a for the computed P and the reached ratio;
//! - `shear_err_l2`: `√(Σ w_i (q_i − q(x_i))²) / √(Σ w_i q(x_i)²)` over every top node, q the
//!   closed form above for the computed P and the reached Q/(μP).

use super::{ContactStatus, FrictionMethod, FrictionProblem, FrictionSolution};
use crate::error::{Error, Result};
use crate::model::elasticity::{self, graded_axis, Geometry, Grid, Material};
use crate::strategy::Method;
use crate::system::Stiffness;

/// The material of both bodies (consistent units; lengths in units of a).
pub const MATERIAL: Material = Material {
    young: 1.0,
    poisson: 0.3,
};
/// The composite radius R of the pair, over a.
pub const RADIUS_OVER_A: f64 = 20.0;
/// The blocks' half-width and height L, over a.
pub const BLOCK_OVER_A: f64 = 16.0;
/// The uniform-size zone around the contact point, over a.
pub const FINE_OVER_A: f64 = 1.2;
/// Element growth beyond it.
pub const GROWTH: f64 = 1.2;
/// |Q/(μP) − target| the secant on s stops at.
pub const RATIO_TOL: f64 = 1e-7;
/// Solves the secant on s may take.
pub const MAX_SECANT: usize = 40;

/// The case at one mesh: lengths in units of a (the Hertz half-width of the target load).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CattaneoMindlin {
    /// Element size at the contact over a.
    pub h_over_a: f64,
    /// Coulomb's μ (> 0).
    pub mu: f64,
}

/// The assembled pair: K, the unit loads of the squeeze and of the slide, and the rows.
#[derive(Clone, Debug)]
pub struct CattaneoProblem {
    k: Stiffness,
    q_squeeze: Vec<f64>,
    q_slide: Vec<f64>,
    normal: Vec<(Vec<(usize, f64)>, f64)>,
    tangents: Vec<Vec<(usize, f64)>>,
    /// x of each contact (A's top nodes, left to right).
    pub xs: Vec<f64>,
    /// The tributary length w_i of each contact.
    pub widths: Vec<f64>,
    layers: Vec<f64>,
    mu: f64,
    /// The squeeze w that carries the target load (Lagrange, frictionless).
    pub squeeze: f64,
}

/// What one solve at a target ratio measured (module doc).
#[derive(Clone, Debug)]
pub struct CattaneoResult {
    /// The frictional solution of the last secant step (increment 0 the squeeze, 1 the slide).
    pub solution: FrictionSolution,
    /// The slide s of B's top.
    pub slide: f64,
    /// P = Σ λ_N of the last increment.
    pub p: f64,
    /// Q = −Σ λ_T (the force B's friction exerts on A along +x).
    pub q: f64,
    /// Q/(μP) reached.
    pub ratio: f64,
    /// Secant solves.
    pub secant_steps: usize,
    /// Numerical stick half-width (None where no contact sticks).
    pub c_num: Option<f64>,
    /// Analytic stick half-width for P and the reached ratio.
    pub c_exact: f64,
    /// Hertz's a for P.
    pub a_exact: f64,
    /// The shear traction's relative L2 error.
    pub shear_err_l2: f64,
}

/// The composite contact modulus E* of the pair: `E/(2(1 − ν²))`.
pub fn e_star() -> f64 {
    0.5 * MATERIAL.contact_modulus()
}

/// The shear modulus G = E/(2(1 + ν)) of both bodies.
pub fn shear_modulus() -> f64 {
    MATERIAL.young / (2.0 * (1.0 + MATERIAL.poisson))
}

/// The load P whose Hertz half-width is a = 1.
pub fn target_load() -> f64 {
    Geometry::PlaneStrain.hertz_load(1.0, RADIUS_OVER_A, e_star())
}

/// q(x) of the module doc for the half-widths a, c and peak pressure p0, times μ.
pub fn shear_exact(x: f64, a: f64, c: f64, mu_p0: f64) -> f64 {
    let root = |x: f64, r: f64| (1.0 - (x / r).powi(2)).max(0.0).sqrt();
    if x.abs() >= a {
        return 0.0;
    }
    let stick = if x.abs() < c { c / a * root(x, c) } else { 0.0 };
    mu_p0 * (root(x, a) - stick)
}

/// `ratio` = Q/(μP) must lie in (0, 1): at Q ≥ μP no static equilibrium exists under force
/// control.
pub fn check_ratio(ratio: f64) -> Result<f64> {
    if ratio.is_finite() && ratio > 0.0 && ratio < 1.0 {
        return Ok(ratio);
    }
    Err(Error::out_of_range(
        "Q/(μP)",
        ratio,
        "in (0, 1): at Q ≥ μP the bodies slide (no static equilibrium under force control)",
    ))
}

/// The mesh's h/a must lie in [1/256, 1/4] (finer meshes exceed the case's size limit).
pub fn check_h_over_a(h_over_a: f64) -> Result<f64> {
    if h_over_a.is_finite() && (1.0 / 256.0..=0.25).contains(&h_over_a) {
        return Ok(h_over_a);
    }
    Err(Error::out_of_range(
        "cattaneo-mindlin h/a",
        h_over_a,
        "in [1/256, 1/4] (finer meshes exceed this case's size limit)",
    ))
}

/// μ must be finite and > 0 (Q/(μP) needs μ > 0).
pub fn check_mu(mu: f64) -> Result<f64> {
    if mu.is_finite() && mu > 0.0 {
        return Ok(mu);
    }
    Err(Error::out_of_range(
        "cattaneo-mindlin μ",
        mu,
        "finite and > 0 (Q/(μP) needs μ > 0)",
    ))
}

impl CattaneoMindlin {
    fn validate(&self) -> Result<()> {
        check_h_over_a(self.h_over_a)?;
        check_mu(self.mu)?;
        Ok(())
    }

    /// The assembled pair with the squeeze that carries [`target_load`] (module doc).
    pub fn build(&self) -> Result<CattaneoProblem> {
        self.validate()?;
        let (l, h) = (BLOCK_OVER_A, self.h_over_a);
        let half = graded_axis(l, h, FINE_OVER_A, GROWTH);
        let xs: Vec<f64> = half
            .iter()
            .rev()
            .map(|x| -x)
            .chain(half.iter().skip(1).copied())
            .collect();
        let ys: Vec<f64> = half.iter().rev().map(|d| l - d).collect();
        let grid = Grid {
            xs: xs.clone(),
            ys: ys.clone(),
        };
        let (nx, ny) = (xs.len(), ys.len());
        let nodes = grid.nodes();
        let off = 2 * nodes;
        let ta = elasticity::assemble(&grid, Geometry::PlaneStrain, &MATERIAL)?;
        let mut t = ta.clone();
        t.extend(ta.into_iter().map(|(i, j, v)| (i + off, j + off, v)));
        // A's base held; B's top (the image of A's base, nodes (i, 0)) moved by (ux, uy).
        let fixed = |ux: f64, uy: f64| {
            let mut f = vec![None; 2 * off];
            for i in 0..nx {
                let n = grid.node(i, 0);
                (f[2 * n], f[2 * n + 1]) = (Some(0.0), Some(0.0));
                (f[off + 2 * n], f[off + 2 * n + 1]) = (Some(ux), Some(uy));
            }
            f
        };
        let (k, q_squeeze, map) = elasticity::eliminate(&t, &fixed(0.0, -1.0))?;
        let (_, q_slide, _) = elasticity::eliminate(&t, &fixed(1.0, 0.0))?;
        let widths = elasticity::top_weights(&xs, Geometry::PlaneStrain);
        let top = ny - 1;
        let (mut normal, mut tangents) = (Vec::with_capacity(nx), Vec::with_capacity(nx));
        for (i, &x) in xs.iter().enumerate() {
            let a = grid.node(i, top);
            let b = grid.node(nx - 1 - i, top);
            let (ua, va) = (map[2 * a], map[2 * a + 1]);
            let (ub, vb) = (map[off + 2 * b], map[off + 2 * b + 1]);
            normal.push((vec![(vb, 1.0), (va, -1.0)], -x * x / (2.0 * RADIUS_OVER_A)));
            tangents.push(vec![(ub, 1.0), (ua, -1.0)]);
        }
        let layer = ys[top] - ys[top - 1];
        let mut p = CattaneoProblem {
            k: k.in_preferred_storage(),
            q_squeeze,
            q_slide,
            normal,
            tangents,
            xs,
            widths,
            layers: vec![layer; nx],
            mu: self.mu,
            squeeze: 1.0,
        };
        p.squeeze = p.squeeze_for(target_load())?;
        Ok(p)
    }
}

impl CattaneoProblem {
    /// The frictional problem of one increment whose load is the squeeze w and the slide s.
    pub fn problem(&self, slide: f64) -> Result<FrictionProblem> {
        let w = self.squeeze;
        let q = self
            .q_squeeze
            .iter()
            .zip(&self.q_slide)
            .map(|(a, b)| w * a + slide * b)
            .collect();
        let g = shear_modulus();
        FrictionProblem::new(
            self.k.clone(),
            vec![q],
            self.normal.clone(),
            self.tangents.clone(),
            self.mu,
            (self.widths.clone(), self.layers.clone(), g),
        )
    }

    /// The frictionless normal force at squeeze w (Lagrange): `−Σ r_c`.
    fn normal_force(&self, w: f64) -> Result<f64> {
        let mut p = self.problem(0.0)?.normal;
        for (qi, &v) in p.q.iter_mut().zip(&self.q_squeeze) {
            *qi = w * v;
        }
        let sol = crate::strategy::solve(&p, Method::lagrange())?;
        Ok(-sol.forces.iter().sum::<f64>())
    }

    /// The squeeze that carries `load` within 10⁻⁶ (frictionless; the slide does not change
    /// it): a secant on P(w) from two guesses near this geometry's answer (w ≈ 0.0869 a).
    fn squeeze_for(&self, load: f64) -> Result<f64> {
        let (mut w0, mut w1) = (0.0868, 0.0872);
        let (mut p0, mut p1) = (self.normal_force(w0)?, self.normal_force(w1)?);
        for _ in 0..MAX_SECANT {
            if (p1 - load).abs() <= 1e-6 * load {
                return Ok(w1);
            }
            let w2 = w1 + (load - p1) * (w1 - w0) / (p1 - p0);
            if !(w2.is_finite() && w2 > 0.0) {
                break;
            }
            (w0, p0) = (w1, p1);
            w1 = w2;
            p1 = self.normal_force(w1)?;
        }
        Err(Error::Numerical(format!(
            "cattaneo-mindlin: no squeeze carries the target load within {MAX_SECANT} secant steps"
        )))
    }

    /// Solves with `method`: the squeeze once (increment 0), then the slide from that state,
    /// s found so that Q/(μP) = `ratio` (module doc); measures the result. `ratio` must lie in
    /// (0, 1): at Q ≥ μP no static equilibrium exists under force control.
    pub fn solve_at(&self, method: &FrictionMethod, ratio: f64) -> Result<CattaneoResult> {
        check_ratio(ratio)?;
        let not_converged = |what: String, sol: &FrictionSolution| {
            Error::Numerical(format!(
                "cattaneo-mindlin: {} did not converge {what}: {}",
                method.name(),
                sol.warnings.join("; ")
            ))
        };
        let base = super::solve(&self.problem(0.0)?, method)?;
        if !base.converged {
            return Err(not_converged("under the squeeze".into(), &base));
        }
        let state = &base.increments[0];
        let mut factorizations = base.factorizations;
        // Q(s) is increasing and concave, capped at μP: a secant kept inside a bracket.
        let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
        let mut s = 1e-3 * self.squeeze;
        let mut prev: Option<(f64, f64)> = None;
        for step in 1..=MAX_SECANT {
            let sol = super::solve_from(&self.problem(s)?, method, Some(state))?;
            factorizations += sol.factorizations;
            if !sol.converged {
                return Err(not_converged(format!("at slide {s}"), &sol));
            }
            let last = &sol.increments[0];
            let (p, r) = (last.normal_force(), -last.tangential_force());
            let r = r / (self.mu * p);
            if (r - ratio).abs() <= RATIO_TOL {
                let mut whole = sol;
                whole.increments.insert(0, state.clone());
                whole.factorizations = factorizations;
                whole.tangent_increment = whole.tangent_increment.map(|k| k + 1);
                whole.warnings = [base.warnings.clone(), whole.warnings].concat();
                return Ok(self.measure(whole, s, p, r, step));
            }
            if r < ratio {
                lo = lo.max(s);
            } else {
                hi = hi.min(s);
            }
            let secant = prev.map(|(s0, r0)| s + (ratio - r) * (s - s0) / (r - r0));
            let next = match secant {
                Some(t) if t.is_finite() && t > lo && t < hi => t,
                _ if hi.is_finite() => 0.5 * (lo + hi),
                // No bracket yet: the line through the origin undershoots Q's concave curve;
                // at least double.
                _ => (s * ratio / r.max(1e-300)).max(2.0 * s),
            };
            prev = Some((s, r));
            s = next;
        }
        Err(Error::Numerical(format!(
            "cattaneo-mindlin: no slide gives Q/(μP) = {ratio} within {MAX_SECANT} secant steps"
        )))
    }

    /// The measures of one solution (module doc).
    fn measure(
        &self,
        solution: FrictionSolution,
        slide: f64,
        p: f64,
        ratio: f64,
        steps: usize,
    ) -> CattaneoResult {
        let last = solution.increments.last().expect("two increments");
        let a = Geometry::PlaneStrain.hertz_half_width(p, RADIUS_OVER_A, e_star());
        let c_exact = a * (1.0 - ratio).sqrt();
        let mu_p0 = self.mu * 2.0 * p / (std::f64::consts::PI * a);
        let (mut num, mut den) = (0.0, 0.0);
        for (i, (&x, &w)) in self.xs.iter().zip(&self.widths).enumerate() {
            let q = -last.lam_t[i] / w;
            let e = shear_exact(x, a, c_exact, mu_p0);
            num += w * (q - e).powi(2);
            den += w * e * e;
        }
        let c_num = stick_half_width(&self.xs, self.mu, last);
        CattaneoResult {
            q: -last.tangential_force(),
            solution,
            slide,
            p,
            ratio,
            secant_steps: steps,
            c_num,
            c_exact,
            a_exact: a,
            shear_err_l2: (num / den).sqrt(),
        }
    }
}

/// `c_num` of the module doc: per side, the outermost sticking node, and where
/// `(1 − |λ_T|/(μλ_N))²` extrapolated from it and the sticking node inside it vanishes, kept
/// before the next node out; the mean of both sides. None if no contact sticks.
fn stick_half_width(xs: &[f64], mu: f64, inc: &super::Increment) -> Option<f64> {
    let stuck = |i: usize| inc.status[i] == ContactStatus::Stick && inc.lam_n[i] > 0.0;
    let f = |i: usize| (1.0 - inc.lam_t[i].abs() / (mu * inc.lam_n[i])).powi(2);
    let n = xs.len();
    let mid = n / 2;
    let side = |order: &mut dyn Iterator<Item = usize>| -> Option<f64> {
        let idx: Vec<usize> = order.collect();
        let k = idx.iter().rposition(|&i| stuck(i))?;
        let out = idx[k];
        let edge = xs[out].abs();
        let next = idx.get(k + 1).map_or(edge, |&i| xs[i].abs());
        if k == 0 {
            return Some(0.5 * (edge + next));
        }
        let inner = idx[k - 1];
        let (f1, f0) = (f(out), f(inner));
        let x0 = xs[inner].abs();
        if f0 > f1 && stuck(inner) {
            Some((edge + f1 * (edge - x0) / (f0 - f1)).clamp(edge, next))
        } else {
            Some(0.5 * (edge + next))
        }
    };
    let right = side(&mut (mid..n));
    let left = side(&mut (0..=mid).rev());
    match (left, right) {
        (Some(l), Some(r)) => Some(0.5 * (l + r)),
        (l, r) => l.or(r),
    }
}
