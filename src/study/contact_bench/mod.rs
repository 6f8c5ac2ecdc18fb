//! `contact_bench`: every contact rule judged against physics — Hertz contact (plane strain and
//! axisymmetric), a rigid flat punch (`flat-punch`), the same punch turned onto a plane inclined by
//! 15°, 30° and 45° (`inclined-15`, …: contact rows with two terms, [`crate::model::inclined`];
//! rows record `theta` and `discretization`) and the two-body patch test with mortar or one-pass
//! node-to-segment rows (`patch-two-body-mortar`, `patch-two-body-nts-1`,
//! [`crate::model::two_body`]: an upper block with a finer, non-matching mesh pressed on the a × a
//! block; rows record `mesh_ratio`, `young2`, `poisson2`) — on graded Q4 meshes
//! ([`crate::model::elasticity`]), with the analytic references of [`analytic`]. On request also
//! `hertz-two-body`, `hertz-normals` and `patch-two-body-nts-2` (two-pass node-to-segment, whose
//! rows are dependent: Lagrange refuses them, and its row says so; the case has no Lagrange
//! reference, so its rows have `p_err_rel` against the exact pressure — the nodal pressures of both
//! bodies' interface nodes — and no `err_penalty`, `err_discretization` or leaderboard entry; every
//! rule starts its force control from the analytic squeeze, and the δ scale is that squeeze).
//!
//! Every solve is **force-controlled**: the lift w of the block's base is found (regula falsi
//! in a bracket, [`solve_at_load`]) so that the rule's own solution carries the load P — rules
//! are compared at equal load, as a user loads a model. Lagrange's pressure against the
//! analytic one is the discretization error of the mesh; a rule's against Lagrange's on the
//! same mesh is the error its penalty adds. One row per (case, method, knob, mesh):
//! - `err_discretization` = [`analytic::pressure_error`] of Lagrange — for Hertz on the
//!   reference block of the domain study ([`domain`]), so that the finite block's bias is not
//!   counted as the mesh's; `err_domain` = that bias, the distance of Lagrange on the
//!   benchmark's block from Lagrange on the reference block (Lagrange's own `p_err_rel` holds
//!   both); `domain.csv` and the figure `domain` hold the study,
//! - `err_penalty` = [`analytic::pressure_distance`] of the rule from Lagrange,
//! - `p_err_rel` = the rule's own [`analytic::pressure_error`] (≤ the sum of the two),
//! - `cond2_system` of its final system matrix ([`crate::metrics`], to `cond_tol`), with
//!   `cond2_bounds_proven` and `cond2_within_contract` (false at the default `cond_tol`, which
//!   is looser than the contract),
//! - what that system costs a solver ([`crate::metrics::solver`]): `cond2_jacobi`, Krylov
//!   counts to the fixed error of u (`pcg_iters_{jacobi,ic0,amg_scalar,amg_nodal}_to_err`,
//!   `minres_iters_to_err`, each with `*_converged`), the residual-stopped counts and the
//!   direct solve's `forward_err_u`, `forward_err_force` ([`BenchRow`]),
//! - `iterations` (the rule's own outer iterations), `force_solves`, `force_mismatch`, and for
//!   `barrier` its stiffness `kappa_initial`, `kappa_final`, `kappa_increases` and the rule
//!   that chose it, `kappa_rule` (`ipc`: ipc-toolkit's, from the block's bounding box; the
//!   scenes carry their contact surface, [`crate::system::Surface`]).
//!
//! The barrier's κ is a second knob: [`kappa`] solves it at fixed κ across both adaptive
//! rules' clamps (`kappa.csv`, figure `kappa_sensitivity`).
//!
//! Knobs: ε per unit contact length/area relative to E*/a (force/length³; the nodal penalty is
//! ε·ω_c, ω_c the node's tributary weight), factors absolute, δ / d̂ / tolerances relative to the
//! case's length scale ([`BenchConfig::length_scale`]: a for Hertz, the punch's compression).
//!
//! The **leaderboard** ([`leaderboard`]) answers "how much penalty is enough": per rule and
//! mesh, the knob value with the smallest cond₂ among those whose penalty error is at most
//! [`MARGIN`] (a tenth) of the mesh's discretization error, the grid refined to three values
//! per decade where a rule crosses it ([`refinement_jobs`]), with each winner's grid
//! resolution and ties; each mesh's [`Floor`] says how far below that any penalties could go.

