//! `friction_bench`: the tangential penalty ε_T judged against the exact Coulomb law, on the
//! `sliding-block` case ([`crate::friction::sliding_block`]) and the two-body patch test in
//! full slip, `patch-two-body-friction` ([`crate::friction::patch`], mortar and one-pass
//! node-to-segment rows: rows record `discretization`, `pressure_err_max`, `shear_err_max`)
//! and the crowned block pressed onto a plane inclined at 30°, `inclined-friction`
//! ([`crate::friction::incline`]: rows coupling two DOFs; rows record `theta`).
//!
//! For each μ the block is pressed, then pushed along the plane in `steps` increments by
//! every method (the patch test: one increment into full slip): `lagrange` (the reference),
//! `augmented` (ε_N = ε_T = 10·G, tolerance 10⁻¹⁰ of the case's length L: the multipliers'
//! changes stall at 10⁻¹² of w on the stiff patch, rounding), and the penalty
//! rules with a normal penalty per unit area `ε_N,c = eps_n·G·w_c/h_c` and a tangential rule of
//! [`crate::friction::TangentRule`] over a ladder of knobs: `constant` (ε_T = f·G), `area`
//! (ε_T,c = r·G·w_c/h_c) and `delta` (δ_T = f·L, the allowed elastic slip); G the (upper)
//! body's shear modulus, L the platen's (clamp's) depth press·H or the patch's squeeze w. One row per
//! (case, μ, discretization, method, knob) ([`FrictionRow`]):
//!
//! - `onset_ratio` = |T|/N at the first increment in full slip — μ wherever every contact
//!   slips the same way, by the law's own bookkeeping (λ_T = ∓μλ_N is imposed on a slipping
//!   contact), so it checks the statuses, not the solve: equilibrium and the law per contact
//!   are tested against independent solutions in the unit tests; `onset_travel`, the platen's
//!   travel there, resolved to one increment (`travel/steps`), and `onset_travel_err`, its
//!   difference from Lagrange's over Lagrange's (a soft ε_T lets the platen travel further
//!   before the block slides);
//! - `history_err` = max over increments of |T − T_lagrange| over μ·N_lagrange: the friction
//!   force's error along the whole loading;
//! - `increments`, `newton_iters` (all linear solves' Newton steps, lagged passes included),
//!   `factorizations`, `converged` (every increment; a row that did not converge is kept and
//!   says so);
//! - cond₂ of the linear system of the last increment with a contact in stick — the
//!   increment before full slip, where ε_T still enters (penalties: the N×N consistent
//!   tangent, unsymmetric under Coulomb's law; Lagrange: its (N+2m)-square active-set system) with
//!   its bracket (`cond2_system`, `cond2_lo`, `cond2_hi`, `cond2_bounds_proven`,
//!   `cond_route`): [`crate::conditioning::cond2`], the dense SVD route for an unsymmetric
//!   matrix; and on the penalties' tangent, GMRES(30)-Jacobi iterations counted to the fixed
//!   error of u (`gmres_iters_jacobi_to_err`, [`FrictionRow::gmres_iters_jacobi_to_err`]).
//!
//! The columns `h_over_a`, `q_over_mup`, `c_num`, `c_exact` and `shear_err_l2` belong to the
//! `cattaneo-mindlin` case (on request: `--cases cattaneo-mindlin`, its own flags `--cm-*` and
//! `--q-over-mup`; `cattaneo` module) and stay empty in the other cases' rows.

pub mod cattaneo;
mod figures;
mod report;

pub use figures::figures;
pub use report::{table, tally};

use crate::conditioning;
use crate::error::{Error, Result};
use crate::friction::cattaneo::{check_h_over_a, check_mu, check_ratio};
use crate::friction::incline::InclinedFriction;
use crate::friction::patch::{PatchFriction, PatchProblem};
use crate::friction::sliding_block::{SlidingBlock, HEIGHT};
use crate::friction::{self, FrictionMethod, FrictionSolution, Law, NormalRule, TangentRule};
use crate::model::incline_block::{HEIGHT as INCLINE_HEIGHT, PRESS};
use crate::model::two_body::Discretization;
use crate::progress::Progress;
use crate::study::checkpoint::Checkpoints;
use crate::study::shape::{Drawing, RunContext, Study};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The most increments `--steps` takes (each a Newton solve per method and μ).
pub const MAX_STEPS: usize = 10_000;
/// The most elements `--mesh` takes (cond₂ of the tangent densifies N ≈ 2·NX·NY unknowns).
pub const MAX_ELEMENTS: usize = 2_500;

