//! Coulomb friction: quasi-static frictional contact in load increments, with slip history.
//!
//! **The law** (per contact c, in the plane: one normal row `d_N`, one tangential row `d_T`):
//!
//! ```text
//!   K u = q_k + Σ_c (λ_N,c d_N,c + λ_T,c d_T,c)          (equilibrium at increment k)
//!   g_N = d_Nᵀu − û ≥ 0,  λ_N ≥ 0,  λ_N g_N = 0           (Signorini)
//!   |λ_T| ≤ μ λ_N;  |λ_T| < μ λ_N ⇒ Δs = 0;  Δs ≠ 0 ⇒ λ_T = −μ λ_N sign(Δs)   (Coulomb)
//! ```
//!
//! with `s = d_Tᵀu` the tangential displacement and `Δs = s − s_{k−1}` its increment over the
//! load step. **Signs and units:** λ_N is the compressive normal force *on the body* along
//! `d_N` (≥ 0; the frictionless strategies' contact force is `r_c = −λ_N`), λ_T the friction
//! force on the body along `d_T`, which opposes the slip: a block pushed to +x has λ_T ≤ 0.
//! Forces in the units of `q` (plane strain: per unit thickness), lengths in those of u,
//! μ dimensionless.
//!
//! **Methods** ([`FrictionMethod`]):
//! - `lagrange` — the exact law by a semismooth Newton (primal–dual active set) method on the
//!   Alart–Curnier functions in (u, λ_N, λ_T) ([`lagrange`]); the reference.
//! - `augmented` — augmented Lagrangian (Uzawa) on both multipliers, ε_N and ε_T fixed, until
//!   the multipliers move less than `tol` (a length) over the penalties ([`penalty`]).
//! - `penalty` — a normal penalty ε_N per contact ([`NormalRule`]: constant, or any
//!   frictionless rule of [`crate::strategy`] evaluated on the first increment and held) and a
//!   tangential ("stick") penalty by a [`TangentRule`]: constant ε_T, ε_T per unit contact area
//!   `r·G·w_c/h_c`, or the paper's idea carried to the tangent — an allowed elastic slip δ_T,
//!   `ε_T,c = μ λ_N,c / δ_T`, recomputed per contact and per Newton iteration (the analogue of
//!   Eq. 17/28: at the onset of slip the elastic slip is δ_T exactly). Return mapping on the
//!   slip, Newton with the consistent tangent, unsymmetric for Coulomb (`∂λ_T/∂u` holds
//!   `μ ∂λ_N/∂u`); the [`Law::Tresca`] variant bounds λ_T by μ times the normal force at the
//!   start of the increment and keeps the tangent symmetric.
//!
//! Use `lagrange` for reference answers; the penalty rules to ask what a choice of (ε_N, ε_T)
//! costs in error, Newton iterations and cond₂ of the tangent ([`FrictionSolution::tangent`],
//! unsymmetric: [`crate::conditioning::cond2`] takes the dense SVD route).
//!
//! Models with friction: [`sliding_block`] (an elastic block pressed and pushed along a rigid
//! plane), [`patch`] (the two-body patch test in full slip, mortar or node-to-segment rows),
//! [`incline`] (the crowned block pressed onto an inclined plane: rows coupling two DOFs) and
//! [`cattaneo`] (two identical bodies pressed, then loaded tangentially below μP: the stick zone
//! against Cattaneo–Mindlin's closed form).

pub mod cattaneo;
pub mod incline;
pub mod lagrange;
pub mod patch;
pub mod penalty;
pub mod sliding_block;

#[cfg(test)]
mod tests;

use crate::error::{Error, Result};
use crate::strategy::Method;
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};
use serde::Serialize;

/// Newton (or active-set) iterations allowed per increment before it is reported unconverged.
pub const MAX_NEWTON: usize = 60;
/// Uzawa updates allowed per increment (`augmented`).
pub const MAX_UZAWA: usize = 200;

