//! The rows of `solver_cost` and what is derived from them: the slopes against h.

use crate::metrics::solver::reached;
use crate::stats::loglog_slope;
use serde::{Deserialize, Serialize};

/// One rule on one mesh level at one accuracy.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Row {
    /// Family (`hertz-plane`, `hertz-axi`, `membrane`, `beam`).
    pub family: String,
    /// Level (0: coarsest).
    pub level: usize,
    /// Element size (module doc of `cases`).
    pub h: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// Rule (registry name).
    pub method: String,
    /// `exact` (lagrange), `discretization` or `penetration`.
    pub accuracy: String,
    /// Knob name (`eps`, `factor`, `delta`, `tol`; empty for lagrange).
    pub knob: String,
    /// Knob value relative to its scale.
    pub knob_rel: Option<f64>,
    /// Absolute knob value.
    pub knob_value: Option<f64>,
    /// The target of the match (the discretization error, or δ).
    pub target: Option<f64>,
    /// The measure at the knob found.
    pub achieved: Option<f64>,
    /// Whether the measure is within the match tolerance of the target.
    pub matched: bool,
    /// Solves of the knob search.
    pub evaluations: usize,
    /// Lagrange's discretization error of the level.
    pub err_discretization: f64,
    /// Whether it was extrapolated (finest membrane and beam levels).
    pub err_discretization_extrapolated: bool,
    /// The rule's penalty error.
    pub err_penalty: Option<f64>,
    /// Largest penetration.
    pub max_penetration: Option<f64>,
    /// The rule's own iterations (active set, Uzawa, Newton).
    pub iterations: Option<usize>,
    /// cond₂ of the final system (to `cond_tol`).
    pub cond2_system: Option<f64>,
    /// cond₂ of the Jacobi-scaled final system (to `cond_tol`).
    pub cond2_jacobi: Option<f64>,
    /// CG iterations with Jacobi (penalties) to the fixed error of u
    /// (`‖u_k − u*‖∞ ≤ krylov_err_target·‖u*‖∞`): the count the tables, slopes and figures use.
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_jacobi_to_err_converged: Option<bool>,
    /// CG iterations with IC(0) to the fixed error of u.
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_ic0_to_err_converged: Option<bool>,
    /// CG iterations with scalar smoothed-aggregation AMG (B = ones; penalties) to the fixed
    /// error of u.
    pub pcg_iters_amg_scalar_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_amg_scalar_to_err_converged: Option<bool>,
    /// CG iterations with nodal smoothed-aggregation AMG (the model's rigid-body modes, block
    /// size 2; the elasticity families) to the fixed error of u.
    #[serde(default)]
    pub pcg_iters_amg_nodal_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_amg_nodal_to_err_converged: Option<bool>,
    /// MINRES iterations (lagrange) to the fixed error of u.
    pub minres_iters_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub minres_iters_to_err_converged: Option<bool>,
    /// CG iterations with Jacobi to the residual test ‖r‖ ≤ τ‖b‖ (not an accuracy: see
    /// `pcg_err_u_at_stop_jacobi`).
    pub pcg_iters_jacobi: Option<usize>,
    /// Whether they reached τ.
    pub pcg_converged_jacobi: Option<bool>,
    /// The relative error of u where the residual-stopped Jacobi run stopped.
    pub pcg_err_u_at_stop_jacobi: Option<f64>,
    /// Effective condition number of the Jacobi-preconditioned operator (estimate).
    pub pcg_cond_eff_jacobi: Option<f64>,
    /// CG iterations with IC(0) to the residual test.
    pub pcg_iters_ic0: Option<usize>,
    /// Whether they reached τ.
    pub pcg_converged_ic0: Option<bool>,
    /// The relative error of u where the residual-stopped IC(0) run stopped.
    pub pcg_err_u_at_stop_ic0: Option<f64>,
    /// Effective condition number of the IC(0)-preconditioned operator (estimate).
    pub pcg_cond_eff_ic0: Option<f64>,
    /// IC(0)'s diagonal shift α (`A + α·diag(A)` factored; 0: none needed).
    pub ic0_shift: Option<f64>,
    /// MINRES iterations (lagrange) to the residual test.
    pub minres_iters: Option<usize>,
    /// Whether they reached τ.
    pub minres_converged: Option<bool>,
    /// The relative error of u where the residual-stopped MINRES run stopped.
    pub minres_err_u_at_stop: Option<f64>,
    /// Relative error of the direct solve's u.
    pub forward_err_u: Option<f64>,
    /// Relative error of the direct solve's contact forces.
    pub forward_err_force: Option<f64>,
    /// Normwise backward error of the direct solve.
    pub backward_err: Option<f64>,
    /// Direct solve (factorization + solve; s).
    pub seconds_direct: Option<f64>,
    /// CG with Jacobi to the error target (s).
    pub seconds_pcg_jacobi: Option<f64>,
    /// CG with IC(0) to the error target (s).
    pub seconds_pcg_ic0: Option<f64>,
    /// MINRES to the error target (s).
    pub seconds_minres: Option<f64>,
    /// The knob search (every solve of it; s).
    pub seconds_search: f64,
    /// Every metric of the row (cond₂ and the solver-cost metrics; s).
    pub seconds_metrics: f64,
    /// What the row could not do (empty: nothing).
    pub note: String,
}

