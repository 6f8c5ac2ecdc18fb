//! One scene, one strategy, every metric: the `solve` binary's study ([`Solve`], a one-shot
//! study: no record in `--out`, no figures) and its table ([`report::table`]).

pub mod report;

pub use report::table;

use crate::error::{Error, Result};
use crate::metrics::{self, finite_or_null, solver::SolverOptions, MetricSet};
use crate::scene;
use crate::strategy::{self, registry, Knob, Knobs, Method, Strategy};
use crate::study::shape::{Drawing, RunContext, Study};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// The `solve` flags of each kind of knob, with the symbol the library names each value by
/// in its errors (`None`: a switch, no value): the one table behind [`with_flag`] and
/// [`check_knob_flags`].
fn knob_flags(knob: Knob) -> &'static [(Option<&'static str>, &'static str)] {
    use strategy::symbol;
    match knob {
        Knob::None => &[],
        Knob::Eps => &[(Some(symbol::EPS), "--eps")],
        Knob::Factor => &[(Some(symbol::FACTOR), "--factor")],
        Knob::Delta => &[(Some(symbol::DELTA), "--delta")],
        Knob::EpsTol => &[
            (Some(symbol::EPS), "--eps"),
            (Some(symbol::TOL), "--tol"),
            (None, "--adaptive"),
        ],
    }
}

/// A knob error of [`Method::new`] as the value of the `solve` flag that sets the knob
/// (the library names the knob by its symbol; flags live here, in the command line's layer).
fn with_flag(e: Error) -> Error {
    let knob = match &e {
        Error::MissingKnob { knob, .. } => *knob,
        Error::NotPositive { name, .. } => name.as_str(),
        _ => return e,
    };
    let flag = [Knob::Eps, Knob::Factor, Knob::Delta, Knob::EpsTol]
        .into_iter()
        .flat_map(knob_flags)
        .find(|(symbol, _)| *symbol == Some(knob))
        .map(|(_, flag)| *flag);
    match flag {
        Some(flag) => e.for_flag(flag),
        None => e,
    }
}

/// Above this many unknowns [`solve_scene`] computes the solver-cost metrics only when asked
/// (`SolveOptions::solver_metrics`, `--solver-metrics`), so that `solve --json` with its
/// default metrics takes at most twice as long as with `--no-solver-metrics`. Their four
/// Krylov runs (each to the residual test and to the fixed error of u), cond₂ of the scaled
/// system and the refined reference grow faster than the solve, most on elasticity (many CG
/// iterations per unknown). Measured (`constant`, 2 cores, the runs side by side): Hertz plane
/// strain 741 / 1 378 / 1 711 / 2 346 / 8 515 / 14 196 unknowns 1.87 / 1.95 / 1.96 / 2.0–2.1 /
/// 2.2 / 2.1× (4.3× at 14 196 before the runs went side by side); a 1 600-unknown membrane
/// 1.5×; the 279-unknown cantilever on its bed 1.4×.
pub const SOLVER_METRICS_AUTO_MAX_N: usize = 1_000;

/// How [`solve_scene`] runs: which metrics, from which start, and what it writes.
#[derive(Clone, Debug, Default)]
pub struct SolveOptions {
    /// Skip every metric (cond₂, determinants, the solver-cost metrics).
    pub no_metrics: bool,
    /// Skip the solver-cost metrics only.
    pub no_solver_metrics: bool,
    /// Compute the solver-cost metrics above [`SOLVER_METRICS_AUTO_MAX_N`] unknowns too.
    pub solver_metrics: bool,
    /// Start constant, scaled and condensed from the exact contact set, and a penalized
    /// system's cond₂ from its free block's bottom vector (module doc of [`solve_scene`]).
    pub exact_start: bool,
    /// Relative accuracy asked of the cond₂ values ([`MetricSet::cond_tol`]; `None`: the
    /// contract).
    pub cond_tol: Option<f64>,
    /// τ and the iteration limit of the Krylov runs ([`metrics::solver`]).
    pub krylov: SolverOptions,
    /// Write the final linear system (`A.mtx`, `b.mtx`) into this folder.
    pub write_system: Option<std::path::PathBuf>,
    /// Write the solution as `<scene name>_<method>.vtu` into this folder (a scene with
    /// `"nodes"`; [`crate::vtk::scene_fields`]).
    pub vtk: Option<std::path::PathBuf>,
}