pub use crate::study::hertz as analytic;
mod cli;
pub mod domain;
pub mod figures;
mod jobs;
pub mod kappa;
mod record;
mod report;
mod row;
mod vtk_out;

pub use cli::{ContactBench, Flags};
use jobs::solve_jobs;
pub use jobs::{jobs, refinement_jobs, BenchJob, ADAPTIVE_START};
pub use report::tables;
pub use row::{BenchRow, Floor, Profile};

pub use record::{
    admissible, convergence_rates, leaderboard, load, rule_of, save, summary, Leader, Summary,
    MARGIN,
};

use crate::error::{Error, Result};
use crate::metrics::{self, MetricSet};
use crate::model::elasticity::{Grid, Indentation};
use crate::progress::Progress;
use crate::strategy::force_control::{solve_at_load, Loaded, FORCE_TOL};
use crate::strategy::{self, registry, Method, Strategy};
use crate::study::checkpoint::Checkpoints;
use analytic::{Case, Exact};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The benchmark suite: cases, meshes and the knob grids.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchConfig {
    /// Cases (`hertz-plane`, `hertz-axi`, `flat-punch`, `inclined-15`, `inclined-30`,
    /// `inclined-45`, `patch-two-body-mortar`, `patch-two-body-nts-1`: [`Case::DEFAULT`];
    /// `hertz-two-body`, `hertz-normals` and `patch-two-body-nts-2` on request).
    pub cases: Vec<Case>,
    /// Element sizes at the contact over a (the Hertz contact half-width; the flat-punch block is
    /// a × a), coarse to fine.
    pub meshes: Vec<f64>,
    /// Methods (saved and read by name).
    #[serde(
        serialize_with = "registry::serialize_names",
        deserialize_with = "registry::deserialize_names"
    )]
    pub methods: Vec<&'static Strategy>,
    /// `constant`: ε = value · E*/a (E* = E/(1 − ν²), a the Hertz half-width or the punch's
    /// half-width): a penalty per unit contact length (plane strain) or area (axisymmetric),
    /// pressure per penetration, force/length³; node c gets ε·ω_c with its tributary weight
    /// ω_c ([`crate::system::Surface`]).
    pub eps_rel: Vec<f64>,
    /// `scaled`: factors f of ε_c = f·K\[d_c,d_c\].
    pub factors: Vec<f64>,
    /// δ-rules and the augmented Lagrangian's tolerance: δ = value · L, L the case's length
    /// scale ([`BenchConfig::length_scale`]: the Hertz half-width a; for the flat punch the
    /// block's whole compression w, about 1e-3·a, so that no δ exceeds the motion it bounds).
    pub deltas_rel: Vec<f64>,
    /// Relative accuracy asked of cond₂ (recorded in every row).
    pub cond_tol: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Indenter radius R.
    pub radius: f64,
    /// Hertz contact half-width (radius) a the load is chosen for: P from a.
    pub a_target: f64,
    /// Hertz block size over a (a square block, clamped at its base: the model of the
    /// half-space; [`domain`] measures what it costs against larger blocks).
    #[serde(default = "default_block")]
    pub block_over_a: f64,
    /// Elements across the second body per elements across the first at the contact
    /// (upper, lower) in the two-body cases: 7:4 by default (the patch test's upper block,
    /// the cylinder's cap); each 1–16.
    #[serde(default = "default_ratio")]
    pub mesh_ratio: (usize, usize),
    /// `--vtk DIR`: where every solved row of a single-body case is written as `.vtu`
    /// ([`crate::vtk`]); not part of the record (a resumed run writes what it solves).
    #[serde(skip)]
    pub vtk: Option<std::path::PathBuf>,
    /// `optimal` runs only on meshes with at most this many DOFs (≤ `optimal::MAX_N`): each
    /// solve takes ≈ 500–1 600 evaluations of the spectrum's ends on the Hertz meshes, and
    /// force control solves it 4–11 times (measured on 2 cores: 60–132 s per δ at 2 211 DOFs,
    /// 8–64 min at 5 253, where the plane mesh took 75 min for its four δ); larger meshes get
    /// a row saying it was skipped.
    pub optimal_max_n: usize,
}

