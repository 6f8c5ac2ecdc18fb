//! `penalty_scaling`: how a penalty's error and the conditioning it causes scale with the
//! mesh size h when the contact rows couple DOFs — the figure a user needs
//! to choose ε on a refined mesh.
//!
//! **Case.** The two-body contact patch test ([`crate::model::two_body`]): a lower block
//! W × H₁ = 1 × 1 (E₁ = 210e3, ν₁ = 0.3) under an upper block 1 × 0.5 (E₂ = 70e3,
//! ν₂ = 0.33), squeezed by w = 1e-3; level l meshes the lower block with `r₁·2^l` elements
//! each way and the upper one with `r₂·2^l` across and `⌈r₂·2^l/2⌉` up (`--ratio r₁:r₂`,
//! default 4:7: the interface meshes never match). h = W/(r₂·2^l), the slave (upper)
//! element size, halves from level to level. The exact solution is uniform compression
//! ([`two_body::exact_displacements`]).
//!
//! **Rules**, per discretization (`mortar`, `nts-1`, `nts-2`) and level:
//! - `lagrange` (schedule `exact`): the reference of the penalty error (it refuses `nts-2`,
//!   whose two passes' rows are dependent: that discretization has no reference);
//! - `constant` with ε per unit contact length (pressure per penetration, as FEBio, Abaqus
//!   and MOOSE define it; [`crate::strategy::constant`]) on two schedules, for each
//!   `ε_rel` of `--eps-rel`, with E* = 1/(1/E₁* + 1/E₂*) the pair's contact modulus:
//!   - `eps-fixed`: ε = ε_rel·E*/h₀ on every level (a penalty chosen on the coarsest mesh
//!     and kept as the mesh is refined);
//!   - `eps-e-over-h`: ε = ε_rel·E*/h (FEBio's automatic penalty ε·E·A/V with A/V = 1/h on
//!     square elements; MOOSE's penalty normalized by the nodal area is the same scaling);
//!
//!   both equal on level 0;
//! - the δ-rules of `--delta-methods` (default `spring`, `paper`, `condensed`) at
//!   δ = `δ_rel`·w on every level (schedule `delta`).
//!
//! **Measures** per row: `err_u = ‖u − u_exact‖∞ / w` (against the analytic field: the patch
//! test's error and the penalty's together); `err_penalty = ‖u − u_L‖∞ / w` against Lagrange
//! on the same discretization and mesh (the penalty's own error); `err_pressure =
//! max_c |p_c − p|/p` over the rows' pressures ([`Indentation::pressures`]; `nts-2`: the
//! nodal pressures of both bodies' interface nodes, its rows' shares of a force not being
//! defined); the largest penetration; cond₂ of the final system and of its Jacobi-scaled
//! form (certified, to `--cond-tol`), CG iterations with Jacobi and IC(0) (MINRES for
//! Lagrange) and the forward error of the direct solve ([`crate::metrics::solver`]), Lagrange's
//! on every level (the certified sparse saddle route for coupled rows). Slopes against h are fitted over
//! the levels ([`record::slopes`]): cond ∝ h^−p, error ∝ h^s.
//!
//! What to expect (derivation): the penalty adds a compliance g/p = 1/ε to the contact, so
//! the penalty's relative error is ≈ (1/ε)/(H₁/E₁* + H₂/E₂*): constant in h for `eps-fixed`,
//! ∝ h for `eps-e-over-h`, ≈ δ/w for the δ-rules; the largest eigenvalue of the penalized
//! system grows like ε·h (the nodal stiffness ε ω_c), the smallest like E h² (K's own), so
//! cond₂ ∝ h^−1 for `eps-fixed`, ∝ h^−2 (K's own slope) for `eps-e-over-h` and wherever
//! the penalty term stays below K's largest eigenvalue.

mod figures;
pub mod record;
mod report;

pub use record::{slopes, Row, Slope};

use crate::error::{Error, Result};
use crate::metrics::{self, solver::SolverOptions, MetricSet};
use crate::model::elasticity::Indentation;
use crate::model::two_body::{self, Discretization, TwoBlocks};
use crate::progress::Progress;
use crate::strategy::{self, registry, Knob, Method, Strategy};
use crate::study::shape::{Drawing, RunContext, Study};
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// The squeeze w of the top face.
pub const SQUEEZE: f64 = 1e-3;

