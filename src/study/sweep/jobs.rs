//! The jobs of one scene (one per strategy and knob value), the work they share, and one row
//! per job.

use super::rows::Row;
use super::{load, LoadedScene, SceneSpec, SweepConfig};
use crate::conditioning::{self, sparse::RitzStarts, Reuse};
use crate::error::Result;
use crate::metrics::{self, solver::SolverOptions, MetricSet};
use crate::strategy::{self, registry, Knob, Method, Prepared};
use crate::system::{Problem, Structure};
use serde::Serialize;
use std::time::Instant;

/// One job of a scene: a method with its knob.
#[derive(Clone, Copy, Debug)]
pub struct Job {
    /// The method.
    pub method: Method,
    /// Relative δ if δ was given relatively.
    pub delta_rel: Option<f64>,
}

/// The jobs of a scene, in row order (lagrange first): every strategy over its knob grid
/// ([`SweepConfig::knob_grid`] at the scene's displacement scale, `augmented` at ε the
/// geometric mean of the constrained diagonal of K; expanded by
/// [`KnobGrid::points`](crate::study::grid::KnobGrid::points)).
pub fn jobs(cfg: &SweepConfig, problem: &Problem, u0: Option<&[f64]>) -> Vec<Job> {
    let scale = u0.map(|u| problem.displacement_scale(u)).unwrap_or(1.0);
    let grid = cfg.knob_grid(scale, problem.mean_constraint_stiffness());
    let mut out = vec![Job {
        method: Method::lagrange(),
        delta_rel: None,
    }];
    out.extend(grid.points(&cfg.methods).into_iter().map(|p| Job {
        method: p.method,
        delta_rel: p.level.rel,
    }));
    out
}

/// What every row of a scene shares, computed once per scene: the problem in its preferred
/// storage, K's factorization and u0, cond₂(K) and log10|det K|, and the jobs.
pub struct SceneWork {
    /// The scene (K in the storage its structure prefers).
    pub scene: LoadedScene,
    /// K's structure.
    pub structure: Structure,
    /// K's factorization and u0 (an error where K is singular; every row then says so).
    pub prepared: Result<Prepared>,
    /// cond₂(K), when requested and available.
    pub cond2_k: Option<f64>,
    /// Its bounds `[cond2_lo, cond2_hi]`.
    pub cond2_k_bounds: Option<(f64, f64)>,
    /// Its whole report (for the rows' proven / within-contract flags).
    pub cond2_k_report: Option<conditioning::CondReport>,
    /// log10|det K|, when requested and available.
    pub log10_det_k: Option<f64>,
    /// K's Ritz vectors of λ_max and λ_min (sparse route): every job's cond₂ starts its
    /// Lanczos runs from them. Shared by the scene's jobs rather than passed from one ε to the
    /// next, so each row is computed the same way whatever the thread count and order.
    pub ritz_k: Option<RitzStarts>,
    /// The jobs, in row order (lagrange first).
    pub jobs: Vec<Job>,
    /// Wall time of each shared step (s): `read`, `prepare`, `cond_k`, `det_k`.
    pub seconds: SetupSeconds,
}

/// Wall time of a scene's shared work (s).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct SetupSeconds {
    /// Building or reading the scene and choosing its storage.
    pub read: f64,
    /// K's factorization and u0.
    pub prepare: f64,
    /// cond₂(K).
    pub cond_k: f64,
    /// log10|det K| (near zero where cond₂(K)'s factorization gave it).
    pub det_k: f64,
}

impl SetupSeconds {
    /// The sum of the four.
    pub fn total(&self) -> f64 {
        self.read + self.prepare + self.cond_k + self.det_k
    }
}

pub(super) fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let v = f();
    (v, t.elapsed().as_secs_f64())
}