/// Every registered rule but `spring`: Eq. 17 sets ε_c from the load on the contact DOF
/// itself (q_d), and the contact DOFs of these cases carry none (the load comes through the
/// lift), so its formula goes negative, its penalties clip to 0 and no lift carries the load
/// (`figures/contact_bench/README.md`). It fails on every row, and a default run would end
/// with exit status 4; `--methods spring` runs it (and exits 4).
pub fn default_methods() -> Vec<&'static Strategy> {
    registry::all()
        .into_iter()
        .filter(|s| !std::ptr::eq(*s, &strategy::spring::STRATEGY))
        .collect()
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            cases: Case::DEFAULT.to_vec(),
            meshes: vec![0.2, 0.1, 0.05],
            methods: default_methods(),
            // Per unit area (nodal ε·ω_c with ω ≈ h inside the contact): the nodal penalties
            // of the earlier grid 0.1 … 1e5·E* at h = a/20 are 2 … 2e6·E*/a.
            eps_rel: vec![1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6],
            // 0.1: LS-DYNA's SLSFAC default; 1: ANSYS's FKN default; 10: Abaqus/Standard's
            // default penalty (10 × a representative element stiffness); then stiffer.
            factors: vec![0.1, 1.0, 10.0, 100.0, 1000.0],
            deltas_rel: vec![1e-2, 1e-3, 1e-4, 1e-5],
            cond_tol: 1e-6,
            young: 210e3,
            poisson: 0.3,
            radius: 10.0,
            a_target: 1.0,
            optimal_max_n: 100,
            block_over_a: BLOCK_OVER_A,
            mesh_ratio: analytic::MESH_RATIO,
            vtk: None,
        }
    }
}

fn default_block() -> f64 {
    BLOCK_OVER_A
}

fn default_ratio() -> (usize, usize) {
    analytic::MESH_RATIO
}

/// Default Hertz block size over a: the model of the half-space ([`domain`]).
pub const BLOCK_OVER_A: f64 = 16.0;
pub use analytic::{FINE_OVER_A, GROWTH};

impl BenchConfig {
    /// The length δ, d̂ and the augmented tolerance are relative to on `case`: the Hertz
    /// half-width a, or for the flat punch its whole compression — `lift`, the base lift at
    /// which Lagrange carries the load (the flat punch's δ = 1e-2·a was ten times the compression:
    /// rows with no lift and NaN).
    pub fn length_scale(&self, case: Case, lift: f64) -> f64 {
        match case {
            c if c.is_uniform() => lift,
            _ => self.a_target,
        }
    }