/// A frictional problem: K, the normal rows (as a frictionless [`Problem`] whose load is the
/// first increment's), one tangential row per contact and the load of every increment.
#[derive(Clone, Debug)]
pub struct FrictionProblem {
    /// K, `q = loads[0]` and one `lower` constraint `d_Nᵀu ≥ û` per contact.
    pub normal: Problem,
    /// The tangential row `d_T` of each contact (terms `(DOF, coefficient)`).
    pub tangents: Vec<Vec<(usize, f64)>>,
    /// q of each increment (at least one).
    pub loads: Vec<Vec<f64>>,
    /// Coulomb's friction coefficient μ ≥ 0.
    pub mu: f64,
    /// The contact length (area per unit thickness) w_c each contact stands for.
    pub areas: Vec<f64>,
    /// The size h_c of the element layer at each contact, normal to the surface.
    pub layers: Vec<f64>,
    /// The body's shear modulus G at the surface (force/length² per unit thickness).
    pub shear_modulus: f64,
}

impl FrictionProblem {
    /// A validated frictional problem. `normal_rows` are `(d_N, û)`; every other argument as
    /// the fields. Errors name the bad value: μ < 0 or not finite, a load of the wrong length
    /// or not finite, no increment, a tangential row with a DOF out of range or a repeated
    /// DOF, an area, layer or G not > 0, and whatever [`Problem::new`] refuses.
    pub fn new(
        k: Stiffness,
        loads: Vec<Vec<f64>>,
        normal_rows: Vec<(Vec<(usize, f64)>, f64)>,
        tangents: Vec<Vec<(usize, f64)>>,
        mu: f64,
        geometry: (Vec<f64>, Vec<f64>, f64),
    ) -> Result<FrictionProblem> {
        if !mu.is_finite() {
            return Err(Error::not_finite("friction coefficient μ"));
        }
        if mu < 0.0 {
            return Err(Error::out_of_range("friction coefficient μ", mu, "≥ 0"));
        }
        let first = loads
            .first()
            .cloned()
            .ok_or_else(|| Error::none_given("load increments", "give at least one load q"))?;
        let constraints = normal_rows
            .into_iter()
            .map(|(terms, limit)| Constraint::row(terms, limit, ConstraintKind::Lower))
            .collect();
        let normal = Problem::new(k, first, constraints)?;
        let (n, m) = (normal.n(), normal.m());
        for (i, q) in loads.iter().enumerate() {
            if q.len() != n {
                return Err(Error::length_mismatch(
                    format!("load of increment {i}"),
                    q.len(),
                    n,
                ));
            }
            if !q.iter().all(|v| v.is_finite()) {
                return Err(Error::not_finite(format!("load of increment {i}")));
            }
        }
        let (areas, layers, shear_modulus) = geometry;
        for (what, len) in [
            ("tangential rows", tangents.len()),
            ("contact areas", areas.len()),
            ("contact layers", layers.len()),
        ] {
            if len != m {
                return Err(Error::length_mismatch(what, len, m));
            }
        }
        for (c, row) in tangents.iter().enumerate() {
            validate_row(c, row, n)?;
        }
        for (c, (&w, &h)) in areas.iter().zip(&layers).enumerate() {
            Error::positive(format!("contact area w_{c}"), w)?;
            Error::positive(format!("contact layer h_{c}"), h)?;
        }
        Error::positive("shear modulus G", shear_modulus)?;
        Ok(FrictionProblem {
            normal,
            tangents,
            loads,
            mu,
            areas,
            layers,
            shear_modulus,
        })
    }

    /// Number of contacts m.
    pub fn m(&self) -> usize {
        self.normal.m()
    }

    /// Number of unknowns N.
    pub fn n(&self) -> usize {
        self.normal.n()
    }

    /// `d_Nᵀu − û` of contact c.
    pub fn gap(&self, c: usize, u: &[f64]) -> f64 {
        let con = &self.normal.constraints[c];
        dot(&con.terms, u) - con.limit
    }

    /// `r·G·w_c/h_c`: the penalty per unit contact area of contact c for the dimensionless
    /// factor r ([`NormalRule::Area`], [`TangentRule::Area`]; force/length).
    pub fn area_penalty(&self, r: f64, c: usize) -> f64 {
        r * self.shear_modulus * self.areas[c] / self.layers[c]
    }

    /// `s = d_Tᵀu` of contact c.
    pub fn slip(&self, c: usize, u: &[f64]) -> f64 {
        dot(&self.tangents[c], u)
    }

