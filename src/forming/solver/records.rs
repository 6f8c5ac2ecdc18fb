//! What a forming run records: per-step telemetry ([`StepRecord`]), snapshots, contact
//! candidates, the detail of a step and the run's result.

use crate::forming::config::{ContactRule, FormingConfig};
use crate::forming::tools::ToolId;
use crate::strategy::Solution;
use crate::system::Problem;
use serde::{Deserialize, Serialize};

fn nan() -> f64 {
    f64::NAN
}

use crate::provenance::null_as_nan;

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
    /// The four cond₂ brackets of the step (system, K, both equilibrated) are proven
    /// ([`crate::conditioning::CondReport::bounds_proven`]); false in records written before.
    #[serde(default)]
    pub cond2_bounds_proven: bool,
    /// The four cond₂ values are proven within the accuracy contract
    /// `max(1e-12, 4·ε_mach·cond₂)` ([`crate::conditioning::CondReport::within_contract`]).
    #[serde(default)]
    pub cond2_within_contract: bool,
    /// cond₂ of the Jacobi-scaled system `S (K + D E Dᵀ) S`, `S = diag(A)^{-1/2}` exactly
    /// (`cond2_jacobi` of [`crate::metrics::solver`]; NaN in records written before).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub cond2_jacobi: f64,
    /// CG iterations with Jacobi to ‖r‖ ≤ 1e-8‖b‖ from 0 on the step's last system (`None`
    /// where CG does not apply or in records written before; not an accuracy: see
    /// `pcg_err_u_at_stop_jacobi`).
    #[serde(default)]
    pub pcg_iters_jacobi: Option<usize>,
    /// Whether that run reached τ within 10·N iterations.
    #[serde(default)]
    pub pcg_converged_jacobi: Option<bool>,
    /// CG iterations with IC(0), the same test.
    #[serde(default)]
    pub pcg_iters_ic0: Option<usize>,
    /// Whether that run reached τ.
    #[serde(default)]
    pub pcg_converged_ic0: Option<bool>,
    /// CG iterations with Jacobi from 0 to the fixed error of u
    /// (`‖v_k − v*‖∞ ≤ 1e-6‖v*‖∞`, v* the refined direct solution of the step's last
    /// system; [`crate::metrics::solver`]): the count the figures and comparisons use.
    #[serde(default)]
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_jacobi_to_err_converged: Option<bool>,
    /// CG iterations with IC(0) to the fixed error of u.
    #[serde(default)]
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_ic0_to_err_converged: Option<bool>,
    /// The relative error of the velocities where the residual-stopped Jacobi run stopped.
    #[serde(default)]
    pub pcg_err_u_at_stop_jacobi: Option<f64>,
    /// The same for IC(0).
    #[serde(default)]
    pub pcg_err_u_at_stop_ic0: Option<f64>,
    /// Relative error of the plain direct solve of the step's last system against its
    /// double-double refinement (`forward_err_u` of [`crate::metrics::solver`]).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub forward_err_u: f64,
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

impl StepRecord {
    /// Jacobi-CG iterations to the error target, where that run reached it.
    pub fn jacobi_iters_to_err(&self) -> Option<usize> {
        crate::metrics::solver::reached(
            self.pcg_iters_jacobi_to_err,
            self.pcg_iters_jacobi_to_err_converged,
        )
    }

    /// IC(0)-CG iterations to the error target, where that run reached it.
    pub fn ic0_iters_to_err(&self) -> Option<usize> {
        crate::metrics::solver::reached(
            self.pcg_iters_ic0_to_err,
            self.pcg_iters_ic0_to_err_converged,
        )
    }
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