/// The options' checks, each error named by its flag.
fn check_options(opts: &SolveOptions) -> Result<()> {
    let k = opts.krylov;
    let only_tol = SolverOptions {
        max_iters: None,
        err_target: metrics::solver::DEFAULT_ERR_TARGET,
        ..k
    };
    only_tol.check().map_err(|e| e.for_flag("--krylov-tol"))?;
    Error::fraction("Krylov error target", k.err_target).map_err(|e| e.for_flag("--krylov-err"))?;
    k.check().map_err(|e| e.for_flag("--krylov-max-iters"))?;
    MetricSet::check_cond_tol(opts.cond_tol).map_err(|e| e.for_flag("--cond-tol"))
}

/// `augmented` without ε or tolerance: ε = max `K[d,d]` over the constrained DOFs (1 if none
/// is positive), tol = 1e-9·max(1, max|û|).
fn augmented_defaults(p: &crate::system::Problem, knobs: &mut Knobs) {
    if knobs.eps.is_none() {
        let e = p.max_constraint_stiffness();
        knobs.eps = Some(if e > 0.0 { e } else { 1.0 });
    }
    if knobs.tol.is_none() {
        let s = p
            .constraints
            .iter()
            .map(|c| c.limit.abs())
            .fold(1.0f64, f64::max);
        knobs.tol = Some(1e-9 * s);
    }
}

/// Reads `scene`, solves it with `method` (its knobs from `knobs`; `augmented` without ε or
/// tolerance gets ε = max `K[d,d]` over the constrained DOFs and tol = 1e-9·max(1, max|û|)),
/// computes the metrics (cond₂ and determinants, and the solver-cost metrics of
/// [`metrics::solver`]) unless `opts.no_metrics`, and returns the `solve --json` object
/// (contract in `shared/notes/methods.md`). With `opts.exact_start`, the scene is first solved
/// by `lagrange` and constant, scaled and condensed start from its contact set, as every
/// `sweep` row does ([`strategy::Prepared::with_contact_set`]; the lagrange solve is not in
/// the statistics or `seconds`), and a penalized system's cond₂ may start its bottom run from
/// K_ℱℱ's bottom Ritz vector at that set ([`metrics::compute_at_contact_set`]). With
/// `opts.write_system`, the final system `A x = b` is written there exactly as solved ([`write_system`]). Errors on unreadable scenes, bad knobs,
/// a `cond_tol` outside (0, 1), singular systems and a non-finite solution.
pub fn solve_scene(
    scene: &Path,
    strategy: &'static Strategy,
    knobs: Knobs,
    opts: &SolveOptions,
) -> Result<Value> {
    check_options(opts)?;
    // K in the storage its structure prefers, as `sweep` reads scenes: the same solve and
    // cond₂ routes (a dense-stored 400-DOF membrane takes the sparse ones, not a dense
    // eigensolver with Kahan-wide bounds).
    let sc = scene::read_scene_preferred(scene)?;
    let Some(dir) = &opts.vtk else {
        return solve_loaded(&sc, strategy, knobs, opts);
    };
    let nodes = sc.nodes.as_ref().ok_or_else(|| {
        Error::unsupported(
            "--vtk",
            "a scene with \"nodes\" (coordinates, DOFs per node, optionally cells)",
        )
    })?;
    let path = dir.join(format!("{}_{}.vtu", sc.name, strategy.name));
    if path.exists() {
        return Err(Error::io(
            path.display(),
            "exists: --vtk does not overwrite",
        ));
    }
    let v = solve_loaded(&sc, strategy, knobs, opts)?;
    let floats = |key: &str| -> Vec<f64> {
        let a = v[key].as_array().map(Vec::as_slice).unwrap_or_default();
        a.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect()
    };
    let fields = crate::vtk::scene_fields(&sc.problem, nodes, &floats("u"), &floats("forces"))?;
    let title = format!("penalty-lab solve {} {}", sc.name, strategy.name);
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir.display(), e.to_string()))?;
    crate::vtk::write_vtu(
        &path,
        &title,
        &crate::vtk::CellMesh::of_nodes(nodes),
        fields,
    )?;
    Ok(v)
}