    /// `K u − q − Σ (λ_N d_N + λ_T d_T)`: the equilibrium residual of increment `k`.
    pub fn residual(&self, k: usize, u: &[f64], lam_n: &[f64], lam_t: &[f64]) -> Vec<f64> {
        let mut r = self.normal.k.matvec(u);
        for (ri, qi) in r.iter_mut().zip(&self.loads[k]) {
            *ri -= qi;
        }
        for c in 0..self.m() {
            for &(d, a) in &self.normal.constraints[c].terms {
                r[d] -= a * lam_n[c];
            }
            for &(d, a) in &self.tangents[c] {
                r[d] -= a * lam_t[c];
            }
        }
        r
    }
}

/// A tangential row's DOFs in range, each once, coefficients finite.
fn validate_row(c: usize, row: &[(usize, f64)], n: usize) -> Result<()> {
    for (i, &(d, a)) in row.iter().enumerate() {
        if d >= n {
            return Err(Error::out_of_range(
                format!("DOF of the tangential row of contact {c}"),
                d,
                format!("< N = {n}"),
            ));
        }
        if !a.is_finite() {
            return Err(Error::not_finite(format!(
                "coefficient of the tangential row of contact {c}"
            )));
        }
        if row[..i].iter().any(|t| t.0 == d) {
            return Err(Error::duplicate(
                format!("DOF in the tangential row of contact {c}"),
                d,
            ));
        }
    }
    if row.is_empty() {
        return Err(Error::none_given(
            format!("terms of the tangential row of contact {c}"),
            "a tangential row needs a DOF",
        ));
    }
    Ok(())
}

/// `Σ a·u[d]` over a row's terms.
pub(crate) fn dot(row: &[(usize, f64)], u: &[f64]) -> f64 {
    row.iter().map(|&(d, a)| a * u[d]).sum()
}

/// How the normal penalty ε_N,c is chosen.
#[derive(Clone, Debug, PartialEq)]
pub enum NormalRule {
    /// One ε_N for every contact (force/length).
    Constant(f64),
    /// `ε_N,c = r·G·w_c/h_c`, as [`TangentRule::Area`]: a penalty per unit contact area (a
    /// contact with half the area gets half the ε), which a uniform pressure loads uniformly.
    Area(f64),
    /// A frictionless rule of [`crate::strategy`] (a penalty rule: `constant`, `scaled`,
    /// `spring`, `paper`, `condensed`, `optimal`) solved on the first increment's load; its
    /// ε_c is held through the increments, and a contact it left unpenalized takes the
    /// largest ε it gave.
    Rule(Method),
}

/// How the tangential penalty ε_T,c is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TangentRule {
    /// One ε_T for every contact (force/length).
    Constant(f64),
    /// `ε_T,c = r·G·w_c/h_c`: the shear stiffness of the element layer at the contact, times
    /// the dimensionless r (G·w/h: force/length, per unit thickness in plane strain).
    Area(f64),
    /// An allowed elastic slip δ_T (length): `ε_T,c = μ λ_N,c / δ_T`, per contact and per
    /// Newton iteration; a contact sticks while its elastic slip is ≤ δ_T.
    Delta(f64),
}

/// Which bound the friction force meets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Law {
    /// `|λ_T| ≤ μ λ_N` with the current λ_N: the consistent tangent is unsymmetric.
    Coulomb,
    /// `|λ_T| ≤ μ λ̂_N`, λ̂_N the normal force at the start of the increment: symmetric. The
    /// first increment starts from λ̂_N = 0 and is frictionless.
    Tresca,
}

/// A way to solve the frictional problem.
#[derive(Clone, Debug, PartialEq)]
pub enum FrictionMethod {
    /// Exact Coulomb law, semismooth Newton ([`lagrange`]).
    Lagrange,
    /// Augmented Lagrangian on λ_N and λ_T with penalties ε_N, ε_T, to `tol` (length).
    Augmented {
        /// ε_N (force/length).
        eps_n: f64,
        /// ε_T (force/length).
        eps_t: f64,
        /// Largest multiplier change over its penalty accepted (length).
        tol: f64,
    },
    /// Penalties on both rows.
    Penalty {
        /// ε_N.
        normal: NormalRule,
        /// ε_T.
        tangent: TangentRule,
        /// Coulomb or Tresca.
        law: Law,
    },
}