impl Row {
    /// Whether the row belongs to the ε map (accuracy `eps-map`), not to a level series.
    pub fn in_eps_map(&self) -> bool {
        self.accuracy == super::EPS_MAP
    }

    /// Digits of u lost by the direct solve: `log₁₀(forward_err_u / ε_mach)`, at least 0.
    pub fn digits_lost(&self) -> Option<f64> {
        self.forward_err_u
            .filter(|e| *e > 0.0)
            .map(|e| (e / f64::EPSILON).log10().max(0.0))
    }

    /// The iterations to the error target of the rule's Krylov solver with its stronger
    /// preconditioner (IC(0)-CG for the penalties, MINRES for lagrange), where that run
    /// reached the target.
    pub fn krylov_iters(&self) -> Option<usize> {
        reached(
            self.pcg_iters_ic0_to_err,
            self.pcg_iters_ic0_to_err_converged,
        )
        .or(reached(
            self.minres_iters_to_err,
            self.minres_iters_to_err_converged,
        ))
    }

    /// Jacobi-CG iterations to the error target, where it was reached.
    pub fn jacobi_iters(&self) -> Option<usize> {
        reached(
            self.pcg_iters_jacobi_to_err,
            self.pcg_iters_jacobi_to_err_converged,
        )
    }
}

/// The fitted exponents of one rule at one accuracy over a family's levels: cond ∝ h^−p,
/// iterations ∝ h^−q (least squares in log–log over the matched levels with the value). The
/// iterations are the error-based counts (to `krylov_err_target`), levels whose run missed
/// the target left out.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Slope {
    /// Family.
    pub family: String,
    /// Rule.
    pub method: String,
    /// Accuracy.
    pub accuracy: String,
    /// Levels whose knob matched the accuracy (the fit uses these only).
    pub levels_matched: usize,
    /// p of cond₂(system).
    pub p_cond2: Option<f64>,
    /// p of cond₂(Jacobi-scaled).
    pub p_cond2_jacobi: Option<f64>,
    /// q of Jacobi-CG iterations.
    pub q_pcg_jacobi: Option<f64>,
    /// q of IC(0)-CG iterations.
    pub q_pcg_ic0: Option<f64>,
    /// q of MINRES iterations.
    pub q_minres: Option<f64>,
}

/// −slope of `value` against h in log–log over `rows`.
fn exponent(rows: &[&Row], value: impl Fn(&Row) -> Option<f64>) -> Option<f64> {
    let (h, v): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| {
            value(r)
                .filter(|v| *v > 0.0 && v.is_finite())
                .map(|v| (r.h, v))
        })
        .unzip();
    if h.len() < 2 {
        return None;
    }
    loglog_slope(&h, &v).map(|s| -s)
}

/// The slopes of every (family, rule, accuracy), in row order (the ε map's rows are not a
/// level series and are left out).
pub fn slopes(rows: &[Row]) -> Vec<Slope> {
    let mut keys: Vec<(&str, &str, &str)> = Vec::new();
    for r in rows.iter().filter(|r| !r.in_eps_map()) {
        let k = (r.family.as_str(), r.method.as_str(), r.accuracy.as_str());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .map(|(f, m, a)| {
            let g: Vec<&Row> = rows
                .iter()
                .filter(|r| r.family == f && r.method == m && r.accuracy == a && r.matched)
                .collect();
            let count = |x: Option<usize>| x.map(|v| v as f64);
            Slope {
                family: f.into(),
                method: m.into(),
                accuracy: a.into(),
                levels_matched: g.len(),
                p_cond2: exponent(&g, |r| r.cond2_system),
                p_cond2_jacobi: exponent(&g, |r| r.cond2_jacobi),
                q_pcg_jacobi: exponent(&g, |r| count(r.jacobi_iters())),
                q_pcg_ic0: exponent(&g, |r| {
                    count(reached(
                        r.pcg_iters_ic0_to_err,
                        r.pcg_iters_ic0_to_err_converged,
                    ))
                }),
                q_minres: exponent(&g, |r| {
                    count(reached(
                        r.minres_iters_to_err,
                        r.minres_iters_to_err_converged,
                    ))
                }),
            }
        })
        .collect()
}