/// [`solve_scene`] on a scene already read (or built in memory, as the Python module does),
/// its K in the storage it should be solved in ([`crate::system::Problem::in_preferred_storage`]).
pub fn solve_loaded(
    sc: &scene::Scene,
    strategy: &'static Strategy,
    knobs: Knobs,
    opts: &SolveOptions,
) -> Result<Value> {
    let (no_metrics, exact_start, cond_tol) = (opts.no_metrics, opts.exact_start, opts.cond_tol);
    check_options(opts)?;
    let p = &sc.problem;
    let mut knobs = knobs;
    if strategy.knob == Knob::EpsTol {
        augmented_defaults(p, &mut knobs);
    }
    let method = Method::new(strategy, knobs).map_err(with_flag)?;
    // The sweep's order: K prepared once, lagrange on it, its contact set for the rest (the
    // start of constant, scaled and condensed; and where the cond₂ of every penalized system
    // may start its bottom run, `metrics::compute_at_contact_set`).
    let exact = exact_start
        .then(|| {
            let prep = strategy::Prepared::new(p).ok()?;
            let set = strategy::solve_prepared(p, Method::lagrange(), Some(&prep))
                .ok()?
                .contact_set()?;
            Some((prep, set))
        })
        .flatten();
    let (prepared, contact) = exact
        .map(|(prep, set)| (prep.with_contact_set(set.clone()), set))
        .unzip();
    let t0 = Instant::now();
    let sol = match &prepared {
        Some(prep) => strategy::solve_prepared(p, method, Some(prep))?,
        None => strategy::solve(p, method)?,
    };
    let seconds = t0.elapsed().as_secs_f64();
    let set = if no_metrics {
        MetricSet::default()
    } else {
        MetricSet {
            cond_tol,
            ..MetricSet::ALL
        }
    };
    let m = metrics::compute_at_contact_set(p, &sol, set, contact.as_deref())?;
    let mut warnings = metrics::warnings(&sol, &m);
    if let Some(c) = m.cond2_system {
        if !c.cond2.is_finite() {
            warnings.push("the system matrix is singular (cond2 = ∞)".into());
        }
    }
    if sol.u.iter().any(|v| !v.is_finite()) {
        return Err(Error::Numerical(
            "the solution contains NaN/Inf (system singular to working precision)".into(),
        ));
    }
    let cost = solver_cost(p, &sol, opts, &mut warnings)?;
    let flags = crate::conditioning::CondReport::flags([
        m.cond2_k.as_ref(),
        m.cond2_system.as_ref(),
        cost.as_ref().and_then(|c| c.cond2_jacobi.as_ref()),
    ]);
    let mut out = json!({
        "scene": sc.name,
        "n": p.n(),
        "m": p.m(),
        "method": method.name(),
        "knob": method,
        "u": sol.u,
        "penalties": sol.penalties,
        "gaps": sol.gaps,
        "forces": sol.forces,
        "max_penetration": sol.max_penetration,
        "cond2_K": finite_or_null(m.cond2_k.map(|c| c.cond2)),
        "cond2_system": finite_or_null(m.cond2_system.map(|c| c.cond2)),
        "cond_route_K": m.cond2_k.map(|c| c.route.name()),
        "cond_route_system": m.cond2_system.map(|c| c.route.name()),
        "cond2_K_lo": finite_or_null(m.cond2_k.map(|c| c.cond2_lo)),
        "cond2_K_hi": finite_or_null(m.cond2_k.map(|c| c.cond2_hi)),
        "cond2_system_lo": finite_or_null(m.cond2_system.map(|c| c.cond2_lo)),
        "cond2_system_hi": finite_or_null(m.cond2_system.map(|c| c.cond2_hi)),
        "cond_tol": cond_tol,
        "cond2_bounds_proven": flags.0,
        "cond2_within_contract": flags.1,
        "cond2_error_bound_K": m.cond2_k.map(|c| finite_or_null(Some(c.error_bound()))),
        "cond2_error_bound_system": m.cond2_system.map(|c| finite_or_null(Some(c.error_bound()))),
        "log10_det_K": finite_or_null(m.log10_det_k),
        "log10_det_system": finite_or_null(m.log10_det_system),
        "log10_det_ratio": finite_or_null(m.log10_det_ratio),
        "linear_solves": sol.stats.linear_solves,
        "factorizations": sol.stats.factorizations,
        "iterations": sol.stats.iterations,
        "converged": sol.stats.converged,
        "refinements": sol.stats.refinements,
        "cg_iterations": sol.stats.cg_iterations,
        "active_set_sizes": sol.stats.active_set_sizes,
        "clipped": sol.stats.clipped,
        "system": sol.system,
        "optimality": sol.stats.optimal.as_ref().map(|o| finite_or_null(Some(o.optimality))),
        "starts_agreeing": sol.stats.optimal.as_ref().map(|o| o.starts_agreeing),
        "kappa": sol.stats.barrier,
        "cond2_lower_bound": sol.stats.optimal.as_ref().map(|o| finite_or_null(Some(o.cond2_lower_bound))),
        "seconds": seconds,
        "warnings": warnings,
    });
    if let (Some(c), Value::Object(o)) = (&cost, &mut out) {
        o.extend(c.json_fields(m.cond2_system.as_ref()));
    }
    Ok(out)
}