/// The incline's angle (degrees) of `inclined-friction`.
pub const INCLINE_THETA: f64 = 30.0;

/// The cases `--cases` knows.
pub const CASES: &[&str] = &[
    "sliding-block",
    "patch-two-body-friction",
    "inclined-friction",
    cattaneo::CASE,
];

/// `friction_bench`'s flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Frictional cases: `sliding-block`, `patch-two-body-friction`, `inclined-friction`
    /// (θ = 30°, the block's `--mesh`, `--steps` press increments); on request
    /// `cattaneo-mindlin` (minutes: its own `--cm-*` flags and `--q-over-mup`).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "sliding-block,patch-two-body-friction,inclined-friction"
    )]
    cases: Vec<String>,
    /// Coulomb friction coefficients μ (≥ 0).
    #[arg(long, value_delimiter = ',', default_value = "0.1,0.2,0.3")]
    mu: Vec<f64>,
    /// Elements of the block, `NXxNY`.
    #[arg(long, default_value = "16x8")]
    mesh: String,
    /// Push increments after the press.
    #[arg(long, default_value_t = 40)]
    steps: usize,
    /// r of the normal penalty ε_N,c = r·G·w_c/h_c of every penalty row (per unit contact
    /// area: G the case's shear modulus, w_c the contact's length, h_c its element layer).
    #[arg(long, default_value_t = 1e4)]
    eps_n: f64,
    /// Tangential penalty factors f: `constant` rows ε_T = f·G, `area` rows r = f.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.1,1,10,100,1000,10000,100000,1000000"
    )]
    eps_t: Vec<f64>,
    /// Allowed elastic slips δ_T over the case's length (the platen's depth press·H, the
    /// patch test's squeeze w) (`delta` rows).
    #[arg(long, value_delimiter = ',', default_value = "1,0.1,0.01,0.001")]
    delta_t: Vec<f64>,
    /// The friction law of the penalty rows: `coulomb` (unsymmetric tangent) or `tresca`.
    #[arg(long, default_value = "coulomb")]
    law: String,
    /// `cattaneo-mindlin`: element sizes h/a at the contact, one mesh each (in [1/256, 1/4]).
    #[arg(long, value_delimiter = ',', default_value = "0.125,0.0625,0.03125")]
    cm_levels: Vec<f64>,
    /// `cattaneo-mindlin`: tangential loads Q/(μP), each in (0, 1).
    #[arg(long, value_delimiter = ',', default_value = "0.25,0.5,0.75")]
    q_over_mup: Vec<f64>,
    /// `cattaneo-mindlin`: r of the `area` rule ε_T,c = r·G·w_c/h_c.
    #[arg(long, value_delimiter = ',', default_value = "100,10000")]
    cm_eps_t: Vec<f64>,
    /// `cattaneo-mindlin`: allowed elastic slips δ_T over a of the `delta` rule.
    #[arg(long, value_delimiter = ',', default_value = "0.001,0.0001")]
    cm_delta_t: Vec<f64>,
}

/// The validated configuration.
#[derive(Clone, Debug, Serialize)]
pub struct BenchConfig {
    /// Cases.
    pub cases: Vec<String>,
    /// μ values.
    pub mu: Vec<f64>,
    /// (nx, ny).
    pub mesh: (usize, usize),
    /// Push increments.
    pub steps: usize,
    /// ε_N/G.
    pub eps_n: f64,
    /// ε_T factors.
    pub eps_t: Vec<f64>,
    /// δ_T/(press·H).
    pub delta_t: Vec<f64>,
    /// Coulomb or Tresca.
    pub law: Law,
    /// `cattaneo-mindlin` meshes, h/a.
    pub cm_levels: Vec<f64>,
    /// `cattaneo-mindlin` targets Q/(μP).
    pub q_over_mup: Vec<f64>,
    /// `cattaneo-mindlin` `area` factors r.
    pub cm_eps_t: Vec<f64>,
    /// `cattaneo-mindlin` δ_T/a.
    pub cm_delta_t: Vec<f64>,
}