/// Most elements across a block on the finest level (the upper block's mesh at 256 across
/// has ≈ 66 000 DOFs beside the lower one's).
pub const MAX_ACROSS: usize = 256;

/// Largest ε_rel: ε = ε_rel·E*/h beyond 1/ε_mach·E*/h leaves K's entries (≈ E*) below the
/// rounding of the penalty's.
pub const MAX_EPS_REL: f64 = 1e15;

/// What to run.
#[derive(Clone, Debug, Serialize)]
pub struct PenaltyScalingConfig {
    /// Interface discretizations.
    pub discretizations: Vec<Discretization>,
    /// Mesh levels (h halving), 2–7.
    pub levels: usize,
    /// Elements across the lower and the upper block on level 0 (r₁, r₂).
    pub ratio: (usize, usize),
    /// ε of `constant` over E*/h₀ (`eps-fixed`) and over E*/h (`eps-e-over-h`).
    pub eps_rel: Vec<f64>,
    /// The δ-rules (rules whose knob is δ; saved by name).
    #[serde(serialize_with = "registry::serialize_names")]
    pub delta_methods: Vec<&'static Strategy>,
    /// δ over the squeeze w.
    pub delta_rel: f64,
    /// τ of the Krylov runs.
    pub krylov_tol: f64,
    /// Relative accuracy asked of each cond₂.
    pub cond_tol: f64,
}

impl Default for PenaltyScalingConfig {
    fn default() -> Self {
        PenaltyScalingConfig {
            discretizations: vec![
                Discretization::Mortar,
                Discretization::Nts1,
                Discretization::Nts2,
            ],
            levels: 5,
            ratio: (4, 7),
            eps_rel: vec![1.0, 100.0],
            delta_methods: vec![
                &strategy::spring::STRATEGY,
                &strategy::paper::STRATEGY,
                &strategy::condensed::STRATEGY,
            ],
            delta_rel: 1e-2,
            krylov_tol: metrics::solver::DEFAULT_TOL,
            cond_tol: 1e-6,
        }
    }
}

impl PenaltyScalingConfig {
    /// Checks the ranges (each error names its flag).
    pub fn validate(&self) -> Result<()> {
        if self.discretizations.is_empty() {
            let valid: Vec<&str> = Discretization::ALL.iter().map(|d| d.name()).collect();
            return Err(Error::none_given(
                "--discretizations",
                format!(" (valid: {})", valid.join(", ")),
            ));
        }
        if !(2..=7).contains(&self.levels) {
            return Err(Error::out_of_range("--levels", self.levels, "in 2..=7"));
        }
        let (r1, r2) = self.ratio;
        if r1 == 0 || r2 == 0 {
            return Err(Error::out_of_range(
                "--ratio",
                format!("{r1}:{r2}"),
                "R1:R2 with both ≥ 1 (at least one element across each block)",
            ));
        }
        let finest = r1.max(r2).checked_mul(1 << (self.levels - 1));
        if finest.is_none_or(|f| f > MAX_ACROSS) {
            return Err(Error::out_of_range(
                format!(
                    "--ratio {r1}:{r2} with --levels {}: the finest level's elements across",
                    self.levels
                ),
                finest.map_or("more than usize::MAX".into(), |f| f.to_string()),
                format!("at most {MAX_ACROSS} (lower either)"),
            ));
        }
        Error::distinct(
            "--discretizations",
            self.discretizations.iter().map(|d| d.name()),
        )?;
        Error::distinct("--delta-methods", self.delta_methods.iter().map(|s| s.name))?;
        Error::distinct("--eps-rel", &self.eps_rel)?;
        for &e in &self.eps_rel {
            if !(e.is_finite() && e > 0.0 && e <= MAX_EPS_REL) {
                return Err(Error::out_of_range(
                    "--eps-rel",
                    e,
                    format!(
                        "in (0, {MAX_EPS_REL:e}] (above, K's entries fall below the rounding \
                         of the penalty's)"
                    ),
                ));
            }
        }
        for (flag, v) in [
            ("--delta-rel", self.delta_rel),
            ("--krylov-tol", self.krylov_tol),
            ("--cond-tol", self.cond_tol),
        ] {
            Error::fraction(flag, v)?;
        }
        Ok(())
    }

