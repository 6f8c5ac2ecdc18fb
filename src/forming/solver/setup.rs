//! The state of one step: reduced DOF numbering, the step's set-up (tools, candidates, loads),
//! the Picard iteration's relaxation and the helpers of its assembly.

use super::records::ContactCandidate;
use crate::forming::assembly::{Block, BlockTri};
use crate::forming::tools::ToolId;
use crate::strategy::{Method, Solution};
use crate::system::Problem;

/// Reduced DOF numbering: the global DOFs without the essential BCs.
pub(super) struct DofNumbering {
    /// Reduced index of each global DOF (`usize::MAX` where fixed).
    pub(super) reduced: Vec<usize>,
    /// Global index of each reduced DOF.
    pub(super) free: Vec<usize>,
}

impl DofNumbering {
    pub(super) fn new(fixed: &[bool]) -> Self {
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
pub(super) struct StepSetup {
    /// Time step Δt (s).
    pub(super) dt: f64,
    /// Number of nodes.
    pub(super) nodes: usize,
    /// Globally fixed DOFs.
    pub(super) fixed: Vec<bool>,
    /// Holder load per node.
    pub(super) holder: Vec<f64>,
    /// Reduced DOF numbering.
    pub(super) dofs: DofNumbering,
    /// Contact candidates, with their reduced DOF.
    pub(super) cands: Vec<ContactCandidate>,
    /// First candidate of each node (one friction term per node).
    pub(super) cand_of: Vec<Option<usize>>,
    /// Local axes `T_i = [e τ 0; 0 0 1]` of the candidate nodes (not the axis node).
    pub(super) rot: Vec<Option<Block>>,
    /// Allowed normal velocity û = V_tool·n − g/Δt per candidate.
    pub(super) uhat: Vec<f64>,
    /// The strategy for the contact rule.
    pub(super) method: Method,
}

/// The μ*, drag and friction coefficients a Picard iteration's system was assembled with.
pub(super) struct Coefficients {
    /// μ* per element and layer.
    pub(super) mu: Vec<Vec<f64>>,
    /// Rigid-mode drag on the v_z diagonals.
    pub(super) drag: f64,
    /// Friction coefficient c per candidate.
    pub(super) friction_c: Vec<f64>,
}

/// A Picard iteration's system `K v = q` in local nodal axes, essential BCs not yet removed.
pub(super) struct Assembly {
    pub(super) k: BlockTri,
    pub(super) q: Vec<f64>,
    pub(super) coeffs: Coefficients,
}

/// One contact solve: the reduced problem with the contact set as bilateral constraints.
pub(super) struct ContactSolve {
    pub(super) problem: Problem,
    pub(super) solution: Solution,
    /// Candidate index of each constraint (the columns of D).
    pub(super) active: Vec<usize>,
}

/// The result of a step's Picard iteration.
pub(super) struct PicardOutcome {
    /// Accepted global velocities (the last solve's, unrelaxed).
    pub(super) v: Vec<f64>,
    /// Normal force per node from the last solve.
    pub(super) normal_force: Vec<f64>,
    /// The last solve.
    pub(super) solve: ContactSolve,
    /// The coefficients of the last solve's system.
    pub(super) coeffs: Coefficients,
    pub(super) iterations: usize,
    pub(super) factorizations: usize,
    pub(super) converged: bool,
    /// Final relative velocity change.
    pub(super) change: f64,
    /// cond₂ of every iteration's system matrix (if requested).
    pub(super) iteration_cond2: Vec<f64>,
}

/// Telemetry of a step's last solve, taken before the geometry update.
pub(super) struct SolveTelemetry {
    pub(super) cond2: f64,
    pub(super) log10_det: f64,
    pub(super) cond2_k: f64,
    pub(super) log10_det_ratio: f64,
    pub(super) cond2_equilibrated: f64,
    pub(super) cond2_k_equilibrated: f64,
    pub(super) cond2_bounds_proven: bool,
    pub(super) cond2_within_contract: bool,
    pub(super) max_penetration: f64,
    pub(super) punch_force: f64,
    pub(super) clipped: usize,
    pub(super) max_penalty: f64,
    pub(super) min_penalty: f64,
    pub(super) mu_ratio: f64,
    pub(super) drag_force: f64,
    /// The solver-cost metrics of the last solve's system ([`crate::metrics::solver`]).
    pub(super) cost: crate::metrics::solver::SolverMetrics,
}

/// Aitken's dynamic relaxation (Irons–Tuck) of the Picard fixed-point map.
pub(super) struct Relaxation {
    pub(super) omega: f64,
    pub(super) aitken: bool,
    pub(super) prev_res: Option<Vec<f64>>,
}

impl Relaxation {
    /// Moves `v` to `v_new` if `accept`, else by `ω (v_new − v)`; with Aitken, first
    /// `ω_k = −ω_{k−1} r_{k−1}ᵀ(r_k − r_{k−1}) / |r_k − r_{k−1}|²`, clamped.
    pub(super) fn apply(&mut self, v: &mut [f64], v_new: &[f64], accept: bool) {
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
pub(super) fn vn(v: &[f64], c: &ContactCandidate) -> f64 {
    v[3 * c.node] * c.normal[0] + v[3 * c.node + 1] * c.normal[1]
}

/// Tangential velocities `(v_t, V_t)` of a candidate's node and its tool.
pub(super) fn tangential(v: &[f64], c: &ContactCandidate) -> (f64, f64) {
    let i = c.node;
    let vt = v[3 * i] * c.tangent[0] + v[3 * i + 1] * c.tangent[1];
    let vtt = c.tool_velocity[0] * c.tangent[0] + c.tool_velocity[1] * c.tangent[1];
    (vt, vtt)
}

/// Adds one friction term `c ττᵀ` to node `i`'s diagonal block and `c V_t τ` to its load.
pub(super) fn add_friction_term(
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
pub(super) fn rotate_to_local(rot: &[Option<Block>], k: &mut BlockTri, q: &mut [f64]) {
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
pub(super) fn picard_change(v_new: &[f64], v: &[f64], punch_speed: f64) -> f64 {
    let (mut vmax, mut dmax) = (0.0f64, 0.0f64);
    for d in (0..v.len()).filter(|d| d % 3 != 2) {
        vmax = vmax.max(v_new[d].abs());
        dmax = dmax.max((v_new[d] - v[d]).abs());
    }
    dmax / vmax.max(punch_speed)
}

impl StepSetup {
    /// Global velocities (3 per node, global axes) from a reduced local-axes solution.
    pub(super) fn global_velocities(&self, u: &[f64]) -> Vec<f64> {
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
    pub(super) fn local_reduced(&self, v: &[f64]) -> Vec<f64> {
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
    pub(super) fn normal_forces(&self, s: &ContactSolve) -> Vec<f64> {
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
    pub(super) fn update_contact_set(
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
    pub(super) fn punch_force(&self, v: &[f64], friction_c: &[f64], normal_force: &[f64]) -> f64 {
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
    pub(super) fn contact_tools(&self, active: &[usize]) -> Vec<Option<ToolId>> {
        let mut contact_tool = vec![None; self.nodes];
        for &ci in active {
            contact_tool[self.cands[ci].node] = Some(self.cands[ci].tool);
        }
        contact_tool
    }
}