/// Loads a scene and does its shared work (cond₂(K) beside the factorization of K, on two
/// threads where the pool has them).
pub fn prepare_scene(spec: &SceneSpec, cfg: &SweepConfig) -> Result<SceneWork> {
    let (loaded, read) = timed(|| {
        load(spec, cfg).map(|mut sc| {
            sc.problem = sc.problem.in_preferred_storage();
            sc
        })
    });
    let scene = loaded?;
    let p = &scene.problem;
    let set = cfg.metric_set();
    let ((prepared, prepare), (cond, cond_k)) = rayon::join(
        || timed(|| Prepared::new(p)),
        || {
            timed(|| {
                set.cond
                    .then(|| {
                        // As `metrics::compute` analyses K: the same Ritz starts, the same rows.
                        let reuse = Reuse {
                            tol: set.cond_tol,
                            ..Reuse::keeping_ritz()
                        };
                        conditioning::cond2_warm(&p.k, reuse).ok()
                    })
                    .flatten()
            })
        },
    );
    let (cond, ritz_k) = cond.unzip();
    let (log10_det_k, det_k) = timed(|| {
        set.det
            .then(|| conditioning::log10_abs_det_after(&p.k, cond.as_ref()).ok())
            .flatten()
    });
    let jobs = jobs(cfg, p, prepared.as_ref().ok().map(|x| x.u0()));
    Ok(SceneWork {
        structure: p.k.structure(),
        prepared,
        cond2_k: cond.map(|c| c.cond2),
        cond2_k_bounds: cond.map(|c| (c.cond2_lo, c.cond2_hi)),
        cond2_k_report: cond,
        log10_det_k,
        ritz_k: ritz_k.flatten(),
        jobs,
        seconds: SetupSeconds {
            read,
            prepare,
            cond_k,
            det_k,
        },
        scene,
    })
}

/// A row with the scene's columns and the job's knobs, before solving.
pub(super) fn base_row(work: &SceneWork, job: Job) -> Row {
    let sc = &work.scene;
    let p = &sc.problem;
    let mut row = Row {
        scene: sc.name.clone(),
        family: sc.family.clone(),
        n: p.n(),
        m: p.m(),
        storage: if p.k.is_sparse() { "sparse" } else { "dense" }.into(),
        nnz: work.structure.nnz,
        half_bandwidth: work.structure.half_bandwidth,
        method: job.method.name().to_string(),
        delta_rel: job.delta_rel,
        cond2_k: work.cond2_k,
        cond2_k_lo: work.cond2_k_bounds.map(|b| b.0),
        cond2_k_hi: work.cond2_k_bounds.map(|b| b.1),
        ..Default::default()
    };
    // The knob values in their columns: ε, f, δ; `augmented`'s tolerance in `delta`.
    let k = job.method.knobs();
    row.eps = k.eps;
    row.factor = k.factor;
    row.delta = k.delta.or(k.tol);
    row
}

/// The row of an `optimal` job on a family outside `optimal_families`: no solve, the reason
/// in `warnings`.
pub(super) fn skipped_row(work: &SceneWork, job: Job, cfg: &SweepConfig) -> Row {
    let mut row = base_row(work, job);
    row.seconds = Some(0.0);
    row.seconds_solve = Some(0.0);
    row.warnings = format!(
        "skipped: optimal runs on the families {:?} only (optimal_families)",
        cfg.optimal_families
            .iter()
            .map(|s| s.name())
            .collect::<Vec<_>>()
    );
    row
}

/// What the lagrange row gives the other rows of its scene.
pub struct Reference {
    /// The exact solution (`error_vs_exact`).
    pub u: Vec<f64>,
    /// The scene's [`Prepared`] with the exact contact set
    /// ([`Prepared::with_contact_set`]): where constant, scaled and condensed start.
    pub prepared: Option<Prepared>,
    /// K_ℱℱ's bottom Ritz vector at the exact contact set ([`metrics::contact_bottom`]):
    /// the bottom start of the penalized rows' cond₂ where it is the better one (with cond₂
    /// asked for and K's Ritz vectors kept).
    pub free_bottom: Option<Vec<f64>>,
}