impl FrictionMethod {
    /// The method's name: `lagrange`, `augmented`, `penalty`.
    pub fn name(&self) -> &'static str {
        match self {
            FrictionMethod::Lagrange => "lagrange",
            FrictionMethod::Augmented { .. } => "augmented",
            FrictionMethod::Penalty { .. } => "penalty",
        }
    }
}

/// Where a contact is at the end of an increment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactStatus {
    /// No normal force.
    Open,
    /// In contact, |λ_T| below the bound (or no tangential motion).
    Stick,
    /// In contact, |λ_T| = μ λ_N.
    Slip,
}

/// The state after one increment.
#[derive(Clone, Debug, Serialize)]
pub struct Increment {
    /// u.
    pub u: Vec<f64>,
    /// λ_N per contact (≥ 0, compressive force on the body).
    pub lam_n: Vec<f64>,
    /// λ_T per contact (friction force on the body along d_T).
    pub lam_t: Vec<f64>,
    /// Status per contact.
    pub status: Vec<ContactStatus>,
    /// ε_T per contact in the last Newton iteration (0 for `lagrange`).
    pub eps_t: Vec<f64>,
    /// Newton (or active-set) iterations of the increment (all Uzawa updates together).
    pub newton_iters: usize,
    /// Whether the increment met its test (the method's doc).
    pub converged: bool,
}

impl Increment {
    /// `N = Σ λ_N,c`.
    pub fn normal_force(&self) -> f64 {
        self.lam_n.iter().sum()
    }

    /// `T = Σ λ_T,c`.
    pub fn tangential_force(&self) -> f64 {
        self.lam_t.iter().sum()
    }

    /// Every contact in contact slips (and at least one is in contact).
    pub fn full_slip(&self) -> bool {
        self.status.contains(&ContactStatus::Slip) && !self.status.contains(&ContactStatus::Stick)
    }
}

/// The result of [`solve`]: one [`Increment`] per load, and totals.
#[derive(Clone, Debug, Serialize)]
pub struct FrictionSolution {
    /// `lagrange`, `augmented` or `penalty`.
    pub method: &'static str,
    /// ε_N per contact (0 for `lagrange`).
    pub eps_n: Vec<f64>,
    /// Every increment, in load order.
    pub increments: Vec<Increment>,
    /// Linear solves (factorizations) over all increments.
    pub factorizations: usize,
    /// Every increment converged.
    pub converged: bool,
    /// The linear system of the last increment with a contact in stick (the final
    /// increment's where none sticks; penalty: the N×N consistent tangent, where ε_T enters
    /// only through sticking contacts; lagrange: the (N+2m)-square active-set system), not
    /// serialized.
    #[serde(skip)]
    pub tangent: Option<Stiffness>,
    /// The increment whose system `tangent` is.
    pub tangent_increment: Option<usize>,
    /// Non-convergence and assumption failures, one line each.
    pub warnings: Vec<String>,
}

impl FrictionSolution {
    /// A solution of `method` with no increment yet (converged until one is not), the
    /// penalties `eps_n` per contact.
    pub fn start(method: &'static str, eps_n: Vec<f64>) -> FrictionSolution {
        FrictionSolution {
            method,
            eps_n,
            increments: Vec::new(),
            factorizations: 0,
            converged: true,
            tangent: None,
            tangent_increment: None,
            warnings: Vec::new(),
        }
    }

    /// A run that failed before any increment: unconverged, `error` its warning.
    pub fn failed(method: &'static str, error: &Error) -> FrictionSolution {
        FrictionSolution {
            converged: false,
            warnings: vec![format!("error: {error}")],
            ..FrictionSolution::start(method, Vec::new())
        }
    }

    /// Total Newton iterations.
    pub fn newton_iters(&self) -> usize {
        self.increments.iter().map(|i| i.newton_iters).sum()
    }

    /// The first increment in full slip, with `|T|/N` there.
    pub fn onset(&self) -> Option<(usize, f64)> {
        self.increments.iter().enumerate().find_map(|(k, inc)| {
            inc.full_slip()
                .then(|| (k, inc.tangential_force().abs() / inc.normal_force()))
        })
    }
}

