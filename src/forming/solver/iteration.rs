//! One step's Picard iteration: assembly, friction, the contact solve with the configured
//! rule, and its telemetry.

use super::records::StepDetail;
use super::setup::{
    add_friction_term, picard_change, rotate_to_local, tangential, vn, Assembly, Coefficients,
    ContactSolve, PicardOutcome, Relaxation, SolveTelemetry, StepSetup,
};
use super::{Simulation, RESIDUAL_PASSES, RESIDUAL_RTOL};
use crate::conditioning;
use crate::error::{Error, Result};
use crate::forming::acceleration::Anderson;
use crate::forming::assembly::BlockTri;
use crate::forming::config::ContactRule;
use crate::metrics;
use crate::strategy;
use crate::system::{Constraint, ConstraintKind, Problem};

impl Simulation {
    /// Step phase 2: Picard iteration on `K[μ*(v)] v = q` with the contact-set update and
    /// (Aitken) relaxation; see the module docs.
    pub(super) fn picard(&self, s: &StepSetup) -> Result<PicardOutcome> {
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
    pub(super) fn assemble(&self, s: &StepSetup, v: &[f64], normal_force: &[f64]) -> Assembly {
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
    pub(super) fn add_friction(
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
    pub(super) fn solve_contact(
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
            .map(|&ci| {
                Constraint::on_dof(
                    s.cands[ci].dof,
                    s.cands[ci].sign * s.uhat[ci],
                    ConstraintKind::Bilateral,
                )
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
    pub(super) fn k_alone(
        &self,
        s: &StepSetup,
        c: &Coefficients,
    ) -> Result<crate::system::Stiffness> {
        let mut k = self.material_matrix(&c.mu);
        for b in k.d.iter_mut() {
            b[1][1] += c.drag;
        }
        k.rotate(&s.rot);
        k.to_stiffness(&s.dofs.reduced, s.dofs.free.len())
    }

    /// Step phase 3: telemetry of the last solve (cond₂, log10|det|, penetration, punch
    /// force, penalty range, μ* spread, drag force).
    pub(super) fn telemetry(&self, s: &StepSetup, p: &PicardOutcome) -> Result<SolveTelemetry> {
        let v = &p.v;
        // Velocity-level penetration of every candidate, in length.
        let max_penetration = (0..s.cands.len())
            .map(|ci| (s.uhat[ci] - vn(v, &s.cands[ci])).max(0.0) * s.dt)
            .fold(0.0, f64::max);
        let sys = metrics::system_matrix(&p.solve.problem, &p.solve.solution);
        let sys_report = conditioning::cond2(&sys)?;
        let cond2 = sys_report.cond2;
        let log10_det = conditioning::log10_abs_det(&sys)?;
        let k_alone = self.k_alone(s, &p.coeffs)?;
        let k_report = conditioning::cond2(&k_alone)?;
        let cond2_k = k_report.cond2;
        let log10_det_ratio = log10_det - conditioning::log10_abs_det(&k_alone)?;
        let equilibrated =
            |a: &crate::system::Stiffness| conditioning::cond2(&a.scaled(&a.equilibration()));
        let (sys_eq, k_eq) = (equilibrated(&sys)?, equilibrated(&k_alone)?);
        let (cond2_equilibrated, cond2_k_equilibrated) = (sys_eq.cond2, k_eq.cond2);
        let (proven, within) =
            conditioning::CondReport::flags([&sys_report, &k_report, &sys_eq, &k_eq].map(Some));
        let punch_force = s.punch_force(v, &p.coeffs.friction_c, &p.normal_force);
        let sol = &p.solve.solution;
        let active: Vec<f64> = sol.penalties.iter().copied().filter(|&e| e > 0.0).collect();
        let (mut mu_min, mut mu_max) = (f64::INFINITY, 0.0f64);
        for m in p.coeffs.mu.iter().flatten() {
            mu_min = mu_min.min(*m);
            mu_max = mu_max.max(*m);
        }
        let drag = p.coeffs.drag;
        let cost = metrics::solver::compute(
            &p.solve.problem,
            sol,
            metrics::solver::SolverOptions::default(),
        )?;
        Ok(SolveTelemetry {
            cond2,
            log10_det,
            cond2_k,
            log10_det_ratio,
            cond2_equilibrated,
            cond2_k_equilibrated,
            cond2_bounds_proven: proven.unwrap_or(false),
            cond2_within_contract: within.unwrap_or(false),
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
            cost,
        })
    }

    /// Everything about the step's last solve, on the start-of-step geometry.
    pub(super) fn step_detail(
        &self,
        s: &StepSetup,
        p: &PicardOutcome,
        punch_force: f64,
    ) -> StepDetail {
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
}