/// One row (module doc).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FrictionRow {
    /// Case name.
    pub case: String,
    /// The interface rows of a two-body case (`mortar`, `nts-1`).
    pub discretization: Option<String>,
    /// The incline's angle θ in degrees (`inclined-friction`).
    pub theta: Option<f64>,
    /// The element size at the contact over a (`cattaneo-mindlin`).
    #[serde(default)]
    pub h_over_a: Option<f64>,
    /// μ.
    pub mu: f64,
    /// `lagrange`, `augmented`, `penalty`.
    pub method: String,
    /// The tangential rule: `exact`, `augmented`, `constant`, `area`, `delta`.
    pub tangent_rule: String,
    /// `coulomb` or `tresca`.
    pub law: String,
    /// ε_N (force/length; empty for Lagrange).
    pub eps_n: Option<f64>,
    /// ε_T (constant and augmented rows; the area rule's at an interior contact).
    pub eps_t: Option<f64>,
    /// δ_T (length).
    pub delta_t: Option<f64>,
    /// Q/(μP) (Cattaneo–Mindlin).
    pub q_over_mup: Option<f64>,
    /// Numerical stick half-width (Cattaneo–Mindlin).
    pub c_num: Option<f64>,
    /// Analytic stick half-width (Cattaneo–Mindlin).
    pub c_exact: Option<f64>,
    /// Shear traction's L2 error (Cattaneo–Mindlin).
    pub shear_err_l2: Option<f64>,
    /// |T|/N at the first full-slip increment.
    pub onset_ratio: Option<f64>,
    /// The platen's travel there.
    pub onset_travel: Option<f64>,
    /// (onset_travel − Lagrange's)/Lagrange's.
    pub onset_travel_err: Option<f64>,
    /// max |T − T_lagrange| / (μ N_lagrange).
    pub history_err: Option<f64>,
    /// The patch test's largest |p_i − p̄|/p̄ over the rows (p̄ their mean).
    pub pressure_err_max: Option<f64>,
    /// The patch test's largest |τ_i − τ̄|/τ̄ over the rows.
    pub shear_err_max: Option<f64>,
    /// Load increments.
    pub increments: usize,
    /// Newton steps, all increments.
    pub newton_iters: usize,
    /// Linear solves.
    pub factorizations: usize,
    /// Every increment converged.
    pub converged: bool,
    /// cond₂ of the last increment's system with a contact in stick.
    pub cond2_system: Option<f64>,
    /// Its lower bound.
    pub cond2_lo: Option<f64>,
    /// Its upper bound.
    pub cond2_hi: Option<f64>,
    /// Whether the bracket is proven.
    pub cond2_bounds_proven: Option<bool>,
    /// The cond₂ route.
    pub cond_route: Option<String>,
    /// GMRES(30) iterations with Jacobi, from x₀ = 0, to ‖u_k − u*‖∞ ≤ 1e-6‖u*‖∞ on the
    /// penalty's tangent J of the increment `cond2_system` is of, b = J·u (u that increment's
    /// displacements; u* the solution of the stored J x = b refined in double-double); empty
    /// for Lagrange and `augmented`, whose systems are not what a user's Krylov solver sees.
    pub gmres_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the error within [`GMRES_MAX_ITERS`].
    pub gmres_iters_jacobi_to_err_converged: Option<bool>,
    /// Warnings, `; `-joined.
    pub warnings: String,
}

/// The restart m of the GMRES counts.
pub const GMRES_RESTART: usize = 30;
/// Their iteration limit.
pub const GMRES_MAX_ITERS: usize = 5000;

/// GMRES(m)-Jacobi iterations to the fixed error of u on `sol`'s tangent (the row's doc);
/// `None` where the system is not a penalty's or cannot be preconditioned.
fn gmres_count(sol: &FrictionSolution) -> Result<Option<(usize, bool)>> {
    use crate::linalg::krylov::{gmres, Stop};
    use crate::linalg::{precond::Jacobi, refine, Factorization};
    let (Some(j), Some(k)) = (&sol.tangent, sol.tangent_increment) else {
        return Ok(None);
    };
    if sol.method != "penalty" {
        return Ok(None);
    }
    let u = &sol.increments[k].u;
    let b = j.matvec(u);
    let fac = Factorization::new(j, j.is_symmetric())?;
    let x0 = fac.solve(&b);
    let reference: Vec<f64> = refine::refine(j, &b, &fac, &x0)
        .x
        .iter()
        .map(|v| v.to_f64())
        .collect();
    let a = j.to_sparse();
    let Ok(pre) = Jacobi::new(a.as_ref()) else {
        return Ok(None);
    };
    let stop = Stop::ErrorOfU {
        reference: &reference,
        target: crate::metrics::solver::DEFAULT_ERR_TARGET,
    };
    let (_, run) = gmres(a.as_ref(), &pre, &b, GMRES_RESTART, stop, GMRES_MAX_ITERS);
    Ok(Some((run.iterations, run.converged)))
}