    /// Validates the grids and the material.
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--cases", self.cases.iter().map(|c| c.name()))?;
        Error::distinct("--meshes", &self.meshes)?;
        Error::distinct("--methods", self.methods.iter().map(|s| s.name))?;
        Error::distinct("--eps-rel", &self.eps_rel)?;
        Error::distinct("--factors", &self.factors)?;
        Error::distinct("--deltas-rel", &self.deltas_rel)?;
        let pos = |name: &str, v: &[f64]| -> Result<()> {
            v.iter()
                .try_for_each(|&x| Error::positive(name, x).map(|_| ()))
        };
        pos("--meshes", &self.meshes)?;
        pos("--eps-rel", &self.eps_rel)?;
        pos("--factors", &self.factors)?;
        pos("--deltas-rel", &self.deltas_rel)?;
        Error::positive("Young's modulus E", self.young)?;
        Error::positive("indenter radius R", self.radius)?;
        Error::positive("Hertz half-width a", self.a_target)?;
        if !(self.block_over_a >= 2.0 * FINE_OVER_A && self.block_over_a <= 1e4) {
            return Err(Error::out_of_range(
                "--block-over-a",
                self.block_over_a,
                format!("in [{}, 1e4]", 2.0 * FINE_OVER_A),
            ));
        }
        let (up, low) = self.mesh_ratio;
        if !((1..=16).contains(&up) && (1..=16).contains(&low)) {
            return Err(Error::out_of_range(
                "--mesh-ratio",
                format!("{up}:{low}"),
                "UP:LOW with both in 1..=16",
            ));
        }
        if let Some(h) = self.meshes.iter().find(|h| **h > 0.5 || **h < 1e-3) {
            return Err(Error::out_of_range("--meshes: h/a", h, "in [1e-3, 0.5]"));
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return Err(Error::out_of_range(
                "Poisson's ratio ν",
                self.poisson,
                "in (−1, 0.5)",
            ));
        }
        if self.optimal_max_n > strategy::optimal::MAX_N {
            return Err(Error::out_of_range(
                "--optimal-max-n",
                self.optimal_max_n,
                format!("≤ {} (the optimiser's limit)", strategy::optimal::MAX_N),
            ));
        }
        MetricSet::check_cond_tol(Some(self.cond_tol)).map_err(|e| e.for_flag("--cond-tol"))?;
        Ok(())
    }

    /// The cases' material and geometry.
    pub fn setup(&self) -> analytic::Setup {
        analytic::Setup {
            young: self.young,
            poisson: self.poisson,
            radius: self.radius,
            a_target: self.a_target,
            mesh_ratio: self.mesh_ratio,
        }
    }

    fn e_star(&self) -> f64 {
        self.setup().e_star()
    }

    /// The case's load P and analytic solution.
    pub fn exact(&self, case: Case) -> (f64, Exact) {
        self.setup().exact(case)
    }

    /// The mesh of `case` at relative size `h_rel`.
    pub fn grid(&self, case: Case, h_rel: f64) -> Result<Grid> {
        self.grid_sized(case, h_rel, self.block_over_a)
    }

    /// The mesh of `case` at relative size `h_rel` on a Hertz block of `block`·a (the flat
    /// punch's block is a × a whatever `block`).
    pub fn grid_sized(&self, case: Case, h_rel: f64, block: f64) -> Result<Grid> {
        self.setup().grid(case, h_rel, block)
    }

    /// The contact scene of `case` on `grid` with base lift `lift`, with its contact surface
    /// ([`Indentation::with_surface`]).
    pub fn scene(&self, case: Case, grid: &Grid, lift: f64) -> Result<Indentation> {
        self.setup().scene(case, grid, lift)
    }
}

/// What [`run`] returns: the rows, the pressure profiles of the finest meshes and each mesh's
/// conditioning floor.
#[derive(Clone, Debug, Default)]
pub struct BenchRun {
    /// One per (case, method, knob, mesh).
    pub rows: Vec<BenchRow>,
    /// One per (case, rule, knob) on the case's finest mesh.
    pub profiles: Vec<Profile>,
    /// One per (case, mesh).
    pub floors: Vec<Floor>,
    /// The barrier's κ study ([`kappa::kappa_sensitivity`]).
    pub kappa: Vec<BenchRow>,
    /// The domain study ([`domain`]), per Hertz mesh and block size.
    pub domain: Vec<domain::DomainRow>,
}

/// The knob value of `m` as the row records it.
fn knob_value(m: &Method) -> Option<f64> {
    let k = m.knobs();
    k.eps
        .filter(|_| k.tol.is_none())
        .or(k.factor)
        .or(k.delta)
        .or(k.tol)
}

/// What one case on one mesh shares across its rows.
pub(crate) struct Mesh<'a> {
    case: Case,
    grid: &'a Grid,
    exact: Exact,
    load: f64,
    h: f64,
    /// Free DOFs.
    n_free: usize,
    /// Lagrange's lift (the start of every rule's search; without Lagrange the first guess)
    /// and its pressures (None without Lagrange: [`Case::dependent_rows`]).
    lift_lagrange: f64,
    p_lagrange: Option<&'a [f64]>,
    err_discretization: f64,
    err_domain: f64,
}