/// One row: `job` solved on the scene with its metrics; `reference` is what the lagrange row
/// gave (`error_vs_exact`, the contact set), and the lagrange row returns it. A failing solve
/// or metric becomes the row's warning, never an error.
pub fn run_job(
    work: &SceneWork,
    job: Job,
    set: MetricSet,
    solver: Option<SolverOptions>,
    reference: Option<&Reference>,
) -> (Row, Option<Reference>) {
    let t0 = Instant::now();
    let p = &work.scene.problem;
    let mut row = base_row(work, job);
    row.cond_tol = set.cond_tol.filter(|_| set.cond);
    let u_ref = reference.map(|r| r.u.as_slice());
    let prep = reference
        .and_then(|r| r.prepared.as_ref())
        .or(work.prepared.as_ref().ok());
    let (solved, seconds_solve) = timed(|| strategy::solve_prepared(p, job.method, prep));
    row.seconds_solve = Some(seconds_solve);
    let mut u_out = None;
    let is_lagrange = job.method.is(&strategy::lagrange::STRATEGY);
    match solved {
        Ok(sol) => {
            let free_bottom = reference.and_then(|r| r.free_bottom.as_deref());
            let k_ritz = work.ritz_k.as_ref();
            match metrics::compute_with_k(p, &sol, set, work.log10_det_k, k_ritz, free_bottom) {
                Ok(m) => {
                    fill_row(&mut row, work, (&sol, &m), set, solver, u_ref);
                    if is_lagrange {
                        row.error_vs_exact = Some(metrics::relative_error(&sol.u, &sol.u));
                    }
                }
                Err(e) => row.warnings = format!("error: {e}"),
            }
            // The reference is the lagrange solve's, whatever its own metrics gave: as
            // `solve --exact-start`, which needs only the solve.
            if is_lagrange {
                u_out = Some(lagrange_reference(work, sol, set));
            }
        }
        Err(e) => row.warnings = format!("error: {e}"),
    }
    row.seconds = Some(t0.elapsed().as_secs_f64());
    (row, u_out)
}

/// The columns of a row whose solve and metrics succeeded (`error_vs_exact` against `u_ref`,
/// the lagrange reference's solution).
fn fill_row(
    row: &mut Row,
    work: &SceneWork,
    (sol, m): (&strategy::Solution, &metrics::Metrics),
    set: MetricSet,
    solver: Option<SolverOptions>,
    u_ref: Option<&[f64]>,
) {
    let pen: Vec<f64> = sol.penalties.iter().copied().filter(|e| *e > 0.0).collect();
    if !pen.is_empty() {
        row.eps_min = Some(pen.iter().copied().fold(f64::INFINITY, f64::min));
        row.eps_max = Some(pen.iter().copied().fold(0.0, f64::max));
    }
    row.active = sol.stats.active_set_sizes.last().copied();
    row.cond2_system = m.cond2_system.map(|c| c.cond2);
    row.cond2_system_lo = m.cond2_system.map(|c| c.cond2_lo);
    row.cond2_system_hi = m.cond2_system.map(|c| c.cond2_hi);
    row.cond_route = m.cond2_system.map(|c| c.route.name().to_string());
    (row.cond2_bounds_proven, row.cond2_within_contract) =
        conditioning::CondReport::flags([work.cond2_k_report.as_ref(), m.cond2_system.as_ref()]);
    row.log10_det_ratio = m.log10_det_ratio;
    row.max_penetration = Some(sol.max_penetration);
    row.error_vs_exact = u_ref.map(|r| metrics::relative_error(&sol.u, r));
    row.linear_solves = Some(sol.stats.linear_solves);
    row.iterations = Some(sol.stats.iterations);
    if let Some(k) = sol.stats.barrier {
        (row.kappa_initial, row.kappa_final, row.kappa_increases) =
            (Some(k.initial), Some(k.last), Some(k.increases));
    }
    row.converged = Some(sol.stats.converged);
    row.seconds_cond = set.cond.then_some(m.seconds_cond);
    row.seconds_det = set.det.then_some(m.seconds_det);
    row.warnings = metrics::warnings(sol, m).join("; ");
    if let Some(opts) = solver {
        solver_columns(row, &work.scene.problem, sol, opts);
    }
}

/// What the lagrange solve `sol` gives the other rows of its scene: the exact solution, the
/// scene's [`Prepared`] at its contact set, and, where cond₂ is asked for, K's Ritz vectors
/// are kept and another job follows, K_ℱℱ's bottom Ritz vector at that set
/// ([`metrics::contact_bottom`]).
fn lagrange_reference(work: &SceneWork, sol: strategy::Solution, set: MetricSet) -> Reference {
    let p = &work.scene.problem;
    let contact = sol.contact_set();
    let free_bottom = contact
        .as_deref()
        .zip(work.ritz_k.as_ref())
        .filter(|_| set.cond && work.jobs.len() > 1)
        .and_then(|(c, r)| metrics::contact_bottom(p, c, r));
    let prepared = work
        .prepared
        .as_ref()
        .ok()
        .zip(contact)
        .map(|(prep, set)| prep.clone().with_contact_set(set));
    Reference {
        u: sol.u,
        prepared,
        free_bottom,
    }
}