/// `"16x8"` → (16, 8).
fn mesh(text: &str) -> Result<(usize, usize)> {
    let bad = || {
        Error::out_of_range(
            "--mesh",
            text,
            format!("NXxNY with NX ≥ 2, NY ≥ 1, NX·NY ≤ {MAX_ELEMENTS} (e.g. 16x8)"),
        )
    };
    let (a, b) = text.split_once('x').ok_or_else(bad)?;
    let (nx, ny) = (a.parse().map_err(|_| bad())?, b.parse().map_err(|_| bad())?);
    if nx < 2 || ny < 1 || nx * ny > MAX_ELEMENTS {
        return Err(bad());
    }
    Ok((nx, ny))
}

/// The binary's defaults (its flags' default values, the one place they are written).
impl Default for BenchConfig {
    fn default() -> Self {
        #[derive(clap::Parser)]
        struct Defaults {
            #[command(flatten)]
            flags: Flags,
        }
        let d = <Defaults as clap::Parser>::parse_from(["friction_bench"]);
        BenchConfig::from_flags(&d.flags).expect("the flags' defaults are valid")
    }
}

impl BenchConfig {
    /// The configuration of `flags`, each value checked.
    pub fn from_flags(f: &Flags) -> Result<BenchConfig> {
        for c in &f.cases {
            if !CASES.contains(&c.as_str()) {
                return Err(Error::unknown("friction case", c, CASES, ""));
            }
        }
        for &mu in &f.mu {
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(Error::out_of_range("--mu", mu, "finite and ≥ 0"));
            }
        }
        for &v in f.eps_t.iter().chain(&f.delta_t) {
            Error::positive("--eps-t / --delta-t entry", v)?;
        }
        if !(1..=MAX_STEPS).contains(&f.steps) {
            return Err(Error::out_of_range(
                "--steps",
                f.steps,
                format!("in 1..={MAX_STEPS}"),
            ));
        }
        Error::distinct("--mu", &f.mu)?;
        Error::distinct("--cases", &f.cases)?;
        if f.cases.iter().any(|c| c == cattaneo::CASE) {
            for &mu in &f.mu {
                check_mu(mu).map_err(|e| e.for_flag("--mu"))?;
            }
            for &h in &f.cm_levels {
                check_h_over_a(h).map_err(|e| e.for_flag("--cm-levels"))?;
            }
            for &q in &f.q_over_mup {
                check_ratio(q).map_err(|e| e.for_flag("--q-over-mup"))?;
            }
            for &v in f.cm_eps_t.iter().chain(&f.cm_delta_t) {
                Error::positive("--cm-eps-t / --cm-delta-t entry", v)?;
            }
            Error::distinct("--cm-levels", &f.cm_levels)?;
            Error::distinct("--q-over-mup", &f.q_over_mup)?;
        }
        let law = match f.law.as_str() {
            "coulomb" => Law::Coulomb,
            "tresca" => Law::Tresca,
            other => return Err(Error::unknown("--law", other, &["coulomb", "tresca"], "")),
        };
        Ok(BenchConfig {
            cases: f.cases.clone(),
            mu: f.mu.clone(),
            mesh: mesh(&f.mesh)?,
            steps: f.steps,
            eps_n: Error::positive("--eps-n", f.eps_n)?,
            eps_t: f.eps_t.clone(),
            delta_t: f.delta_t.clone(),
            law,
            cm_levels: f.cm_levels.clone(),
            q_over_mup: f.q_over_mup.clone(),
            cm_eps_t: f.cm_eps_t.clone(),
            cm_delta_t: f.cm_delta_t.clone(),
        })
    }

    /// Every scenario of one case and μ (the patch test once per discretization).
    fn scenarios(&self, case: &str, mu: f64) -> Vec<Scenario> {
        match case {
            "sliding-block" => vec![Scenario::Block(SlidingBlock {
                nx: self.mesh.0,
                ny: self.mesh.1,
                mu,
                steps: self.steps,
                ..SlidingBlock::default()
            })],
            cattaneo::CASE => Vec::new(),
            "inclined-friction" => vec![Scenario::Incline(InclinedFriction {
                theta_deg: INCLINE_THETA,
                nx: self.mesh.0,
                ny: self.mesh.1,
                mu,
                steps: self.steps,
            })],
            _ => [Discretization::Mortar, Discretization::Nts1]
                .into_iter()
                .map(|d| {
                    Scenario::Patch(PatchFriction {
                        mu,
                        ..PatchFriction::standard(d)
                    })
                })
                .collect(),
        }
    }

    /// Every (method, rule name) for a case with shear modulus `g` and length scale `depth`,
    /// Lagrange first.
    fn methods(&self, g: f64, depth: f64) -> Vec<(FrictionMethod, &'static str)> {
        self.methods_with(g, depth, (&self.eps_t, true), &self.delta_t)
    }

    /// [`Self::methods`] over the ladders `eps_t` (the `area` rule's r; with `constant`
    /// rows ε_T = f·G where `.1`) and `delta_t` (δ_T over `depth`).
    fn methods_with(
        &self,
        g: f64,
        depth: f64,
        (eps_t, constant): (&[f64], bool),
        delta_t: &[f64],
    ) -> Vec<(FrictionMethod, &'static str)> {
        let mut m = vec![
            (FrictionMethod::Lagrange, "exact"),
            (
                FrictionMethod::Augmented {
                    eps_n: 10.0 * g,
                    eps_t: 10.0 * g,
                    tol: 1e-10 * depth,
                },
                "augmented",
            ),
        ];
        let pen = |tangent| FrictionMethod::Penalty {
            normal: NormalRule::Area(self.eps_n),
            tangent,
            law: self.law,
        };
        for &f in eps_t {
            if constant {
                m.push((pen(TangentRule::Constant(f * g)), "constant"));
            }
            m.push((pen(TangentRule::Area(f)), "area"));
        }
        for &d in delta_t {
            m.push((pen(TangentRule::Delta(d * depth)), "delta"));
        }
        m
    }
}

