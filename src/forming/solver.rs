//! The flow-approach solver: updated Lagrangian steps, Picard iteration on μ*, penalty contact
//! in local nodal axes, telemetry.
//!
//! ## One time step (Δt = travel / steps / v_punch)
//! 1. **Contact candidates** from the geometry at the start of the step: for every node the
//!    nearest tool, its gap `g = d − t_node/2` and outward normal n; nodes with
//!    `g < max(3 v_punch Δt, t₀)` are candidates. The node's `(v_r, v_z)` are rotated to local
//!    `(n, τ)` axes so that D is Boolean (paper Eq. 7–9); non-penetration after the step reads
//!    `v·n ≥ û = V_tool·n − g/Δt`. The axis node keeps global axes (v_r = 0 there) and is
//!    constrained on v_z.
//! 2. **Picard iteration** on `K[μ*(v)] v = q` (Eq. 6): μ* per element from the current
//!    iterate (Eq. 4, cut-off rate, see [`MuThroughThickness`]), K assembled from the element
//!    matrices ([`super::element`]), lagged regularized Coulomb friction added as `c ττᵀ`,
//!    `c = μ (N + H) / sqrt(v_t² + v₀²)` with the previous iterate's normal force N and holder
//!    load H (keeps K symmetric), the rigid-mode drag added to the v_z diagonals, essential BCs
//!    removed (axis: v_r = β = 0; clamped rim: all three). The candidates in the current
//!    **contact set** become `bilateral` constraints `v·n = û` (D selects exactly the active
//!    contact DOFs, as the paper's D does); the [`Problem`] is solved with
//!    [`crate::strategy::solve`]: `constant {ε}`, `paper {δ/Δt}` or `condensed {δ/Δt}`. The
//!    contact set is then updated (contacts with a tensile normal force released, penetrating
//!    candidates added). Converged when `max|v_new − v| ≤ tol · max(max|v_new|, v_punch)`
//!    over the nodal velocities and the contact set did not change; otherwise the next
//!    iterate comes from Anderson acceleration ([`super::acceleration`], depth 3, history
//!    restarted when the contact set changes or the residual grows), or with
//!    `picard.anderson = 0` from `v ← v + ω (v_new − v)` with Aitken's ω. A step that reaches
//!    the iteration cap is recorded `converged = false` with its final change; the run
//!    summary counts such steps and the validity guards reject a run with more than 5 % of
//!    them. The accepted velocity is the last solve's
//!    (unrelaxed) output, so the penalty rule's guarantees hold for it exactly.
//! 3. **Telemetry** of the last solve: exact cond₂ and log10|det| of the system matrix
//!    `K + D E Dᵀ` ([`crate::metrics::system_matrix`]), punch force, penetration, …
//! 4. **Update** (updated Lagrangian): `ε̄ += ε̄̇ Δt` per layer, thickness (see
//!    [`ThicknessUpdate`]), `x += v Δt`, punch tip `−= v_punch Δt`.
//!
//! [`Simulation::step`] reads as these phases: `prepare_step` (1: BCs, reduced numbering,
//! candidates, local axes, û), `picard` (2: per iteration `assemble` — material matrix, drag,
//! holder loads, friction, rotation to local axes — then `solve_contact`, the contact-set
//! update and the relaxation), `telemetry` (3), `advance` (4), then the geometric
//! penetration and the snapshots.
//!
//! The blank holder is a prescribed force spread as nodal loads `−H_i e_z` over the nodes on the
//! flat of the die (tributary area); it does not add constraints. This keeps D Boolean and the
//! holder force exactly the prescribed one, at the price of ignoring where the flange actually
//! touches the holder.
//!
//! ## Punch force
//! The z-component of the force the sheet exerts on the punch (positive while the punch
//! pushes): `P = −Σ_punch (N n_z + f τ_z)` over the punch constraints, N = −r_c the normal
//! force (r_c = ε_c g_c from the strategy), f = −c (v_t − V_t) the friction force.
//! [`Simulation::equilibrium_punch_force`] recomputes it from the element internal forces.

use super::acceleration::Anderson;
use super::assembly::{Block, BlockTri};
use super::config::{ContactRule, FormingConfig, MuThroughThickness, ThicknessUpdate};
use super::element::{self, ElementGeom};
use super::tools::{Die, Punch, ToolId};
use crate::conditioning;
use crate::error::{Error, Result};
use crate::metrics;
use crate::strategy::{self, Method, Solution};
use crate::system::{Constraint, ConstraintKind, Problem};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// `paper-residual`: the Eq. 18 corrector passes of a Picard iteration (frozen K) stop when
/// every contact gap is within this fraction of δ of δ ...
pub const RESIDUAL_RTOL: f64 = 0.05;
/// ... or at most this many times per Picard iteration.
pub const RESIDUAL_PASSES: usize = 20;

fn nan() -> f64 {
    f64::NAN
}

/// JSON writes non-finite numbers as `null`; read them back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Telemetry of one converged (or capped) step.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StepRecord {
    /// Step number (1-based).
    pub step: usize,
    /// Punch travel at the end of the step (in).
    pub punch_travel: f64,
    /// Punch force (ton-force), see module docs.
    pub punch_force: f64,
    /// Exact cond₂ of the system matrix `K + D E Dᵀ` of the step's last solve.
    #[serde(deserialize_with = "null_as_nan")]
    pub cond2: f64,
    /// log10|det| of that matrix.
    #[serde(deserialize_with = "null_as_nan")]
    pub log10_det: f64,
    /// Exact cond₂ of K alone: the step's material matrix with the rigid-mode drag, in the
    /// same local axes and reduced numbering, without any contact term (no penalty, no
    /// friction) — the paper's "system of equation without any contact conditions".
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub cond2_k: f64,
    /// `log10|det(K + D E Dᵀ)| − log10|det K|` with K as in `cond2_k` (the paper's "ratio of
    /// main determinants"; friction is part of the numerator).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub log10_det_ratio: f64,
    /// cond₂ of the diagonally equilibrated system matrix `S (K + D E Dᵀ) S`,
    /// `S = diag(2^k_i) ≈ diag(A_ii^{-1/2})` (`Stiffness::equilibration`).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub cond2_equilibrated: f64,
    /// cond₂ of the equilibrated K alone.
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub cond2_k_equilibrated: f64,
    /// Max penetration of the last solve, in length: `max_c p_c · Δt` (in) — the quantity δ
    /// bounds.
    pub max_penetration: f64,
    /// Max geometric penetration of a contact node into its tool after the update (in).
    pub geometric_penetration: f64,
    /// Sheet volume after the update (in³).
    pub volume: f64,
    /// Radius of the blank rim (last node) after the update (in).
    #[serde(default)]
    pub rim_r: f64,
    /// Picard iterations.
    pub iterations: usize,
    /// Matrix factorizations over all Picard iterations (strategy statistics).
    pub factorizations: usize,
    /// Picard converged within the cap.
    pub converged: bool,
    /// Final relative velocity change of the Picard test.
    pub picard_change: f64,
    /// Contact constraints (the contact set, columns of D) in the last solve.
    pub contact_nodes: usize,
    /// Contact candidates of the step (nodes close enough to a tool).
    pub candidates: usize,
    /// Constraints whose Eq. 28 penalty came out ≤ 0: clipped to 0 and released
    /// (`paper-literal`), or floored at K_dd and corrected to δ (`paper-residual`).
    pub clipped: usize,
    /// Largest and smallest penalty ε_c among the active constraints (ton-force·s/in).
    pub max_penalty: f64,
    /// Smallest active penalty.
    pub min_penalty: f64,
    /// max μ* / min μ* over elements and layers (cut-off induced spread of K).
    #[serde(deserialize_with = "null_as_nan")]
    pub mu_ratio: f64,
    /// Total force of the rigid-mode drag on the sheet (ton-force, z).
    pub drag_force: f64,
    /// cond₂ of every Picard iteration's system matrix (only if requested).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub iteration_cond2: Vec<f64>,
}