/// The row of `job` on `mesh` before its solve: the case, the knob, the mesh's errors and
/// analytic values; everything the solve measures NaN or empty.
fn base_row(cfg: &BenchConfig, mesh: &Mesh, job: &BenchJob) -> BenchRow {
    let exact = &mesh.exact;
    let two = mesh
        .case
        .two_body()
        .map(|_| cfg.setup().two_blocks(mesh.grid));
    let cylinder = (mesh.case == Case::HertzTwoBody).then(|| cfg.setup().cylinder_material());
    let ratio = cfg.mesh_ratio;
    BenchRow {
        case: mesh.case.name().into(),
        discretization: mesh.case.discretization().into(),
        theta: mesh.case.theta_deg(),
        mesh_ratio: two
            .map(|b| b.mesh_upper.0 as f64 / b.mesh_lower.0 as f64)
            .or(cylinder.map(|_| ratio.0 as f64 / ratio.1 as f64)),
        young2: two.map(|b| b.upper.young).or(cylinder.map(|m| m.young)),
        poisson2: two.map(|b| b.upper.poisson).or(cylinder.map(|m| m.poisson)),
        radius2: cylinder.map(|_| cfg.radius),
        method: job.method.name().into(),
        knob: job.knob.into(),
        knob_value: knob_value(&job.method),
        knob_rel: job.rel,
        h: mesh.h,
        n_dofs: 0,
        load: mesh.load,
        lift: f64::NAN,
        radius: if mesh.case.is_uniform() {
            0.0
        } else {
            cfg.radius
        },
        young: cfg.young,
        poisson: cfg.poisson,
        a_exact: exact.a,
        a_num: f64::NAN,
        p0_exact: exact.p0,
        p0_num: f64::NAN,
        p_err_rel: f64::NAN,
        err_penalty: f64::NAN,
        err_discretization: mesh.err_discretization,
        err_domain: mesh.err_domain,
        max_penetration: f64::NAN,
        p_spread: f64::NAN,
        cond2_system: None,
        cond_tol: cfg.cond_tol,
        cond2_bounds_proven: None,
        cond2_within_contract: None,
        cond2_jacobi: None,
        pcg_iters_jacobi: None,
        pcg_iters_ic0: None,
        pcg_converged: None,
        minres_iters: None,
        pcg_iters_jacobi_to_err: None,
        pcg_iters_jacobi_to_err_converged: None,
        pcg_iters_ic0_to_err: None,
        pcg_iters_ic0_to_err_converged: None,
        minres_iters_to_err: None,
        minres_iters_to_err_converged: None,
        pcg_iters_amg_scalar_to_err: None,
        pcg_iters_amg_scalar_to_err_converged: None,
        pcg_iters_amg_nodal_to_err: None,
        pcg_iters_amg_nodal_to_err_converged: None,
        forward_err_u: None,
        forward_err_force: None,
        converged: false,
        force_solves: 0,
        iterations: 0,
        kappa_initial: None,
        kappa_final: None,
        kappa_increases: None,
        kappa_rule: None,
        force_mismatch: f64::NAN,
        seconds: f64::NAN,
        error: String::new(),
    }
}

