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
//!    contact DOFs, as the paper's D does); the [`Problem`](crate::system::Problem) is solved with
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

use super::assembly::{Block, BlockTri};
use super::config::{ContactRule, FormingConfig, MuThroughThickness, ThicknessUpdate};
use super::element::{self, ElementGeom};
use super::tools::{Die, Punch, ToolId};
use crate::error::{Error, Result};
use crate::strategy::Method;
use std::time::Instant;

mod iteration;
mod records;
mod setup;

pub use records::{ContactCandidate, RunResult, Snapshot, StepDetail, StepRecord};
use setup::*;

/// `paper-residual`: the Eq. 18 corrector passes of a Picard iteration (frozen K) stop when
/// every contact gap is within this fraction of δ of δ ...
pub const RESIDUAL_RTOL: f64 = 0.05;
/// ... or at most this many times per Picard iteration.
pub const RESIDUAL_PASSES: usize = 20;

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
            cond2_bounds_proven: tel.cond2_bounds_proven,
            cond2_within_contract: tel.cond2_within_contract,
            cond2_jacobi: tel.cost.cond2_jacobi.map_or(f64::NAN, |c| c.cond2),
            pcg_iters_jacobi: tel.cost.pcg_jacobi.residual().map(|r| r.iterations),
            pcg_converged_jacobi: tel.cost.pcg_jacobi.residual().map(|r| r.converged),
            pcg_iters_ic0: tel.cost.pcg_ic0.residual().map(|r| r.iterations),
            pcg_converged_ic0: tel.cost.pcg_ic0.residual().map(|r| r.converged),
            pcg_iters_jacobi_to_err: tel.cost.pcg_jacobi.to_err().map(|r| r.iterations),
            pcg_iters_jacobi_to_err_converged: tel.cost.pcg_jacobi.to_err().map(|r| r.converged),
            pcg_iters_ic0_to_err: tel.cost.pcg_ic0.to_err().map(|r| r.iterations),
            pcg_iters_ic0_to_err_converged: tel.cost.pcg_ic0.to_err().map(|r| r.converged),
            pcg_err_u_at_stop_jacobi: tel.cost.pcg_jacobi.err_u_at_stop(),
            pcg_err_u_at_stop_ic0: tel.cost.pcg_ic0.err_u_at_stop(),
            forward_err_u: tel.cost.forward_err_u.unwrap_or(f64::NAN),
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