    /// The two blocks of level `l` (module doc).
    pub fn blocks(&self, l: usize) -> TwoBlocks {
        let (r1, r2) = (self.ratio.0 << l, self.ratio.1 << l);
        TwoBlocks::steel_under_aluminium(1.0, (1.0, 0.5), (r1, r1), (r2, r2.div_ceil(2)))
    }

    /// The contact modulus E* = 1/(1/E₁* + 1/E₂*) of the pair.
    pub fn e_star(&self) -> f64 {
        let b = self.blocks(0);
        1.0 / (1.0 / b.lower.contact_modulus() + 1.0 / b.upper.contact_modulus())
    }

    /// The slave element size h of level `l`.
    pub fn h(&self, l: usize) -> f64 {
        1.0 / (self.ratio.1 << l) as f64
    }

    /// The penalty jobs of a level: `(method, schedule, ε_rel)` (Lagrange runs apart), through
    /// the one expansion of knob grids ([`KnobGrid::points`]): `constant` at each relative ε
    /// on the coarsest level's h (`eps-fixed`) and on this level's (`eps-e-over-h`), then the
    /// δ-methods at δ = `delta_rel` times the squeeze.
    fn jobs(&self, l: usize) -> Vec<(Method, &'static str, Option<f64>)> {
        use crate::study::grid::{KnobGrid, Level};
        let e = self.e_star();
        let mut out = Vec::new();
        for &r in &self.eps_rel {
            let grid = KnobGrid {
                eps: vec![
                    Level::absolute(r * e / self.h(0)),
                    Level::absolute(r * e / self.h(l)),
                ],
                ..KnobGrid::default()
            };
            let points = grid.points(&[&strategy::constant::STRATEGY]);
            out.extend(
                points
                    .into_iter()
                    .zip(["eps-fixed", "eps-e-over-h"])
                    .map(|(p, schedule)| (p.method, schedule, Some(r))),
            );
        }
        let deltas = KnobGrid {
            deltas: vec![Level::absolute(self.delta_rel * SQUEEZE)],
            ..KnobGrid::default()
        };
        // (Validated in `config`: every δ-method takes δ.)
        out.extend(
            deltas
                .points(&self.delta_methods)
                .into_iter()
                .map(|p| (p.method, "delta", None)),
        );
        out
    }
}

/// One (discretization, level): the scene, the exact field and Lagrange's solution.
struct Level {
    disc: Discretization,
    index: usize,
    h: f64,
    scene: Indentation,
    exact: Vec<f64>,
    exact_p: f64,
    u_lagrange: Option<Vec<f64>>,
}

/// Runs every discretization's levels (one progress step per level; the penalty jobs of a
/// level in parallel, rows in job order: the same rows for any number of threads, but for
/// the timing columns).
pub fn run(cfg: &PenaltyScalingConfig, progress: &Progress) -> Result<Vec<Row>> {
    cfg.validate()?;
    progress.set_total(cfg.discretizations.len() * cfg.levels);
    let mut rows = Vec::new();
    for &disc in &cfg.discretizations {
        for l in 0..cfg.levels {
            let blocks = cfg.blocks(l);
            let scene = two_body::patch(&blocks, SQUEEZE, disc)?
                .with_surface_of(blocks.width, blocks.h_lower + blocks.h_upper)?;
            let mut level = Level {
                disc,
                index: l,
                h: cfg.h(l),
                exact: two_body::exact_displacements(&blocks, SQUEEZE)?,
                exact_p: blocks.exact_pressure(SQUEEZE),
                scene,
                u_lagrange: None,
            };
            let lagrange = row_of(cfg, &level, Method::lagrange(), "exact", None);
            level.u_lagrange = lagrange.1;
            let jobs = cfg.jobs(l);
            let mut level_rows = vec![lagrange.0];
            level_rows.extend(
                jobs.par_iter()
                    .map(|&(m, schedule, eps_rel)| row_of(cfg, &level, m, schedule, eps_rel).0)
                    .collect::<Vec<_>>(),
            );
            rows.extend(level_rows);
            progress.step(&format!(
                "{} level {l}: h = {:.4}, {} DOFs, {} rows",
                disc.name(),
                level.h,
                level.scene.problem.n(),
                level.scene.problem.m()
            ));
        }
    }
    progress.finish();
    Ok(rows)
}