/// One job on one mesh: its row and its nodal pressures (empty if it failed).
pub(crate) fn run_job(cfg: &BenchConfig, mesh: &Mesh, job: &BenchJob) -> (BenchRow, Vec<f64>) {
    let exact = &mesh.exact;
    let mut row = base_row(cfg, mesh, job);
    if job.method.is(&strategy::optimal::STRATEGY) && mesh.n_free > cfg.optimal_max_n {
        row.error = format!(
            "skipped: {} DOFs > optimal_max_n = {}",
            mesh.n_free, cfg.optimal_max_n
        );
        return (row, Vec::new());
    }
    let t = Instant::now();
    let loaded = solve_at_load(
        mesh.case.name(),
        |w| cfg.scene(mesh.case, mesh.grid, w),
        job.method,
        mesh.load,
        mesh.lift_lagrange,
        job.method.strategy().force_tol,
    );
    let Loaded {
        scene,
        sol,
        solves,
        mismatch,
    } = match loaded {
        Ok(l) => l,
        Err(e) => {
            row.error = e.to_string();
            return (row, Vec::new());
        }
    };
    row.seconds = t.elapsed().as_secs_f64();
    row.force_solves = solves;
    row.force_mismatch = mismatch;
    row.n_dofs = scene.n_free;
    row.lift = scene.lift;
    let problem = &scene.problem;
    let nodes = &scene.contact;
    let p = scene.pressures(&sol.u);
    if let Some(dir) = &cfg.vtk {
        if let Err(e) = vtk_out::write(dir, mesh, &row, &scene, &sol.u, &p) {
            row.error = format!("VTK output failed: {e}");
        }
    }
    row.p0_num = p[0];
    row.a_num = analytic::contact_width(nodes, &p, 1e-9 * exact.p0);
    row.p_err_rel = analytic::pressure_error(nodes, &p, exact);
    row.err_penalty = mesh.p_lagrange.map_or(f64::NAN, |pl| {
        analytic::pressure_distance(nodes, &p, pl, exact)
    });
    row.max_penetration = sol.max_penetration;
    row.converged = sol.stats.converged;
    row.iterations = sol.stats.iterations;
    if let Some(k) = sol.stats.barrier {
        (row.kappa_initial, row.kappa_final, row.kappa_increases) =
            (Some(k.initial), Some(k.last), Some(k.increases));
        row.kappa_rule = Some(k.rule.name().into());
    }
    let loaded: Vec<f64> = p.iter().copied().filter(|v| *v > 1e-9 * exact.p0).collect();
    if !loaded.is_empty() {
        let mean = loaded.iter().sum::<f64>() / loaded.len() as f64;
        let (lo, hi) = loaded
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        row.p_spread = (hi - lo) / mean;
    }
    let set = MetricSet {
        cond: true,
        det: false,
        cond_tol: Some(cfg.cond_tol),
    };
    match metrics::compute(problem, &sol, set) {
        Ok(m) => {
            row.cond2_system = m.cond2_system.map(|c| c.cond2);
            (row.cond2_bounds_proven, row.cond2_within_contract) =
                crate::conditioning::CondReport::flags([m.cond2_system.as_ref()]);
        }
        Err(e) => row.error = format!("cond₂: {e}"),
    }
    let opts = metrics::solver::SolverOptions {
        cond_tol: Some(cfg.cond_tol),
        ..Default::default()
    };
    match metrics::solver::compute(problem, &sol, opts) {
        Ok(c) => row.set_solver_columns(c.summary()),
        Err(e) => row.error = format!("solver metrics: {e}"),
    }
    (row, p)
}

/// What one mesh of one case gives: its rows, its pressure profiles (finest mesh only) and its
/// conditioning floor. [`run`] checkpoints one per mesh ([`Checkpoints`], key `<case>-h<h_rel>`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MeshRun {
    /// Case.
    pub case: Case,
    /// Element size at the contact over a (the `meshes` entry).
    pub h_rel: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// Lagrange's lift at the load (NaN where Lagrange refused the case:
    /// [`Case::dependent_rows`]).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub lift: f64,
    /// One per (method, knob).
    pub rows: Vec<BenchRow>,
    /// One per (rule, knob) if this is the finest mesh, else none.
    pub profiles: Vec<Profile>,
    /// The mesh's conditioning floor.
    pub floor: Floor,
    /// Hertz: Lagrange on every block of the domain study ([`domain`]).
    #[serde(default)]
    pub domain: Vec<domain::DomainRow>,
}

/// One case on one mesh before its jobs: the grid, the load and its analytic solution, and
/// Lagrange's force-controlled solve (the reference of every rule's penalty error).
pub(crate) struct Prepared {
    pub(crate) case: Case,
    /// The `meshes` entry.
    pub(crate) h_rel: f64,
    /// Element size at the contact.
    pub(crate) h: f64,
    grid: Grid,
    load: f64,
    pub(crate) exact: Exact,
    /// Lagrange at the load, or the case without it.
    pub(crate) reference: Reference,
    /// Lagrange's pressures (empty without Lagrange).
    pub(crate) p_lagrange: Vec<f64>,
    /// Lagrange's error against the analytic pressure on this block (NaN without Lagrange).
    pub(crate) err_own: f64,
}

/// What a mesh's rows are measured against.
pub(crate) enum Reference {
    /// Lagrange at the load.
    Lagrange(Box<Loaded>),
    /// Lagrange refused the case's dependent rows ([`Case::dependent_rows`]; its row says
    /// why): the scene at the first guess of the lift (the patch test's analytic squeeze),
    /// for the jobs' knobs and the mesh's floor.
    Refused { scene: Box<Indentation> },
}