/// The sheet state at a given punch travel (for figures).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Snapshot {
    /// Punch travel (in).
    pub travel: f64,
    /// Node coordinates r (in).
    pub r: Vec<f64>,
    /// Node coordinates z (in).
    pub z: Vec<f64>,
    /// Initial mid radius of each element (in).
    pub r0: Vec<f64>,
    /// Thickness strain ln(t/t₀) per element.
    pub thickness_strain: Vec<f64>,
    /// Mid-surface equivalent strain per element.
    pub eps_bar: Vec<f64>,
    /// Punch tip z (in).
    pub punch_tip_z: f64,
}

/// A node close to a tool: a possible contact constraint for the step.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ContactCandidate {
    /// Node index.
    pub node: usize,
    /// Tool.
    pub tool: ToolId,
    /// Gap at the start of the step (in).
    pub gap: f64,
    /// Outward tool normal.
    pub normal: [f64; 2],
    /// Tangent τ.
    pub tangent: [f64; 2],
    /// Tool velocity.
    pub tool_velocity: [f64; 2],
    /// Global direction e of the constrained local DOF (the normal of the node's nearest
    /// tool, or e_z at the axis node); τ is perpendicular to e.
    pub dof_direction: [f64; 2],
    /// `n·e = ±1` (−1 only at the axis node under the punch): the constraint is
    /// `v·e = sign · û` when active.
    pub sign: f64,
    /// Index of the constrained DOF in the reduced system.
    pub dof: usize,
    /// Holder load on the node (ton-force, ≥ 0).
    pub holder: f64,
}

/// Everything about the last solve of the last step (for checks and tests).
#[derive(Clone, Debug)]
pub struct StepDetail {
    /// The problem of the last Picard iteration.
    pub problem: Problem,
    /// Its solution.
    pub solution: Solution,
    /// Contact candidates of the step.
    pub candidates: Vec<ContactCandidate>,
    /// Candidate index of each constraint of `problem` (the columns of D).
    pub constraint_candidate: Vec<usize>,
    /// Friction coefficient c per candidate (ton-force·s/in).
    pub friction_c: Vec<f64>,
    /// μ* per element and layer used in the last solve.
    pub mu: Vec<Vec<f64>>,
    /// Global velocities (3 per node) of the last solve.
    pub v: Vec<f64>,
    /// Node coordinates at the start of the step.
    pub x: Vec<[f64; 2]>,
    /// Element thicknesses at the start of the step.
    pub t: Vec<f64>,
    /// Global external loads (3 per node; holder loads).
    pub q: Vec<f64>,
    /// Rigid-mode drag coefficient on the v_z DOFs.
    pub drag: f64,
    /// Punch force reported for the step.
    pub punch_force: f64,
}

/// A complete run.
#[derive(Clone, Debug, Serialize)]
pub struct RunResult {
    /// Configuration.
    pub config: FormingConfig,
    /// Contact rule.
    pub rule: ContactRule,
    /// Per-step telemetry.
    pub steps: Vec<StepRecord>,
    /// Sheet snapshots.
    pub snapshots: Vec<Snapshot>,
    /// Wall time of the run (s).
    pub seconds: f64,
}

/// The simulation state. `Clone` lets a caller branch a run (e.g. benchmark one step from a
/// mid-draw state).
#[derive(Clone)]
pub struct Simulation {
    cfg: FormingConfig,
    rule: ContactRule,
    x: Vec<[f64; 2]>,
    r0_elem: Vec<f64>,
    t: Vec<f64>,
    eps_bar: Vec<Vec<f64>>,
    v: Vec<f64>,
    normal_force: Vec<f64>,
    contact_tool: Vec<Option<ToolId>>,
    travel: f64,
    step: usize,
    xi: Vec<f64>,
    w: Vec<f64>,
    detail: Option<StepDetail>,
    snapshots: Vec<Snapshot>,
}

/// Reduced DOF numbering: the global DOFs without the essential BCs.
struct DofNumbering {
    /// Reduced index of each global DOF (`usize::MAX` where fixed).
    reduced: Vec<usize>,
    /// Global index of each reduced DOF.
    free: Vec<usize>,
}

impl DofNumbering {
    fn new(fixed: &[bool]) -> Self {
        let mut reduced = vec![usize::MAX; fixed.len()];
        let mut free = Vec::new();
        for (d, &f) in fixed.iter().enumerate() {
            if !f {
                reduced[d] = free.len();
                free.push(d);
            }
        }
        DofNumbering { reduced, free }
    }
}