/// The `--metrics solver` columns of a row ([`crate::metrics::solver`]); a failure is
/// appended to `warnings`.
fn solver_columns(
    row: &mut Row,
    p: &crate::system::Problem,
    sol: &strategy::Solution,
    opts: SolverOptions,
) {
    let (c, seconds) = timed(|| metrics::solver::compute(p, sol, opts));
    row.seconds_solver = Some(seconds);
    match c {
        Ok(c) => {
            let m = c.summary();
            row.cond2_jacobi = m.cond2_jacobi;
            row.pcg_iters_jacobi = m.pcg_iters_jacobi;
            row.pcg_iters_ic0 = m.pcg_iters_ic0;
            row.pcg_converged = m.pcg_converged;
            row.minres_iters = m.minres_iters;
            row.pcg_iters_jacobi_to_err = m.pcg_iters_jacobi_to_err;
            row.pcg_iters_jacobi_to_err_converged = m.pcg_iters_jacobi_to_err_converged;
            row.pcg_iters_ic0_to_err = m.pcg_iters_ic0_to_err;
            row.pcg_iters_ic0_to_err_converged = m.pcg_iters_ic0_to_err_converged;
            row.minres_iters_to_err = m.minres_iters_to_err;
            row.minres_iters_to_err_converged = m.minres_iters_to_err_converged;
            row.pcg_iters_amg_scalar_to_err = m.pcg_iters_amg_scalar_to_err;
            row.pcg_iters_amg_scalar_to_err_converged = m.pcg_iters_amg_scalar_to_err_converged;
            row.pcg_iters_amg_nodal_to_err = m.pcg_iters_amg_nodal_to_err;
            row.pcg_iters_amg_nodal_to_err_converged = m.pcg_iters_amg_nodal_to_err_converged;
            row.forward_err_u = m.forward_err_u;
            row.forward_err_force = m.forward_err_force;
            for note in c.unavailable {
                if !row.warnings.is_empty() {
                    row.warnings.push_str("; ");
                }
                row.warnings.push_str(&note);
            }
        }
        Err(e) => {
            if !row.warnings.is_empty() {
                row.warnings.push_str("; ");
            }
            row.warnings.push_str(&format!("solver metrics: {e}"));
        }
    }
}

/// Runs every job of one scene: the shared work, the lagrange reference, then the other jobs
/// as separate work units on the current rayon pool, one task each (rows in job order
/// whatever the thread count). Errors of single jobs become rows with the error in
/// `warnings`; only an unreadable scene is an error.
pub fn run_scene(spec: &SceneSpec, cfg: &SweepConfig) -> Result<(Vec<Row>, SceneWork)> {
    use rayon::prelude::*;
    let work = prepare_scene(spec, cfg)?;
    let set = cfg.metric_set();
    let (first, rest) = work.jobs.split_first().expect("lagrange is always a job");
    let solver = cfg.solver_options();
    let (lag_row, reference) = run_job(&work, *first, set, solver, None);
    let mut rows = Vec::with_capacity(work.jobs.len());
    rows.push(lag_row);
    let others: Vec<Row> = rest
        .par_iter()
        .with_max_len(1)
        .map(|&job| {
            let skip = job.method.is(&strategy::optimal::STRATEGY)
                && !cfg
                    .optimal_families
                    .iter()
                    .any(|s| s.name() == work.scene.family);
            if skip {
                skipped_row(&work, job, cfg)
            } else {
                run_job(&work, job, set, solver, reference.as_ref()).0
            }
        })
        .collect();
    rows.extend(others);
    set_ratios_to_optimal(&mut rows);
    Ok((rows, work))
}

/// Fills `cond_ratio_to_optimal` on one scene's rows: every δ-driven row (spring, paper,
/// condensed, optimal) whose δ has an `optimal` row with a cond₂ gets cond₂ / cond₂(optimal).
pub fn set_ratios_to_optimal(rows: &mut [Row]) {
    let optima: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.method == strategy::optimal::STRATEGY.name)
        .filter_map(|r| Some((r.delta?, r.cond2_system?)))
        .filter(|(_, c)| c.is_finite() && *c > 0.0)
        .collect();
    for r in rows.iter_mut() {
        if registry::find(&r.method).is_none_or(|s| s.knob != Knob::Delta) {
            continue;
        }
        let (Some(d), Some(c)) = (r.delta, r.cond2_system) else {
            continue;
        };
        if let Some(&(_, best)) = optima.iter().find(|(od, _)| *od == d) {
            r.cond_ratio_to_optimal = Some(c / best);
        }
    }
}