/// One frictional model of the bench.
#[derive(Clone, Copy, Debug)]
enum Scenario {
    Block(SlidingBlock),
    Patch(PatchFriction),
    Incline(InclinedFriction),
}

impl Scenario {
    fn case(&self) -> &'static str {
        match self {
            Scenario::Block(_) => "sliding-block",
            Scenario::Patch(_) => "patch-two-body-friction",
            Scenario::Incline(_) => "inclined-friction",
        }
    }

    fn mu(&self) -> f64 {
        match self {
            Scenario::Block(b) => b.mu,
            Scenario::Patch(p) => p.mu,
            Scenario::Incline(i) => i.mu,
        }
    }

    /// The problem, and the patch test's traction reader.
    fn build(&self) -> Result<(friction::FrictionProblem, Option<PatchProblem>)> {
        match self {
            Scenario::Block(b) => Ok((b.problem()?, None)),
            Scenario::Incline(i) => Ok((i.problem()?, None)),
            Scenario::Patch(p) => {
                let pp = p.problem()?;
                Ok((pp.problem.clone(), Some(pp)))
            }
        }
    }

    /// The length δ_T is given in units of.
    fn depth(&self) -> f64 {
        match self {
            Scenario::Block(b) => b.press * HEIGHT,
            Scenario::Patch(p) => p.squeeze,
            Scenario::Incline(_) => PRESS * INCLINE_HEIGHT,
        }
    }

    /// The platen's travel at increment k (the sliding block's).
    fn travel_at(&self, k: usize) -> Option<f64> {
        match self {
            Scenario::Block(b) => Some(b.travel_at(k)),
            Scenario::Patch(_) | Scenario::Incline(_) => None,
        }
    }
}