/// What a step fixes before its Picard iteration (start-of-step geometry): BCs, holder loads,
/// contact candidates with their local axes and allowed normal velocities, the strategy.
struct StepSetup {
    /// Time step Δt (s).
    dt: f64,
    /// Number of nodes.
    nodes: usize,
    /// Globally fixed DOFs.
    fixed: Vec<bool>,
    /// Holder load per node.
    holder: Vec<f64>,
    /// Reduced DOF numbering.
    dofs: DofNumbering,
    /// Contact candidates, with their reduced DOF.
    cands: Vec<ContactCandidate>,
    /// First candidate of each node (one friction term per node).
    cand_of: Vec<Option<usize>>,
    /// Local axes `T_i = [e τ 0; 0 0 1]` of the candidate nodes (not the axis node).
    rot: Vec<Option<Block>>,
    /// Allowed normal velocity û = V_tool·n − g/Δt per candidate.
    uhat: Vec<f64>,
    /// The strategy for the contact rule.
    method: Method,
}

/// The μ*, drag and friction coefficients a Picard iteration's system was assembled with.
struct Coefficients {
    /// μ* per element and layer.
    mu: Vec<Vec<f64>>,
    /// Rigid-mode drag on the v_z diagonals.
    drag: f64,
    /// Friction coefficient c per candidate.
    friction_c: Vec<f64>,
}

/// A Picard iteration's system `K v = q` in local nodal axes, essential BCs not yet removed.
struct Assembly {
    k: BlockTri,
    q: Vec<f64>,
    coeffs: Coefficients,
}

/// One contact solve: the reduced problem with the contact set as bilateral constraints.
struct ContactSolve {
    problem: Problem,
    solution: Solution,
    /// Candidate index of each constraint (the columns of D).
    active: Vec<usize>,
}

/// The result of a step's Picard iteration.
struct PicardOutcome {
    /// Accepted global velocities (the last solve's, unrelaxed).
    v: Vec<f64>,
    /// Normal force per node from the last solve.
    normal_force: Vec<f64>,
    /// The last solve.
    solve: ContactSolve,
    /// The coefficients of the last solve's system.
    coeffs: Coefficients,
    iterations: usize,
    factorizations: usize,
    converged: bool,
    /// Final relative velocity change.
    change: f64,
    /// cond₂ of every iteration's system matrix (if requested).
    iteration_cond2: Vec<f64>,
}

/// Telemetry of a step's last solve, taken before the geometry update.
struct SolveTelemetry {
    cond2: f64,
    log10_det: f64,
    cond2_k: f64,
    log10_det_ratio: f64,
    cond2_equilibrated: f64,
    cond2_k_equilibrated: f64,
    max_penetration: f64,
    punch_force: f64,
    clipped: usize,
    max_penalty: f64,
    min_penalty: f64,
    mu_ratio: f64,
    drag_force: f64,
}

/// Aitken's dynamic relaxation (Irons–Tuck) of the Picard fixed-point map.
struct Relaxation {
    omega: f64,
    aitken: bool,
    prev_res: Option<Vec<f64>>,
}

impl Relaxation {
    /// Moves `v` to `v_new` if `accept`, else by `ω (v_new − v)`; with Aitken, first
    /// `ω_k = −ω_{k−1} r_{k−1}ᵀ(r_k − r_{k−1}) / |r_k − r_{k−1}|²`, clamped.
    fn apply(&mut self, v: &mut [f64], v_new: &[f64], accept: bool) {
        let res: Vec<f64> = v_new.iter().zip(v.iter()).map(|(a, b)| a - b).collect();
        if self.aitken {
            if let Some(prev) = &self.prev_res {
                let (mut num, mut den) = (0.0, 0.0);
                for (a, b) in res.iter().zip(prev) {
                    num += b * (a - b);
                    den += (a - b) * (a - b);
                }
                if den > 0.0 {
                    self.omega = (-self.omega * num / den).clamp(0.05, 2.0);
                }
            }
        }
        if accept {
            v.copy_from_slice(v_new);
        } else {
            for (a, r) in v.iter_mut().zip(&res) {
                *a += self.omega * r;
            }
        }
        self.prev_res = Some(res);
    }
}

/// Normal velocity `v·n` of a candidate's node.
fn vn(v: &[f64], c: &ContactCandidate) -> f64 {
    v[3 * c.node] * c.normal[0] + v[3 * c.node + 1] * c.normal[1]
}

/// Tangential velocities `(v_t, V_t)` of a candidate's node and its tool.
fn tangential(v: &[f64], c: &ContactCandidate) -> (f64, f64) {
    let i = c.node;
    let vt = v[3 * i] * c.tangent[0] + v[3 * i + 1] * c.tangent[1];
    let vtt = c.tool_velocity[0] * c.tangent[0] + c.tool_velocity[1] * c.tangent[1];
    (vt, vtt)
}

/// Adds one friction term `c ττᵀ` to node `i`'s diagonal block and `c V_t τ` to its load.
fn add_friction_term(
    k: &mut BlockTri,
    q: &mut [f64],
    i: usize,
    tau: [f64; 2],
    vt_tool: f64,
    c: f64,
) {
    for a in 0..2 {
        for b in 0..2 {
            k.d[i][a][b] += c * tau[a] * tau[b];
        }
        q[3 * i + a] += c * vt_tool * tau[a];
    }
}

/// Rotates the candidate nodes' blocks and loads to their local axes `(e, τ)`.
fn rotate_to_local(rot: &[Option<Block>], k: &mut BlockTri, q: &mut [f64]) {
    k.rotate(rot);
    for (i, t) in rot.iter().enumerate() {
        if let Some(t) = t {
            let (a, b) = (q[3 * i], q[3 * i + 1]);
            q[3 * i] = t[0][0] * a + t[1][0] * b;
            q[3 * i + 1] = t[0][1] * a + t[1][1] * b;
        }
    }
}

/// Picard change `max|v_new − v| / max(max|v_new|, v_punch)` over the nodal velocities
/// (v_r, v_z); rotation rates β are in other units (rad/s) and follow the velocity gradients.
fn picard_change(v_new: &[f64], v: &[f64], punch_speed: f64) -> f64 {
    let (mut vmax, mut dmax) = (0.0f64, 0.0f64);
    for d in (0..v.len()).filter(|d| d % 3 != 2) {
        vmax = vmax.max(v_new[d].abs());
        dmax = dmax.max((v_new[d] - v[d]).abs());
    }
    dmax / vmax.max(punch_speed)
}