/// Whether the solver-cost metrics run: not skipped, and asked for or at most
/// [`SOLVER_METRICS_AUTO_MAX_N`] unknowns.
fn solver_metrics_on(p: &crate::system::Problem, opts: &SolveOptions) -> bool {
    !(opts.no_metrics || opts.no_solver_metrics)
        && (opts.solver_metrics || p.n() <= SOLVER_METRICS_AUTO_MAX_N)
}

/// The solver-cost metrics of `sol` unless `opts` skips them (their warnings, or why they
/// were skipped by size, into `warnings`), and its final system written to `opts.write_system` (with the direct solve x̂ where the metrics ran); the system is
/// formed once for both.
fn solver_cost(
    p: &crate::system::Problem,
    sol: &strategy::Solution,
    opts: &SolveOptions,
    warnings: &mut Vec<String>,
) -> Result<Option<metrics::solver::SolverMetrics>> {
    let with_cost = solver_metrics_on(p, opts);
    if !(with_cost || opts.no_metrics || opts.no_solver_metrics) {
        warnings.push(format!(
            "solver-cost metrics not computed: {} unknowns is above {SOLVER_METRICS_AUTO_MAX_N} \
             (--solver-metrics computes them)",
            p.n()
        ));
    }
    let system =
        (with_cost || opts.write_system.is_some()).then(|| metrics::solver::final_system(p, sol));
    let cost = match &system {
        Some(fs) if with_cost => {
            let krylov = SolverOptions {
                cond_tol: opts.cond_tol,
                ..opts.krylov
            };
            Some(metrics::solver::compute_for(p, sol, fs, krylov)?)
        }
        _ => None,
    };
    if let (Some(dir), Some(fs)) = (&opts.write_system, &system) {
        let x = cost.as_ref().map(|c| c.x_direct.as_slice());
        write_system(dir, fs, x)?;
    }
    if let Some(c) = &cost {
        warnings.extend(c.unavailable.iter().cloned());
    }
    Ok(cost)
}

/// Writes the final linear system `A x = b` into `dir` (created if missing): `A.mtx` (Matrix
/// Market, shortest round-trip values: the stored matrix bit for bit), `b.mtx` (one column,
/// Matrix Market `array`) and, when given, `x_hat.mtx`: the plain direct solve whose forward
/// error `forward_err_u` reports. For `lagrange` A is the saddle point `[K D_A; D_Aᵀ 0]` and
/// x = [u; r_A] ([`metrics::solver`] defines b for every strategy).
pub fn write_system(
    dir: &Path,
    fs: &metrics::solver::FinalSystem,
    x_hat: Option<&[f64]>,
) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir.display(), e))?;
    scene::write_matrix_market(&dir.join("A.mtx"), &fs.a)?;
    scene::write_matrix_market_vector(&dir.join("b.mtx"), &fs.b)?;
    match x_hat {
        Some(x) if !x.is_empty() => scene::write_matrix_market_vector(&dir.join("x_hat.mtx"), x),
        _ => Ok(()),
    }
}

impl serde::Serialize for SolveConfig {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        serde::Serialize::serialize(
            &json!({"scene": self.scene, "method": self.strategy.name}),
            s,
        )
    }
}

/// The files [`write_system`] writes.
pub const SYSTEM_FILES: [&str; 3] = ["A.mtx", "b.mtx", "x_hat.mtx"];

/// `--write-system DIR` never overwrites: an error naming the first of [`SYSTEM_FILES`] that
/// exists in `dir` (`--force` replaces them).
fn check_system_files_absent(dir: &Path) -> Result<()> {
    match SYSTEM_FILES
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.exists())
    {
        Some(p) => Err(Error::bad_file(
            p.display(),
            "exists; --write-system does not overwrite: choose another folder, or --force to \
             replace it",
        )),
        None => Ok(()),
    }
}