/// What the rows of one mesh report as `err_discretization` and `err_domain`, and the domain
/// study behind them.
pub(crate) struct MeshErrors {
    pub(crate) discretization: f64,
    pub(crate) domain: f64,
    pub(crate) study: Vec<domain::DomainRow>,
}

impl Prepared {
    /// Builds the mesh and solves Lagrange at the load.
    pub(crate) fn new(cfg: &BenchConfig, case: Case, h_rel: f64) -> Result<Prepared> {
        Prepared::new_sized(cfg, case, h_rel, cfg.block_over_a)
    }

    /// [`Prepared::new`] on a Hertz block of `block`·a.
    pub(crate) fn new_sized(
        cfg: &BenchConfig,
        case: Case,
        h_rel: f64,
        block: f64,
    ) -> Result<Prepared> {
        let (load, exact) = cfg.exact(case);
        let grid = cfg.grid_sized(case, h_rel, block)?;
        let guess = cfg.setup().lift_guess(case, &grid);
        let lagrange = solve_at_load(
            case.name(),
            |w| cfg.scene(case, &grid, w),
            Method::lagrange(),
            load,
            guess,
            FORCE_TOL,
        );
        let (reference, p_lagrange, err_own) = match lagrange {
            Ok(l) => {
                let p = l.scene.pressures(&l.sol.u);
                let err = analytic::pressure_error(&l.scene.contact, &p, &exact);
                (Reference::Lagrange(Box::new(l)), p, err)
            }
            // Two-pass node-to-segment: the refusal is the literature's over-constraint,
            // reported in the Lagrange row; the penalties are measured without a reference.
            Err(_) if case.dependent_rows() => {
                let scene = cfg.scene(case, &grid, guess)?;
                (
                    Reference::Refused {
                        scene: Box::new(scene),
                    },
                    Vec::new(),
                    f64::NAN,
                )
            }
            Err(e) => return Err(e),
        };
        Ok(Prepared {
            case,
            h_rel,
            h: h_rel * cfg.a_target,
            grid,
            load,
            exact,
            reference,
            p_lagrange,
            err_own,
        })
    }

    /// Lagrange at the load, where it solved the case.
    pub(crate) fn lagrange(&self) -> Option<&Loaded> {
        match &self.reference {
            Reference::Lagrange(l) => Some(l),
            Reference::Refused { .. } => None,
        }
    }

    /// The scene of the mesh: Lagrange's at its lift, or the scene at the first guess.
    pub(crate) fn scene(&self) -> &Indentation {
        match &self.reference {
            Reference::Lagrange(l) => &l.scene,
            Reference::Refused { scene } => scene,
        }
    }

    /// Lagrange's lift at the load (NaN without Lagrange).
    pub(crate) fn lift_lagrange(&self) -> f64 {
        self.lagrange().map_or(f64::NAN, |l| l.scene.lift)
    }

    /// The rows' errors: rigid Hertz from the domain study ([`domain`]); the flat punch is
    /// exact on its block (its own error, no domain error); `hertz-two-body` its own error
    /// against Hertz on its block and cap (which holds their finite size: no domain study).
    pub(crate) fn errors(&self, cfg: &BenchConfig) -> Result<MeshErrors> {
        if !self.case.is_rigid_hertz() {
            return Ok(MeshErrors {
                discretization: self.err_own,
                domain: 0.0,
                study: Vec::new(),
            });
        }
        domain::domain(cfg, self)
    }

    /// What the mesh's jobs share, with the rows' `errors`.
    pub(crate) fn mesh(&self, errors: &MeshErrors) -> Mesh<'_> {
        let scene = self.scene();
        Mesh {
            case: self.case,
            grid: &self.grid,
            exact: self.exact,
            load: self.load,
            h: self.h,
            n_free: scene.n_free,
            lift_lagrange: scene.lift,
            err_discretization: errors.discretization,
            err_domain: errors.domain,
            p_lagrange: self.lagrange().map(|_| self.p_lagrange.as_slice()),
        }
    }
}

/// A job that takes at least this long (s) gets its own progress line.
pub const LONG_JOB_S: f64 = 10.0;