impl StepSetup {
    /// Global velocities (3 per node, global axes) from a reduced local-axes solution.
    fn global_velocities(&self, u: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; 3 * self.nodes];
        for (j, &d) in self.dofs.free.iter().enumerate() {
            v[d] = u[j];
        }
        for c in &self.cands {
            if c.node == 0 {
                continue;
            }
            let (p0, p1) = (3 * c.node, 3 * c.node + 1);
            let (a, b) = (v[p0], v[p1]);
            v[p0] = a * c.normal[0] + b * c.tangent[0];
            v[p1] = a * c.normal[1] + b * c.tangent[1];
        }
        v
    }

    /// The reduced local-axes vector of global velocities `v` (inverse of
    /// `global_velocities`).
    fn local_reduced(&self, v: &[f64]) -> Vec<f64> {
        let mut g = v.to_vec();
        for c in self.cands.iter().filter(|c| c.node != 0) {
            let (p0, p1) = (3 * c.node, 3 * c.node + 1);
            let (a, b) = (v[p0], v[p1]);
            g[p0] = a * c.normal[0] + b * c.normal[1];
            g[p1] = a * c.tangent[0] + b * c.tangent[1];
        }
        self.dofs.free.iter().map(|&d| g[d]).collect()
    }

    /// Normal force `N = (−r_c e)·n` per node of a solve's constraints.
    fn normal_forces(&self, s: &ContactSolve) -> Vec<f64> {
        let mut normal_force = vec![0.0; self.nodes];
        for (k, &ci) in s.active.iter().enumerate() {
            let c = &self.cands[ci];
            let r = s.solution.forces[k];
            let f = [-r * c.dof_direction[0], -r * c.dof_direction[1]];
            normal_force[c.node] = f[0] * c.normal[0] + f[1] * c.normal[1];
        }
        normal_force
    }

    /// Contact-set update: release tensile contacts, add penetrating candidates (one
    /// constraint per node).
    fn update_contact_set(
        &self,
        in_contact: &[bool],
        normal_force: &[f64],
        v_new: &[f64],
        punch_speed: f64,
    ) -> Vec<bool> {
        let cands = &self.cands;
        let mut new_set: Vec<bool> = (0..cands.len())
            .map(|ci| in_contact[ci] && normal_force[cands[ci].node] >= 0.0)
            .collect();
        let mut taken = vec![false; self.nodes];
        for (ci, c) in cands.iter().enumerate() {
            taken[c.node] |= new_set[ci];
        }
        for (ci, c) in cands.iter().enumerate() {
            if !in_contact[ci]
                && !taken[c.node]
                && vn(v_new, c) < self.uhat[ci] - 1e-9 * punch_speed
            {
                new_set[ci] = true;
                taken[c.node] = true;
            }
        }
        new_set
    }

    /// Punch force `−Σ_punch (N n_z + f τ_z)`, `f = −c (v_t − V_t)` (see module docs).
    fn punch_force(&self, v: &[f64], friction_c: &[f64], normal_force: &[f64]) -> f64 {
        let mut punch_force = 0.0;
        for (ci, c) in self.cands.iter().enumerate() {
            if c.tool != ToolId::Punch {
                continue;
            }
            let (vt, vtt) = tangential(v, c);
            let f = -friction_c[ci] * (vt - vtt);
            punch_force -= normal_force[c.node] * c.normal[1] + f * c.tangent[1];
        }
        punch_force
    }

    /// The tool each node is in contact with after a solve with constraints `active`.
    fn contact_tools(&self, active: &[usize]) -> Vec<Option<ToolId>> {
        let mut contact_tool = vec![None; self.nodes];
        for &ci in active {
            contact_tool[self.cands[ci].node] = Some(self.cands[ci].tool);
        }
        contact_tool
    }
}

impl Simulation {
    /// A flat blank of `cfg.elements` equal elements on z = 0, punch touching its top surface.
    pub fn new(cfg: &FormingConfig, rule: ContactRule) -> Result<Self> {
        cfg.validate()?;
        rule.validate()?;
        let ne = cfg.elements;
        let x: Vec<[f64; 2]> = (0..=ne)
            .map(|i| [cfg.blank_radius * i as f64 / ne as f64, 0.0])
            .collect();
        let r0_elem = (0..ne).map(|e| 0.5 * (x[e][0] + x[e + 1][0])).collect();
        let (xi, w) = element::gauss_layers(cfg.layers);
        Ok(Simulation {
            cfg: cfg.clone(),
            rule,
            x,
            r0_elem,
            t: vec![cfg.thickness; ne],
            eps_bar: vec![vec![0.0; cfg.layers]; ne],
            v: vec![0.0; 3 * (ne + 1)],
            normal_force: vec![0.0; ne + 1],
            contact_tool: vec![None; ne + 1],
            travel: 0.0,
            step: 0,
            xi,
            w,
            detail: None,
            snapshots: Vec::new(),
        })
    }

    /// Runs all steps and returns the telemetry.
    pub fn run(cfg: &FormingConfig, rule: ContactRule) -> Result<RunResult> {
        match Simulation::run_until_failure(cfg, rule)? {
            (r, None) => Ok(r),
            (_, Some(e)) => Err(e),
        }
    }