/// The `solve` binary's flags.
#[derive(clap::Args, Clone, Debug)]
pub struct Flags {
    /// Scene file (JSON; stiffness dense or Matrix Market).
    scene: std::path::PathBuf,
    /// Strategy.
    #[arg(long, value_parser = registry::method_parser())]
    method: String,
    /// Allowed penetration δ (units of u) for spring, paper, condensed.
    #[arg(long, allow_negative_numbers = true)]
    delta: Option<f64>,
    /// Penalty ε for constant and augmented.
    #[arg(long, allow_negative_numbers = true)]
    eps: Option<f64>,
    /// Factor f for scaled (ε_c = f·d_cᵀKd_c/‖d_c‖⁴: f times K's diagonal entry at the DOF for a single-DOF row).
    #[arg(long, allow_negative_numbers = true)]
    factor: Option<f64>,
    /// Penetration tolerance for augmented.
    #[arg(long, allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Adaptive per-constraint penalty update (augmented).
    #[arg(long)]
    adaptive: bool,
    /// Skip the solver-cost metrics only (cond2_jacobi, the Krylov runs, the forward errors).
    #[arg(long)]
    no_solver_metrics: bool,
    /// Compute the solver-cost metrics above 1 000 unknowns too (by default they are
    /// computed up to 1 000 unknowns only: above, their Krylov runs, the scaled system's cond₂
    /// and the refined reference would more than double the run's time).
    #[arg(long, conflicts_with = "no_solver_metrics")]
    solver_metrics: bool,
    /// Skip every metric: cond₂, log-det and the solver-cost metrics (cond₂ costs O(N³) for
    /// dense systems).
    #[arg(long)]
    no_metrics: bool,
    /// Start constant, scaled and condensed from the exact contact set (a lagrange solve
    /// first), and a penalized system's cond₂ from K's free block at it, as every sweep row
    /// does: reproduces a sweep row bit for bit.
    #[arg(long)]
    exact_start: bool,
    /// Relative accuracy asked of the cond₂ values, in (0, 1) (default: the accuracy
    /// contract, max(1e-12, 4·ε_mach·cond₂)); looser is faster, the bounds stay proven.
    #[arg(long, allow_negative_numbers = true)]
    cond_tol: Option<f64>,
    /// τ of the solver-cost Krylov runs (PCG with Jacobi and IC(0); MINRES for lagrange):
    /// stop at ‖r‖ ≤ τ‖b‖, from x₀ = 0.
    #[arg(long, default_value_t = metrics::solver::DEFAULT_TOL, allow_negative_numbers = true)]
    krylov_tol: f64,
    /// The relative error of u the reported Krylov counts are taken to
    /// (`*_to_err`: ‖u_k − u*‖∞ ≤ e‖u*‖∞, u* the refined direct solution of the same system).
    #[arg(long, default_value_t = metrics::solver::DEFAULT_ERR_TARGET, allow_negative_numbers = true)]
    krylov_err: f64,
    /// Iteration limit of each Krylov run (default 10·N, SciPy's, at most 1e5).
    #[arg(long)]
    krylov_max_iters: Option<usize>,
    /// Write the final linear system as solved into this folder: A.mtx and b.mtx (Matrix
    /// Market, values round-trip exact) and, where the solver metrics ran, x_hat.mtx (the
    /// plain direct solve their forward errors measure). Existing files are refused (--force
    /// replaces them).
    #[arg(long, value_name = "DIR")]
    write_system: Option<std::path::PathBuf>,
    /// Write the solution as `DIR/<scene name>_<method>.vtu` (ParaView, meshio): per node u, the
    /// contact force, the rows' smallest clearance and a contact flag, on the scene's
    /// "nodes" (its "cells", or one vertex per node). Needs a scene with "nodes"; an existing
    /// file is refused.
    #[arg(long, value_name = "DIR")]
    vtk: Option<std::path::PathBuf>,
}