/// The row of one solution of `sc`, `reference` Lagrange's of the same scenario.
fn row(
    sc: &Scenario,
    (method, rule): &(FrictionMethod, &'static str),
    sol: &FrictionSolution,
    reference: Option<&FrictionSolution>,
    (p, patch): (&friction::FrictionProblem, Option<&PatchProblem>),
) -> FrictionRow {
    let onset = sol.onset();
    let travel = onset.and_then(|(k, _)| sc.travel_at(k));
    // A reference that did not converge (or a run cut short) measures nothing.
    let reference = reference.filter(|r| r.converged && r.increments.len() == sol.increments.len());
    let ref_travel = reference
        .and_then(|r| r.onset())
        .and_then(|(k, _)| sc.travel_at(k));
    let history_err = reference.map(|r| {
        let nmax = r
            .increments
            .iter()
            .map(|i| i.normal_force())
            .fold(0.0, f64::max);
        let d = sol
            .increments
            .iter()
            .zip(&r.increments)
            .map(|(a, b)| (a.tangential_force() - b.tangential_force()).abs())
            .fold(0.0, f64::max);
        d / (sc.mu() * nmax)
    });
    let cond = sol.tangent.as_ref().map(conditioning::cond2);
    let mut warnings = sol.warnings.clone();
    if reference.is_none() {
        warnings
            .push("no converged Lagrange reference: history and onset errors left empty".into());
    }
    if let Some(Err(e)) = &cond {
        warnings.push(format!("cond2 unavailable: {e}"));
    }
    let cond = cond.and_then(|c| c.ok());
    let gm = gmres_count(sol).unwrap_or_else(|e| {
        warnings.push(format!("gmres count unavailable: {e}"));
        None
    });
    let (eps_t, delta_t, eps_n) = match method {
        FrictionMethod::Lagrange => (None, None, None),
        FrictionMethod::Augmented { eps_n, eps_t, .. } => (Some(*eps_t), None, Some(*eps_n)),
        FrictionMethod::Penalty { tangent, .. } => {
            let en = sol.eps_n.first().copied();
            match *tangent {
                TangentRule::Constant(e) => (Some(e), None, en),
                // The area rule's ε_T at an interior contact (the edges have half its area).
                TangentRule::Area(r) => (Some(p.area_penalty(r, p.m() / 2)), None, en),
                TangentRule::Delta(d) => (None, Some(d), en),
            }
        }
    };
    let law = match method {
        FrictionMethod::Penalty { law, .. } => *law,
        _ => Law::Coulomb,
    };
    let (pressure_err_max, shear_err_max) = patch.map(|pp| pp.traction_errors(sol)).unzip();
    FrictionRow {
        case: sc.case().into(),
        discretization: match sc {
            Scenario::Patch(pf) => Some(pf.disc.name().into()),
            _ => None,
        },
        theta: match sc {
            Scenario::Incline(i) => Some(i.theta_deg),
            _ => None,
        },
        h_over_a: None,
        mu: sc.mu(),
        method: method.name().into(),
        tangent_rule: (*rule).into(),
        law: format!("{law:?}").to_lowercase(),
        eps_n,
        eps_t,
        delta_t,
        q_over_mup: None,
        c_num: None,
        c_exact: None,
        shear_err_l2: None,
        onset_ratio: onset.map(|o| o.1),
        onset_travel: travel,
        onset_travel_err: travel.zip(ref_travel).map(|(a, b)| (a - b) / b),
        history_err,
        pressure_err_max,
        shear_err_max,
        increments: sol.increments.len(),
        newton_iters: sol.newton_iters(),
        factorizations: sol.factorizations,
        converged: sol.converged,
        cond2_system: cond.as_ref().map(|c| c.cond2),
        cond2_lo: cond.as_ref().map(|c| c.cond2_lo),
        cond2_hi: cond.as_ref().map(|c| c.cond2_hi),
        cond2_bounds_proven: cond.as_ref().map(|c| c.bounds_proven),
        cond_route: cond.as_ref().map(|c| c.route.name().to_string()),
        gmres_iters_jacobi_to_err: gm.map(|g| g.0),
        gmres_iters_jacobi_to_err_converged: gm.map(|g| g.1),
        warnings: warnings.join("; "),
    }
}

/// `friction::solve`, a numerical failure (a singular system, …) kept as an unconverged
/// solution with no increment and the error as its warning: one method's failure is its row,
/// not the end of the run. Bad input stays an error.
fn solved_or_failed(p: &friction::FrictionProblem, m: &FrictionMethod) -> Result<FrictionSolution> {
    match friction::solve(p, m) {
        Err(e) if !e.is_input() => Ok(FrictionSolution::failed(m.name(), &e)),
        other => other,
    }
}

/// Runs every (case, μ, method) of `cfg`, one progress step per row (`cattaneo-mindlin` last).
pub fn run(
    cfg: &BenchConfig,
    progress: &Progress,
    checkpoints: Option<&Checkpoints>,
) -> Result<Vec<FrictionRow>> {
    let scenarios: Vec<Scenario> = cfg
        .cases
        .iter()
        .flat_map(|c| cfg.mu.iter().flat_map(move |&mu| cfg.scenarios(c, mu)))
        .collect();
    let per = cfg.methods(1.0, 1.0).len();
    progress.set_total(scenarios.len() * per);
    let rows: Vec<Vec<FrictionRow>> = scenarios
        .par_iter()
        .map(|sc| {
            let (p, patch) = sc.build()?;
            let methods = cfg.methods(p.shear_modulus, sc.depth());
            let reference = solved_or_failed(&p, &methods[0].0)?;
            let mut rows = Vec::with_capacity(methods.len());
            for m in &methods {
                let sol = match m.0 {
                    FrictionMethod::Lagrange => reference.clone(),
                    _ => solved_or_failed(&p, &m.0)?,
                };
                rows.push(row(sc, m, &sol, Some(&reference), (&p, patch.as_ref())));
                progress.step(&format!(
                    "friction_bench: {}, μ = {}, {} {}",
                    sc.case(),
                    sc.mu(),
                    m.0.name(),
                    m.1
                ));
            }
            Ok(rows)
        })
        .collect::<Result<_>>()?;
    let mut rows: Vec<FrictionRow> = rows.into_iter().flatten().collect();
    if cfg.cases.iter().any(|c| c == cattaneo::CASE) {
        rows.extend(cattaneo::rows(
            cfg,
            progress,
            scenarios.len() * per,
            checkpoints,
        )?);
    }
    Ok(rows)
}

/// The study as the shared entry runs it.
pub struct FrictionBench;

impl Study for FrictionBench {
    const NAME: &'static str = "friction_bench";
    const ABOUT: &'static str =
        "Coulomb friction: every tangential penalty rule against the exact law (sliding block, two-body patch test, inclined block)";
    const PROGRESS: &'static str = "friction_bench (runs)";
    const DEFAULT_OUT: &'static str = "results/friction_bench";
    const RESUMABLE: bool = true;
    type Flags = Flags;
    type Config = BenchConfig;
    type Record = Vec<FrictionRow>;

    fn config(flags: &Flags) -> Result<BenchConfig> {
        BenchConfig::from_flags(flags)
    }

    /// Runs with the checkpoints of `OUT/cattaneo-mindlin/` (reused with `--resume`).
    fn run(cfg: &BenchConfig, ctx: &RunContext) -> Result<Vec<FrictionRow>> {
        let checkpoints = Checkpoints::new(ctx.out, cattaneo::CASE, cfg, ctx.resume)?;
        run(cfg, ctx.progress, Some(&checkpoints))
    }

    fn save(
        out: &Path,
        cfg: &BenchConfig,
        rows: &Vec<FrictionRow>,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        let fields = serde_json::json!({ "config": cfg, "max_newton": friction::MAX_NEWTON });
        crate::study::shape::save_rows(out, provenance, fields, rows)?;
        Checkpoints::remove_in(out, cattaneo::CASE)
    }

    fn load(out: &Path) -> Result<Vec<FrictionRow>> {
        crate::study::shape::load_rows(out, Self::NAME)
    }

    fn figures(rows: &Vec<FrictionRow>) -> Result<Vec<Drawing>> {
        let mut d = figures(rows);
        d.extend(cattaneo::figures(rows));
        Ok(d)
    }

    fn report(rows: &Vec<FrictionRow>) -> String {
        // `cattaneo::table` picks its own rows; the other cases' table the rest.
        let other: Vec<FrictionRow> = rows
            .iter()
            .filter(|r| r.case != cattaneo::CASE)
            .cloned()
            .collect();
        let mut t = if other.is_empty() {
            String::new()
        } else {
            table(&other)
        };
        t.push_str(&cattaneo::table(rows));
        t.push_str(&format!("\nrows per method:\n{}", tally(rows).text(100)));
        t
    }

    /// Exit status 4 where a method (with its tangential rule) failed on every row it ran.
    fn failure(rows: &Vec<FrictionRow>) -> Option<String> {
        tally(rows).all_failed()
    }

    fn after_help() -> String {
        "Writes friction_bench.csv, friction_bench.json (rows with provenance) and the figures; \
         the Cattaneo–Mindlin case keeps each finished mesh and μ in OUT/cattaneo-mindlin/ until \
         then (--resume reuses them).\nExit status: 0 ok, 2 bad input, 4 a method (with its \
         tangential rule) failed on every row it ran."
            .into()
    }
}