/// ε_N per contact for `rule` on `p` (module doc of [`NormalRule`]).
pub fn normal_penalties(p: &FrictionProblem, rule: &NormalRule) -> Result<Vec<f64>> {
    let eps = match rule {
        NormalRule::Constant(e) => vec![Error::positive("normal penalty ε_N", *e)?; p.m()],
        NormalRule::Area(r) => {
            let r = Error::positive("normal penalty factor r", *r)?;
            (0..p.m()).map(|c| p.area_penalty(r, c)).collect()
        }
        NormalRule::Rule(method) => {
            let sol = crate::strategy::solve(&p.normal, *method)?;
            let top = sol.penalties.iter().cloned().fold(0.0f64, f64::max);
            if !(top > 0.0 && top.is_finite()) {
                return Err(Error::unsupported(
                    format!("normal rule `{}` for friction", method.name()),
                    "a penalty rule that penalizes some contact at the first increment",
                ));
            }
            sol.penalties
                .iter()
                .map(|&e| if e > 0.0 { e } else { top })
                .collect()
        }
    };
    Ok(eps)
}

/// Solves every increment of `p` with `method`, each from the state of the one before
/// (u = 0, λ = 0, s = 0 before the first).
pub fn solve(p: &FrictionProblem, method: &FrictionMethod) -> Result<FrictionSolution> {
    solve_from(p, method, None)
}

/// [`solve`] from the state `start` (an increment of an earlier solve of the same K, rows
/// and method; None: the unloaded state): its u, λ_N, λ_T and slip history (the penalties'
/// plastic slip `s + λ_T/ε_T` from its ε_T) are those before `p`'s first load. Used where
/// many continuations share one loading history (`cattaneo-mindlin`'s slide from one squeeze).
pub fn solve_from(
    p: &FrictionProblem,
    method: &FrictionMethod,
    start: Option<&Increment>,
) -> Result<FrictionSolution> {
    if let Some(s) = start {
        let m = p.m();
        if s.u.len() != p.n() {
            return Err(Error::length_mismatch("start state's u", s.u.len(), p.n()));
        }
        for (what, len) in [
            ("λ_N", s.lam_n.len()),
            ("λ_T", s.lam_t.len()),
            ("ε_T", s.eps_t.len()),
        ] {
            if len != m {
                return Err(Error::length_mismatch(
                    format!("start state's {what}"),
                    len,
                    m,
                ));
            }
        }
    }
    match method {
        FrictionMethod::Lagrange => lagrange::solve(p, start),
        FrictionMethod::Augmented { eps_n, eps_t, tol } => {
            let eps_n = vec![Error::positive("normal penalty ε_N", *eps_n)?; p.m()];
            Error::positive("tangential penalty ε_T", *eps_t)?;
            Error::positive("augmented tolerance", *tol)?;
            let t = penalty::Tangential::Augmented(*eps_t, *tol);
            penalty::solve(p, eps_n, t, start)
        }
        FrictionMethod::Penalty {
            normal,
            tangent,
            law,
        } => {
            if *law == Law::Tresca && !p.normal.k.is_symmetric() {
                return Err(Error::unsupported(
                    "the Tresca variant on an unsymmetric K",
                    "a symmetric K (its tangent is symmetric only then)",
                ));
            }
            let eps_n = normal_penalties(p, normal)?;
            let t = match *tangent {
                TangentRule::Constant(e) => {
                    let e = Error::positive("tangential penalty ε_T", e)?;
                    penalty::Tangential::Penalty(vec![e; p.m()], *law)
                }
                TangentRule::Area(r) => {
                    let r = Error::positive("tangential penalty factor r", r)?;
                    let e = (0..p.m()).map(|c| p.area_penalty(r, c));
                    penalty::Tangential::Penalty(e.collect(), *law)
                }
                TangentRule::Delta(d) => penalty::Tangential::Delta(
                    Error::positive("allowed elastic slip δ_T", d)?,
                    *law,
                ),
            };
            penalty::solve(p, eps_n, t, start)
        }
    }
}