    /// Runs all steps, or up to the first step that fails; returns the telemetry of the steps
    /// done and that step's error. Bad input is still an error.
    pub fn run_until_failure(
        cfg: &FormingConfig,
        rule: ContactRule,
    ) -> Result<(RunResult, Option<Error>)> {
        let t0 = Instant::now();
        let mut sim = Simulation::new(cfg, rule)?;
        let mut steps = Vec::with_capacity(cfg.steps);
        let mut failure = None;
        for _ in 0..cfg.steps {
            match sim.step() {
                Ok(s) => steps.push(s),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
        }
        let r = RunResult {
            config: cfg.clone(),
            rule,
            steps,
            snapshots: sim.snapshots.clone(),
            seconds: t0.elapsed().as_secs_f64(),
        };
        Ok((r, failure))
    }

    /// Node coordinates (r, z).
    pub fn nodes(&self) -> &[[f64; 2]] {
        &self.x
    }

    /// Element thicknesses.
    pub fn thickness(&self) -> &[f64] {
        &self.t
    }

    /// Current punch travel (in).
    pub fn travel(&self) -> f64 {
        self.travel
    }

    /// Snapshots taken so far.
    pub fn snapshots(&self) -> &[Snapshot] {
        &self.snapshots
    }

    /// The last solve of the last step.
    pub fn detail(&self) -> Option<&StepDetail> {
        self.detail.as_ref()
    }

    /// The punch at the current travel.
    pub fn punch(&self) -> Punch {
        let c = &self.cfg;
        Punch {
            radius: c.punch.radius,
            profile_radius: c.punch.profile_radius.unwrap_or(c.punch.radius),
            tip_z: 0.5 * c.thickness - self.travel,
        }
    }

    /// The die.
    pub fn die(&self) -> Die {
        let c = &self.cfg;
        Die {
            opening_radius: c.die.opening_radius,
            profile_radius: c.die.profile_radius,
            face_z: -0.5 * c.thickness,
        }
    }

    /// Sheet volume `Σ 2π r_m L t` (in³).
    pub fn volume(&self) -> f64 {
        (0..self.t.len())
            .map(|e| ElementGeom::new(self.x[e], self.x[e + 1]).area() * self.t[e])
            .sum()
    }

    fn node_thickness(&self, i: usize) -> f64 {
        let ne = self.t.len();
        if i == 0 {
            self.t[0]
        } else if i == ne {
            self.t[ne - 1]
        } else {
            0.5 * (self.t[i - 1] + self.t[i])
        }
    }

    /// Globally fixed DOFs (axis: v_r, β; clamped rim: all three).
    fn fixed(&self) -> Vec<bool> {
        let n = 3 * self.x.len();
        let mut f = vec![false; n];
        f[0] = true;
        f[2] = true;
        if self.cfg.clamped_rim {
            let last = self.x.len() - 1;
            for d in 0..3 {
                f[3 * last + d] = true;
            }
        }
        f
    }

    /// μ* per element and layer for global velocities `v` (Eq. 4 with the cut-off).
    pub fn mu_star(&self, v: &[f64]) -> Vec<Vec<f64>> {
        let m = &self.cfg.material;
        (0..self.t.len())
            .map(|e| {
                let g = ElementGeom::new(self.x[e], self.x[e + 1]);
                let ve: [f64; 6] = std::array::from_fn(|k| v[3 * e + k]);
                let sr = element::strain_rates(&g, &ve);
                let eb: f64 = self.eps_bar[e]
                    .iter()
                    .zip(&self.w)
                    .map(|(e, w)| 0.5 * w * e)
                    .sum();
                match self.cfg.mu_through_thickness {
                    MuThroughThickness::Layered => {}
                    MuThroughThickness::Midsurface => {
                        let mu = m.mu_star(eb, element::effective_rate(sr.eps_s, sr.eps_theta));
                        return vec![mu; self.xi.len()];
                    }
                    MuThroughThickness::Rms => {
                        let ms: f64 = self
                            .xi
                            .iter()
                            .zip(&self.w)
                            .map(|(&x, &w)| {
                                let (a, b) = sr.at(0.5 * x * self.t[e]);
                                0.5 * w * element::effective_rate(a, b).powi(2)
                            })
                            .sum();
                        return vec![m.mu_star(eb, ms.sqrt()); self.xi.len()];
                    }
                }
                self.xi
                    .iter()
                    .zip(&self.eps_bar[e])
                    .map(|(&x, &eb)| {
                        let (a, b) = sr.at(0.5 * x * self.t[e]);
                        m.mu_star(eb, element::effective_rate(a, b))
                    })
                    .collect()
            })
            .collect()
    }

    /// Global material matrix (block-tridiagonal, global axes) for μ* `mu`.
    pub fn material_matrix(&self, mu: &[Vec<f64>]) -> BlockTri {
        let mut k = BlockTri::zeros(self.x.len());
        for e in 0..self.t.len() {
            let g = ElementGeom::new(self.x[e], self.x[e + 1]);
            let ke = element::element_matrix(&g, self.t[e], &mu[e], &self.xi, &self.w);
            k.add_element(e, &ke);
        }
        k
    }

    /// Holder load H_i (ton-force, ≥ 0, acting in −z) per node.
    fn holder_loads(&self) -> Vec<f64> {
        let nn = self.x.len();
        let mut h = vec![0.0; nn];
        if self.cfg.holder_force <= 0.0 || self.cfg.clamped_rim {
            return h;
        }
        let r_h = self.cfg.die.opening_radius + self.cfg.die.profile_radius;
        for e in 0..self.t.len() {
            let g = ElementGeom::new(self.x[e], self.x[e + 1]);
            if g.r_m >= r_h {
                h[e] += 0.5 * g.area();
                h[e + 1] += 0.5 * g.area();
            }
        }
        let total: f64 = h.iter().sum();
        if total > 0.0 {
            for v in &mut h {
                *v *= self.cfg.holder_force / total;
            }
        }
        h
    }

    /// Contact candidates: per node the nearest tool; its normal fixes the node's local axes.
    fn candidates(&self, dt: f64, holder: &[f64], fixed: &[bool]) -> Vec<ContactCandidate> {
        let punch = self.punch();
        let die = self.die();
        let vp = self.cfg.punch_speed;
        let capture = (3.0 * vp * dt).max(self.cfg.thickness);
        let mut out = Vec::new();
        for i in 0..self.x.len() {
            if fixed[3 * i] && fixed[3 * i + 1] {
                continue;
            }
            let p = self.x[i];
            let half = 0.5 * self.node_thickness(i);
            let mut tools: Vec<(ToolId, f64, [f64; 2], [f64; 2])> = Vec::with_capacity(3);
            let (dp, np) = punch.distance(p);
            tools.push((ToolId::Punch, dp - half, np, [0.0, -vp]));
            let (dd, nd) = die.distance(p);
            tools.push((ToolId::Die, dd - half, nd, [0.0, 0.0]));
            let k = (0..tools.len())
                .min_by(|&a, &b| tools[a].1.total_cmp(&tools[b].1))
                .expect("two tools at least");
            let (tool, gap, mut n, vel) = tools[k];
            if gap >= capture {
                continue;
            }
            if i == 0 {
                n = [0.0, if n[1] >= 0.0 { 1.0 } else { -1.0 }];
            }
            let e = if i == 0 { [0.0, 1.0] } else { n };
            let tangent = [e[1], -e[0]];
            out.push(ContactCandidate {
                node: i,
                tool,
                gap,
                normal: n,
                tangent,
                tool_velocity: vel,
                dof_direction: e,
                sign: n[0] * e[0] + n[1] * e[1],
                dof: usize::MAX,
                holder: holder[i],
            });
        }
        out
    }

    /// Advances one time step; returns its telemetry.
    pub fn step(&mut self) -> Result<StepRecord> {
        let setup = self.prepare_step();
        let picard = self.picard(&setup)?;
        let tel = self.telemetry(&setup, &picard)?;
        let contact_tool = setup.contact_tools(&picard.solve.active);
        self.detail = Some(self.step_detail(&setup, &picard, tel.punch_force));
        self.advance(&picard.v, setup.dt);
        self.v = picard.v;
        self.normal_force = picard.normal_force;
        self.contact_tool = contact_tool;
        let geometric_penetration = self.geometric_penetration(&setup.cands, &picard.solve.active);
        self.take_snapshots();
        Ok(StepRecord {
            step: self.step,
            punch_travel: self.travel,
            punch_force: tel.punch_force,
            cond2: tel.cond2,
            log10_det: tel.log10_det,
            cond2_k: tel.cond2_k,
            log10_det_ratio: tel.log10_det_ratio,
            cond2_equilibrated: tel.cond2_equilibrated,
            cond2_k_equilibrated: tel.cond2_k_equilibrated,
            max_penetration: tel.max_penetration,
            geometric_penetration,
            volume: self.volume(),
            rim_r: self.x.last().map_or(f64::NAN, |p| p[0]),
            iterations: picard.iterations,
            factorizations: picard.factorizations,
            converged: picard.converged,
            picard_change: picard.change,
            contact_nodes: picard.solve.active.len(),
            candidates: setup.cands.len(),
            clipped: tel.clipped,
            max_penalty: tel.max_penalty,
            min_penalty: tel.min_penalty,
            mu_ratio: tel.mu_ratio,
            drag_force: tel.drag_force,
            iteration_cond2: picard.iteration_cond2,
        })
    }

    /// Step phase 1: BCs, reduced numbering, holder loads, contact candidates with their
    /// local axes and allowed normal velocities, the strategy.
    fn prepare_step(&self) -> StepSetup {
        let dt = self.cfg.dt();
        let nodes = self.x.len();
        let fixed = self.fixed();
        let holder = self.holder_loads();
        let mut cands = self.candidates(dt, &holder, &fixed);
        let dofs = DofNumbering::new(&fixed);
        for c in cands.iter_mut() {
            c.dof = if c.node == 0 {
                dofs.reduced[1]
            } else {
                dofs.reduced[3 * c.node]
            };
        }
        let mut cand_of = vec![None; nodes];
        for (k, c) in cands.iter().enumerate() {
            if cand_of[c.node].is_none() {
                cand_of[c.node] = Some(k);
            }
        }
        // Local axes T_i = [e τ 0; 0 0 1]; the axis node keeps global axes.
        let mut rot: Vec<Option<Block>> = vec![None; nodes];
        for c in cands.iter().filter(|c| c.node != 0) {
            let (nv, tv) = (c.dof_direction, c.tangent);
            rot[c.node] = Some([[nv[0], tv[0], 0.0], [nv[1], tv[1], 0.0], [0.0, 0.0, 1.0]]);
        }
        // Allowed normal velocities û = V_tool·n − g/Δt; the axis node with n = −e_z is
        // constrained on v_z = −v·n (sign −1).
        let uhat = cands
            .iter()
            .map(|c| {
                c.tool_velocity[0] * c.normal[0] + c.tool_velocity[1] * c.normal[1] - c.gap / dt
            })
            .collect();
        let method = match self.rule {
            ContactRule::Classical { eps } => Method::constant(eps),
            ContactRule::PaperLiteral { delta } | ContactRule::PaperResidual { delta } => {
                Method::paper(delta / dt)
            }
            ContactRule::Condensed { delta } => Method::condensed(delta / dt),
        };
        StepSetup {
            dt,
            nodes,
            fixed,
            holder,
            dofs,
            cands,
            cand_of,
            rot,
            uhat,
            method,
        }
    }

    /// The initial contact set: the previous step's contacts plus the candidates the
    /// velocity guess `v` violates, at most one per node.
    fn initial_contact_set(&self, s: &StepSetup, v: &[f64]) -> Vec<bool> {
        let mut in_contact = vec![false; s.cands.len()];
        let mut taken = vec![false; s.nodes];
        for pass in 0..2 {
            for (ci, c) in s.cands.iter().enumerate() {
                let on = if pass == 0 {
                    self.contact_tool[c.node] == Some(c.tool)
                } else {
                    vn(v, c) < s.uhat[ci]
                };
                if on && !taken[c.node] {
                    in_contact[ci] = true;
                    taken[c.node] = true;
                }
            }
        }
        in_contact
    }

    /// Step phase 2: Picard iteration on `K[μ*(v)] v = q` with the contact-set update and
    /// (Aitken) relaxation; see the module docs.
    fn picard(&self, s: &StepSetup) -> Result<PicardOutcome> {
        let pc = &self.cfg.picard;
        let vp = self.cfg.punch_speed;
        let mut v = self.v.clone();
        let mut in_contact = self.initial_contact_set(s, &v);
        let mut normal_force = self.normal_force.clone();
        let mut relax = Relaxation {
            omega: pc.relaxation,
            aitken: pc.aitken,
            prev_res: None,
        };
        let mut anderson = Anderson::new(pc.anderson, pc.relaxation);
        let (mut iterations, mut factorizations) = (0, 0);
        let (mut converged, mut change) = (false, f64::INFINITY);
        let mut iteration_cond2 = Vec::new();
        let mut last = None;
        while iterations < pc.max_iterations {
            iterations += 1;
            let asm = self.assemble(s, &v, &normal_force);
            let solve = self.solve_contact(s, &asm, &in_contact, &v)?;
            factorizations += solve.solution.stats.factorizations;
            if self.cfg.cond_per_iteration {
                let sys = metrics::system_matrix(&solve.problem, &solve.solution);
                iteration_cond2.push(conditioning::cond2(&sys)?.cond2);
            }
            let v_new = s.global_velocities(&solve.solution.u);
            normal_force = s.normal_forces(&solve);
            let new_set = s.update_contact_set(&in_contact, &normal_force, &v_new, vp);
            let set_changed = new_set != in_contact;
            change = picard_change(&v_new, &v, vp);
            let done = change <= pc.tol && !set_changed;
            let accept = done || iterations >= pc.max_iterations;
            if pc.anderson == 0 {
                relax.apply(&mut v, &v_new, accept);
            } else if accept {
                v.copy_from_slice(&v_new);
            } else {
                if set_changed {
                    anderson.reset();
                }
                anderson.apply(&mut v, &v_new);
            }
            last = Some((solve, asm.coeffs));
            in_contact = new_set;
            if done {
                converged = true;
                break;
            }
        }
        let (solve, coeffs) = last.expect("at least one iteration");
        Ok(PicardOutcome {
            v,
            normal_force,
            solve,
            coeffs,
            iterations,
            factorizations,
            converged,
            change,
            iteration_cond2,
        })
    }

    /// Assembles a Picard iterate's system in local axes: material matrix for μ*(v),
    /// rigid-mode drag, holder loads, lagged friction, rotation to the candidates' axes.
    fn assemble(&self, s: &StepSetup, v: &[f64], normal_force: &[f64]) -> Assembly {
        let mu = self.mu_star(v);
        let mut k = self.material_matrix(&mu);
        // Rigid-mode drag on v_z.
        let kzz_max = k.d.iter().map(|b| b[1][1]).fold(0.0, f64::max);
        let drag = self.cfg.drag * kzz_max;
        for b in k.d.iter_mut() {
            b[1][1] += drag;
        }
        let mut q = vec![0.0; 3 * s.nodes];
        for (i, h) in s.holder.iter().enumerate() {
            q[3 * i + 1] -= h;
        }
        let friction_c = self.add_friction(s, v, normal_force, &mut k, &mut q);
        rotate_to_local(&s.rot, &mut k, &mut q);
        Assembly {
            k,
            q,
            coeffs: Coefficients {
                mu,
                drag,
                friction_c,
            },
        }
    }

    /// Lagged regularized Coulomb friction `c ττᵀ`, `c V_t τ` (global axes),
    /// `c = μ (N + H) / sqrt((v_t − V_t)² + v₀²)`: one term per candidate node (not the axis,
    /// whose tangent is radial and fixed), radial holder friction on the other loaded nodes.
    /// Returns c per candidate.
    fn add_friction(
        &self,
        s: &StepSetup,
        v: &[f64],
        normal_force: &[f64],
        k: &mut BlockTri,
        q: &mut [f64],
    ) -> Vec<f64> {
        let mut fric_c = vec![0.0; s.cands.len()];
        let mu_f = self.cfg.friction;
        let v0 = self.cfg.friction_v0;
        if mu_f <= 0.0 {
            return fric_c;
        }
        for (ci, c) in s.cands.iter().enumerate() {
            if c.node == 0 || s.cand_of[c.node] != Some(ci) {
                continue;
            }
            let (vt, vtt) = tangential(v, c);
            let p = normal_force[c.node].max(0.0) + c.holder;
            let cc = mu_f * p / ((vt - vtt).powi(2) + v0 * v0).sqrt();
            fric_c[ci] = cc;
            add_friction_term(k, q, c.node, c.tangent, vtt, cc);
        }
        for (i, &h) in s.holder.iter().enumerate() {
            if h > 0.0 && s.cand_of[i].is_none() && !s.fixed[3 * i] {
                let cc = mu_f * h / (v[3 * i].powi(2) + v0 * v0).sqrt();
                add_friction_term(k, q, i, [1.0, 0.0], 0.0, cc);
            }
        }
        fric_c
    }

    /// Removes the essential BCs, makes the contact set bilateral constraints `v·e = sign û`
    /// and solves with the step's strategy; `paper-residual` evaluates Eq. 28 at the current
    /// iterate `v` (global velocities).
    fn solve_contact(
        &self,
        s: &StepSetup,
        asm: &Assembly,
        in_contact: &[bool],
        v: &[f64],
    ) -> Result<ContactSolve> {
        let kmat = asm.k.to_stiffness(&s.dofs.reduced, s.dofs.free.len())?;
        let qr: Vec<f64> = s.dofs.free.iter().map(|&d| asm.q[d]).collect();
        let active: Vec<usize> = (0..s.cands.len()).filter(|&c| in_contact[c]).collect();
        let constraints: Vec<Constraint> = active
            .iter()
            .map(|&ci| Constraint {
                dof: s.cands[ci].dof,
                limit: s.cands[ci].sign * s.uhat[ci],
                kind: ConstraintKind::Bilateral,
            })
            .collect();
        let problem = Problem::new(kmat, qr, constraints)?;
        let paper_delta = s
            .method
            .delta()
            .filter(|_| s.method.is(&strategy::paper::STRATEGY));
        let solution = match (self.rule, paper_delta) {
            (ContactRule::PaperResidual { .. }, Some(delta)) => {
                let u_ref = s.local_reduced(v);
                strategy::paper::solve_residual(
                    &problem,
                    delta,
                    &u_ref,
                    RESIDUAL_RTOL,
                    RESIDUAL_PASSES,
                )?
            }
            _ => strategy::solve(&problem, s.method)?,
        };
        if solution.u.iter().any(|x| !x.is_finite()) {
            return Err(Error::Numerical(format!(
                "step {}: the velocity solution is not finite",
                self.step + 1
            )));
        }
        Ok(ContactSolve {
            problem,
            solution,
            active,
        })
    }

    /// K alone for the last solve's coefficients: material matrix and drag, rotated to the
    /// candidates' local axes, essential BCs removed; no penalty, no friction.
    fn k_alone(&self, s: &StepSetup, c: &Coefficients) -> Result<crate::system::Stiffness> {
        let mut k = self.material_matrix(&c.mu);
        for b in k.d.iter_mut() {
            b[1][1] += c.drag;
        }
        k.rotate(&s.rot);
        k.to_stiffness(&s.dofs.reduced, s.dofs.free.len())
    }

    /// Step phase 3: telemetry of the last solve (cond₂, log10|det|, penetration, punch
    /// force, penalty range, μ* spread, drag force).
    fn telemetry(&self, s: &StepSetup, p: &PicardOutcome) -> Result<SolveTelemetry> {
        let v = &p.v;
        // Velocity-level penetration of every candidate, in length.
        let max_penetration = (0..s.cands.len())
            .map(|ci| (s.uhat[ci] - vn(v, &s.cands[ci])).max(0.0) * s.dt)
            .fold(0.0, f64::max);
        let sys = metrics::system_matrix(&p.solve.problem, &p.solve.solution);
        let cond2 = conditioning::cond2(&sys)?.cond2;
        let log10_det = conditioning::log10_abs_det(&sys)?;
        let k_alone = self.k_alone(s, &p.coeffs)?;
        let cond2_k = conditioning::cond2(&k_alone)?.cond2;
        let log10_det_ratio = log10_det - conditioning::log10_abs_det(&k_alone)?;
        let equilibrated = |a: &crate::system::Stiffness| {
            conditioning::cond2(&a.scaled(&a.equilibration())).map(|r| r.cond2)
        };
        let cond2_equilibrated = equilibrated(&sys)?;
        let cond2_k_equilibrated = equilibrated(&k_alone)?;
        let punch_force = s.punch_force(v, &p.coeffs.friction_c, &p.normal_force);
        let sol = &p.solve.solution;
        let active: Vec<f64> = sol.penalties.iter().copied().filter(|&e| e > 0.0).collect();
        let (mut mu_min, mut mu_max) = (f64::INFINITY, 0.0f64);
        for m in p.coeffs.mu.iter().flatten() {
            mu_min = mu_min.min(*m);
            mu_max = mu_max.max(*m);
        }
        let drag = p.coeffs.drag;
        Ok(SolveTelemetry {
            cond2,
            log10_det,
            cond2_k,
            log10_det_ratio,
            cond2_equilibrated,
            cond2_k_equilibrated,
            max_penetration,
            punch_force,
            clipped: sol.stats.clipped,
            max_penalty: active.iter().copied().fold(0.0, f64::max),
            min_penalty: if active.is_empty() {
                0.0
            } else {
                active.iter().copied().fold(f64::INFINITY, f64::min)
            },
            mu_ratio: mu_max / mu_min,
            drag_force: (0..s.nodes).map(|i| drag * v[3 * i + 1]).sum(),
        })
    }

    /// Everything about the step's last solve, on the start-of-step geometry.
    fn step_detail(&self, s: &StepSetup, p: &PicardOutcome, punch_force: f64) -> StepDetail {
        let q = (0..3 * s.nodes)
            .map(|d| if d % 3 == 1 { -s.holder[d / 3] } else { 0.0 })
            .collect();
        StepDetail {
            problem: p.solve.problem.clone(),
            solution: p.solve.solution.clone(),
            candidates: s.cands.clone(),
            constraint_candidate: p.solve.active.clone(),
            friction_c: p.coeffs.friction_c.clone(),
            mu: p.coeffs.mu.clone(),
            v: p.v.clone(),
            x: self.x.clone(),
            t: self.t.clone(),
            q,
            drag: p.coeffs.drag,
            punch_force,
        }
    }

    /// Step phase 4 (updated Lagrangian): `ε̄ += ε̄̇ Δt` per layer, thickness, `x += v Δt`,
    /// punch travel, step count.
    fn advance(&mut self, v: &[f64], dt: f64) {
        let update = self.cfg.thickness_update;
        let ne = self.t.len();
        let areas_old: Vec<f64> = (0..ne)
            .map(|e| ElementGeom::new(self.x[e], self.x[e + 1]).area())
            .collect();
        for e in 0..ne {
            let g = ElementGeom::new(self.x[e], self.x[e + 1]);
            let ve: [f64; 6] = std::array::from_fn(|k| v[3 * e + k]);
            let sr = element::strain_rates(&g, &ve);
            for (l, &x) in self.xi.iter().enumerate() {
                let (a, b) = sr.at(0.5 * x * self.t[e]);
                self.eps_bar[e][l] += element::effective_rate(a, b) * dt;
            }
            if update == ThicknessUpdate::Rate {
                self.t[e] *= (sr.thickness_rate() * dt).exp();
            }
        }
        for (i, x) in self.x.iter_mut().enumerate() {
            x[0] += v[3 * i] * dt;
            x[1] += v[3 * i + 1] * dt;
        }
        self.x[0][0] = 0.0;
        if update == ThicknessUpdate::Volume {
            for e in 0..ne {
                let a = ElementGeom::new(self.x[e], self.x[e + 1]).area();
                self.t[e] *= areas_old[e] / a;
            }
        }
        self.travel += self.cfg.punch_speed * dt;
        self.step += 1;
    }

    /// Max geometric penetration of the constrained nodes into their tools (current
    /// geometry).
    fn geometric_penetration(&self, cands: &[ContactCandidate], active: &[usize]) -> f64 {
        let (punch, die) = (self.punch(), self.die());
        let mut geo = 0.0f64;
        for &ci in active {
            let c = &cands[ci];
            let p = self.x[c.node];
            let half = 0.5 * self.node_thickness(c.node);
            let d = match c.tool {
                ToolId::Punch => punch.distance(p).0,
                ToolId::Die => die.distance(p).0,
            } - half;
            geo = geo.max(-d);
        }
        geo
    }

    /// Takes the snapshots whose travel the current travel matches (half a step each side),
    /// once each.
    fn take_snapshots(&mut self) {
        let h = 0.5 * self.cfg.travel / self.cfg.steps as f64;
        for &s in &self.cfg.snapshots {
            if (self.travel - s).abs() <= h * (1.0 + 1e-9)
                && !self.snapshots.iter().any(|x| (x.travel - s).abs() <= h)
            {
                self.snapshots.push(self.snapshot());
            }
        }
    }

    /// The current sheet state.
    pub fn snapshot(&self) -> Snapshot {
        let t0 = self.cfg.thickness;
        Snapshot {
            travel: self.travel,
            r: self.x.iter().map(|p| p[0]).collect(),
            z: self.x.iter().map(|p| p[1]).collect(),
            r0: self.r0_elem.clone(),
            thickness_strain: self.t.iter().map(|t| (t / t0).ln()).collect(),
            eps_bar: self
                .eps_bar
                .iter()
                .map(|l| l.iter().zip(&self.w).map(|(e, w)| 0.5 * w * e).sum())
                .collect(),
            punch_tip_z: self.punch().tip_z,
        }
    }

    /// Punch force of the last step recomputed from equilibrium, independently of the
    /// penalty forces: at every punch-contact node the contact force (normal + friction)
    /// equals `(K_mat v + drag v − q)` in global axes, with K_mat the material matrix for the
    /// μ* of the last solve. Returns `−Σ_punch (K_mat v + drag v − q)_z`.
    pub fn equilibrium_punch_force(&self) -> Option<f64> {
        let d = self.detail.as_ref()?;
        // Material matrix on the start-of-step geometry.
        let ne = d.t.len();
        let n = 3 * d.x.len();
        let mut f = vec![0.0; n];
        for e in 0..ne {
            let g = ElementGeom::new(d.x[e], d.x[e + 1]);
            let ke = element::element_matrix(&g, d.t[e], &d.mu[e], &self.xi, &self.w);
            for a in 0..6 {
                for b in 0..6 {
                    f[3 * e + a] += ke[a][b] * d.v[3 * e + b];
                }
            }
        }
        let mut p = 0.0;
        for c in &d.candidates {
            if c.tool != ToolId::Punch {
                continue;
            }
            let i = c.node;
            p -= f[3 * i + 1] + d.drag * d.v[3 * i + 1] - d.q[3 * i + 1];
        }
        Some(p)
    }
}