/// A knob flag given to a method that does not take it (it would be ignored silently): an
/// error naming the flag and what the method takes.
fn check_knob_flags(f: &Flags, strategy: &'static Strategy) -> Result<()> {
    let takes: Vec<&str> = knob_flags(strategy.knob).iter().map(|(_, f)| *f).collect();
    let given = [
        ("--eps", f.eps.is_some()),
        ("--factor", f.factor.is_some()),
        ("--delta", f.delta.is_some()),
        ("--tol", f.tol.is_some()),
        ("--adaptive", f.adaptive),
    ];
    match given
        .iter()
        .find(|(flag, set)| *set && !takes.contains(flag))
    {
        Some((flag, _)) => Err(Error::unsupported(
            *flag,
            format!(
                "a method that takes it ({} takes {})",
                strategy.name,
                if takes.is_empty() {
                    "no knob".to_string()
                } else {
                    takes.join(", ")
                }
            ),
        )),
        None => Ok(()),
    }
}

/// What one `solve` run does, parsed and checked from the flags at the edge: the scene file,
/// the strategy (looked up once), its knobs and the options.
#[derive(Clone, Debug)]
pub struct SolveConfig {
    /// The scene file.
    pub scene: std::path::PathBuf,
    /// The strategy.
    pub strategy: &'static Strategy,
    /// Its knobs (`augmented`'s missing ε and tolerance default from the scene in
    /// [`solve_scene`]).
    pub knobs: Knobs,
    /// Metrics, start and output.
    pub opts: SolveOptions,
}

/// The study as the shared entry runs it: prints the table, or with `--json` the object.
pub struct Solve;

impl Study for Solve {
    const NAME: &'static str = "solve";
    const ABOUT: &'static str =
        "Solve one contact scene with one penalty strategy and report exact conditioning";
    const PROGRESS: &'static str = "solve";
    const DEFAULT_OUT: &'static str = "";
    const SAVES: bool = false;
    type Flags = Flags;
    type Config = SolveConfig;
    type Record = Value;

    fn after_help() -> String {
        "Methods: constant (--eps), scaled (--factor), spring|paper|condensed (--delta), \
         lagrange, augmented (--eps, --tol; defaults: eps = max K[d,d] over the constrained \
         DOFs, tol = 1e-9·max(1, max|û|); --adaptive for the per-constraint penalty \
         update).\nExit status: 0 ok, 2 bad input or singular system."
            .into()
    }

    fn config(f: &Flags) -> Result<SolveConfig> {
        let strategy = registry::lookup(&f.method)?;
        let knobs = Knobs {
            eps: f.eps,
            factor: f.factor,
            delta: f.delta,
            tol: f.tol,
            adaptive: f.adaptive,
            ..Knobs::NONE
        };
        let opts = SolveOptions {
            no_metrics: f.no_metrics,
            no_solver_metrics: f.no_solver_metrics,
            solver_metrics: f.solver_metrics,
            exact_start: f.exact_start,
            cond_tol: f.cond_tol,
            krylov: SolverOptions {
                tol: f.krylov_tol,
                err_target: f.krylov_err,
                max_iters: f.krylov_max_iters,
                cond_tol: None,
            },
            write_system: f.write_system.clone(),
            vtk: f.vtk.clone(),
        };
        check_options(&opts)?;
        check_knob_flags(f, strategy)?;
        // The knobs checked here where they do not depend on the scene (augmented's defaults
        // do: checked in the run, after they are filled in).
        if strategy.knob != Knob::EpsTol {
            Method::new(strategy, knobs).map_err(with_flag)?;
        }
        Ok(SolveConfig {
            scene: f.scene.clone(),
            strategy,
            knobs,
            opts,
        })
    }

    fn run(c: &SolveConfig, ctx: &RunContext) -> Result<Value> {
        if let Some(dir) = &c.opts.write_system {
            if ctx.force {
                // Replaced as a whole: no x_hat.mtx of an earlier system beside the new A.
                for f in SYSTEM_FILES {
                    crate::provenance::remove_if_present(&dir.join(f))?;
                }
            } else {
                check_system_files_absent(dir)?;
            }
        }
        solve_scene(&c.scene, c.strategy, c.knobs, &c.opts)
    }

    fn save(_: &Path, _: &SolveConfig, _: &Value, _: &crate::provenance::Provenance) -> Result<()> {
        Ok(())
    }

    fn load(_: &Path) -> Result<Value> {
        Err(Error::unsupported(
            "--render-only",
            "a study that keeps a record (solve keeps no record)",
        ))
    }

    fn figures(_: &Value) -> Result<Vec<Drawing>> {
        Ok(Vec::new())
    }

    fn report(v: &Value) -> String {
        table(v)
    }

    fn json(v: &Value) -> Result<String> {
        crate::provenance::json_text("solve result", v)
    }
}