/// ‖a − b‖∞ / w.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / SQUEEZE
}

/// One rule on one level: its row and its u (None where the solve failed).
fn row_of(
    cfg: &PenaltyScalingConfig,
    level: &Level,
    m: Method,
    schedule: &str,
    eps_rel: Option<f64>,
) -> (Row, Option<Vec<f64>>) {
    let problem = &level.scene.problem;
    let mut row = Row {
        discretization: level.disc.name().into(),
        level: level.index,
        h: level.h,
        n_dofs: problem.n(),
        n_rows: problem.m(),
        method: m.name().into(),
        schedule: schedule.into(),
        eps_rel,
        knob_value: m.knobs().eps.or(m.knobs().delta),
        ..Row::default()
    };
    let t0 = std::time::Instant::now();
    let sol = match strategy::solve(problem, m) {
        Ok(s) => s,
        Err(e) => {
            row.note = e.to_string();
            return (row, None);
        }
    };
    row.seconds_solve = t0.elapsed().as_secs_f64();
    // The rule's own warnings (e.g. spring's penalties clipped to 0) say what it did.
    row.note = sol.warnings.join("; ");
    row.iterations = Some(sol.stats.iterations);
    row.max_penetration = Some(sol.max_penetration);
    row.err_u = Some(distance(&sol.u, &level.exact));
    row.err_penalty = level.u_lagrange.as_ref().map(|ul| distance(&sol.u, ul));
    let p = level.scene.pressures(&sol.u);
    if p.iter().all(|v| v.is_finite()) {
        row.err_pressure = Some(
            p.iter()
                .map(|v| (v - level.exact_p).abs() / level.exact_p)
                .fold(0.0, f64::max),
        );
    }
    let t1 = std::time::Instant::now();
    let set = MetricSet {
        cond: true,
        det: false,
        cond_tol: Some(cfg.cond_tol),
    };
    match metrics::compute(problem, &sol, set) {
        Ok(c) => row.cond2_system = c.cond2_system.map(|c| c.cond2),
        Err(e) => row.note = format!("cond₂: {e}"),
    }
    let opts = SolverOptions {
        tol: cfg.krylov_tol,
        max_iters: None,
        err_target: metrics::solver::DEFAULT_ERR_TARGET,
        cond_tol: Some(cfg.cond_tol),
    };
    match metrics::solver::compute(problem, &sol, opts) {
        Ok(c) => {
            row.cond2_jacobi = c.cond2_jacobi.map(|r| r.cond2);
            row.pcg_iters_jacobi_to_err = c.pcg_jacobi.iters_reached();
            row.pcg_iters_ic0_to_err = c.pcg_ic0.iters_reached();
            row.minres_iters_to_err = c.minres.iters_reached();
            row.forward_err_u = c.forward_err_u;
            if !c.unavailable.is_empty() {
                let sep = if row.note.is_empty() { "" } else { "; " };
                row.note = format!("{}{sep}{}", row.note, c.unavailable.join("; "));
            }
        }
        Err(e) => row.note = format!("solver metrics: {e}"),
    }
    row.seconds_metrics = t1.elapsed().as_secs_f64();
    (row, Some(sol.u))
}