/// Solves one mesh: the force-controlled Lagrange scene, then every job (in parallel). The
/// progress message counts the mesh's finished jobs; each job of [`LONG_JOB_S`] or more
/// gets a line (`optimal` takes 8–64 min per δ on the 5 253-DOF plane mesh).
pub fn run_mesh(cfg: &BenchConfig, case: Case, h_rel: f64, progress: &Progress) -> Result<MeshRun> {
    let finest = cfg.meshes.iter().copied().fold(f64::INFINITY, f64::min);
    let prep = Prepared::new(cfg, case, h_rel)?;
    let errors = prep.errors(cfg)?;
    // Lagrange's scene, or the case's at the first guess where Lagrange refused it.
    let scene = prep.scene();
    // K and the contact DOFs do not depend on the lift: one floor per mesh.
    let floor = Floor {
        case: case.name().into(),
        h: h_rel * cfg.a_target,
        n_dofs: scene.n_free,
        // Coupled rows: K on the null space of Dᵀ; NaN where the rows are dependent.
        cond2_floor: if scene.problem.is_selection() {
            strategy::optimal::cond2_lower_bound(&scene.problem)?
        } else {
            strategy::optimal::cond2_lower_bound(&scene.problem).unwrap_or(f64::NAN)
        },
    };
    let mesh = prep.mesh(&errors);
    // The jobs of a mesh are independent: solved in parallel, kept in job order; then the
    // knob values added near each rule's leaderboard threshold, solved the same way.
    let scale = cfg.length_scale(case, scene.lift);
    let first = jobs(cfg, scene, scale);
    let mut solved = solve_jobs(cfg, &mesh, &first, progress, h_rel);
    let rows: Vec<&BenchRow> = solved.iter().map(|(r, _)| r).collect();
    let extra = refinement_jobs(cfg, scene, scale, &rows);
    solved.extend(solve_jobs(cfg, &mesh, &extra, progress, h_rel));
    let mut out = MeshRun {
        case,
        h_rel,
        n_dofs: scene.n_free,
        lift: prep.lift_lagrange(),
        rows: Vec::new(),
        profiles: Vec::new(),
        floor,
        domain: errors.study,
    };
    for (row, p) in solved {
        if h_rel == finest && !p.is_empty() {
            out.profiles.push(Profile {
                case: row.case.clone(),
                rule: rule_of(&row),
                knob: row.knob.clone(),
                knob_rel: row.knob_rel,
                h: row.h,
                x: scene.contact.iter().map(|n| n.x).collect(),
                p,
            });
        }
        out.rows.push(row);
    }
    Ok(out)
}

/// Runs the suite: [`run_mesh`] per case and mesh, in order. With `checkpoints`, each finished
/// mesh is written to its directory at once, and with `--resume` a mesh whose checkpoint was
/// written by the same build for the same config is read back instead of solved
/// ([`crate::study::checkpoint`]); long runs (hours with `optimal` on 5 000-DOF meshes) survive an
/// interruption.
pub fn run(
    cfg: &BenchConfig,
    progress: &Progress,
    checkpoints: Option<&Checkpoints>,
) -> Result<BenchRun> {
    cfg.validate()?;
    let mut out = BenchRun::default();
    progress.set_total(cfg.cases.len() * cfg.meshes.len());
    for &case in &cfg.cases {
        for &h_rel in &cfg.meshes {
            let key = format!("{}-h{h_rel}", case.name());
            let (mesh, from_checkpoint) = Checkpoints::get_or_maybe(checkpoints, &key, || {
                run_mesh(cfg, case, h_rel, progress)
            })?;
            let lift = if mesh.lift.is_nan() {
                "no Lagrange reference (its rows are dependent)".to_string()
            } else {
                format!("lift {:.4e}", mesh.lift)
            };
            progress.step(&format!(
                "{} h/a = {h_rel}: {} DOFs, {lift}{}",
                case.name(),
                mesh.n_dofs,
                if from_checkpoint { " (checkpoint)" } else { "" }
            ));
            out.rows.extend(mesh.rows);
            out.profiles.extend(mesh.profiles);
            out.floors.push(mesh.floor);
            out.domain.extend(mesh.domain);
        }
    }
    out.kappa = kappa::kappa_sensitivity(cfg, progress)?;
    progress.finish();
    Ok(out)
}