/// The `penalty_scaling` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Interface discretizations, comma-separated (mortar, nts-1, nts-2).
    #[arg(long, value_delimiter = ',')]
    discretizations: Option<Vec<String>>,
    /// Mesh levels (h halving), 2–7.
    #[arg(long, default_value_t = 5)]
    levels: usize,
    /// Elements across the lower and the upper block on level 0.
    #[arg(long, default_value = "4:7", value_parser = crate::study::grid::parse_ratio)]
    ratio: (usize, usize),
    /// ε of `constant` over E*/h₀ (eps-fixed) and over E*/h (eps-e-over-h), comma-separated.
    #[arg(long, value_delimiter = ',')]
    eps_rel: Option<Vec<f64>>,
    /// The δ-rules, comma-separated (rules whose knob is δ).
    #[arg(long, value_delimiter = ',')]
    delta_methods: Option<Vec<String>>,
    /// δ over the squeeze w.
    #[arg(long, default_value_t = 1e-2)]
    delta_rel: f64,
    /// τ of the Krylov runs (‖r‖ ≤ τ‖b‖ from x₀ = 0).
    #[arg(long, default_value_t = metrics::solver::DEFAULT_TOL)]
    krylov_tol: f64,
    /// Relative accuracy asked of each cond₂.
    #[arg(long, default_value_t = 1e-6)]
    cond_tol: f64,
}

/// The study as the shared entry runs it ([`crate::study::shape::main`]).
pub struct PenaltyScaling;

/// What `penalty_scaling` saves: its configuration is in the provenance.
pub type Record = Vec<Row>;

impl Study for PenaltyScaling {
    const NAME: &'static str = "penalty_scaling";
    const ABOUT: &'static str =
        "How penalty error and cond₂ scale with h on coupled contact rows (two-body patch test)";
    const PROGRESS: &'static str = "penalty_scaling (levels)";
    const DEFAULT_OUT: &'static str = "results/penalty_scaling";
    type Flags = Flags;
    type Config = PenaltyScalingConfig;
    type Record = Record;

    fn after_help() -> String {
        "Writes penalty_scaling.csv, penalty_scaling.json (rows with provenance), summary.json \
         (slopes) and the figures.\nExit status: 0 ok, 2 bad input."
            .into()
    }

    fn config(f: &Flags) -> Result<PenaltyScalingConfig> {
        let d = PenaltyScalingConfig::default();
        let discretizations = match &f.discretizations {
            None => d.discretizations,
            Some(names) => names
                .iter()
                .map(|n| Discretization::from_name(n).map_err(|e| e.for_flag("--discretizations")))
                .collect::<Result<_>>()?,
        };
        let delta_methods = match &f.delta_methods {
            None => d.delta_methods,
            Some(names) => names
                .iter()
                .map(|n| {
                    let s = registry::lookup(n).map_err(|e| e.for_flag("--delta-methods"))?;
                    if s.knob != Knob::Delta {
                        let takes_delta: Vec<&str> = registry::all()
                            .into_iter()
                            .filter(|s| s.knob == Knob::Delta)
                            .map(|s| s.name)
                            .collect();
                        return Err(Error::out_of_range(
                            "--delta-methods entry",
                            format!("'{n}'"),
                            format!("a method that takes δ ({})", takes_delta.join(", ")),
                        ));
                    }
                    Ok(s)
                })
                .collect::<Result<_>>()?,
        };
        let cfg = PenaltyScalingConfig {
            discretizations,
            levels: f.levels,
            ratio: f.ratio,
            eps_rel: f.eps_rel.clone().unwrap_or(d.eps_rel),
            delta_methods,
            delta_rel: f.delta_rel,
            krylov_tol: f.krylov_tol,
            cond_tol: f.cond_tol,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    fn run(cfg: &PenaltyScalingConfig, ctx: &RunContext) -> Result<Record> {
        run(cfg, ctx.progress)
    }

    fn save(
        out: &Path,
        cfg: &PenaltyScalingConfig,
        rows: &Record,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        let fields = serde_json::json!({
            "config": cfg,
            "e_star": cfg.e_star(),
            "squeeze": SQUEEZE,
        });
        crate::study::shape::save_rows(out, provenance, fields, rows)?;
        crate::provenance::write_json(
            &out.join("summary.json"),
            &serde_json::json!({ "slopes": slopes(rows) }),
        )
    }

    fn load(out: &Path) -> Result<Record> {
        crate::study::shape::load_rows(out, Self::NAME)
    }

    fn figures(rows: &Record) -> Result<Vec<Drawing>> {
        figures::drawings(rows)
    }

    fn report(rows: &Record) -> String {
        report::text(rows)
    }
}
