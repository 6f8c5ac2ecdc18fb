//! The rows of `penalty_scaling` and what is derived from them: the slopes against h.

use crate::stats::loglog_slope;
use serde::{Deserialize, Serialize};

/// One rule on one level of one discretization.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Row {
    /// `mortar`, `nts-1` or `nts-2`.
    pub discretization: String,
    /// Level (0: coarsest).
    pub level: usize,
    /// Slave element size h (W = 1).
    pub h: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// Constraint rows.
    pub n_rows: usize,
    /// Rule (registry name).
    pub method: String,
    /// `exact` (lagrange), `eps-fixed`, `eps-e-over-h` (constant) or `delta`.
    pub schedule: String,
    /// ε over E*/h₀ (`eps-fixed`) or E*/h (`eps-e-over-h`).
    pub eps_rel: Option<f64>,
    /// The knob given to the rule: ε (per unit contact length) or δ.
    pub knob_value: Option<f64>,
    /// ‖u − u_exact‖∞ / w.
    pub err_u: Option<f64>,
    /// ‖u − u_lagrange‖∞ / w on the same discretization and mesh (none where Lagrange
    /// refused the rows).
    pub err_penalty: Option<f64>,
    /// max_c |p_c − p|/p (none where a pressure is not finite; `nts-2`: over the nodal
    /// pressures of both bodies' interface nodes).
    pub err_pressure: Option<f64>,
    /// Largest penetration.
    pub max_penetration: Option<f64>,
    /// The rule's own iterations.
    pub iterations: Option<usize>,
    /// cond₂ of the final system (to `cond_tol`).
    pub cond2_system: Option<f64>,
    /// cond₂ of the Jacobi-scaled final system (to `cond_tol`).
    pub cond2_jacobi: Option<f64>,
    /// CG iterations with Jacobi (penalties) to the fixed error of u
    /// ([`crate::metrics::solver`], 1e-6 by default); empty where the run missed it.
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// CG iterations with IC(0) (penalties) to the same error; empty where missed.
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// MINRES iterations (lagrange) to the same error; empty where missed.
    pub minres_iters_to_err: Option<usize>,
    /// Relative error of the direct solve's u.
    pub forward_err_u: Option<f64>,
    /// The rule's solve (s).
    pub seconds_solve: f64,
    /// Every metric of the row (s).
    pub seconds_metrics: f64,
    /// What the row could not do (empty: nothing).
    pub note: String,
}

impl Row {
    /// The curve the row belongs to: `(discretization, method, schedule, ε_rel)`.
    pub fn curve(&self) -> (String, String, String, Option<u64>) {
        (
            self.discretization.clone(),
            self.method.clone(),
            self.schedule.clone(),
            self.eps_rel.map(f64::to_bits),
        )
    }

    /// The curve's legend text: the rule and its schedule.
    pub fn label(&self) -> String {
        let e = self
            .eps_rel
            .map(|v| crate::study::text::fmt_e_trim(v, 2))
            .unwrap_or_default();
        match self.schedule.as_str() {
            "eps-fixed" => format!("constant, ε = {e}·E*/h₀ (fixed)"),
            "eps-e-over-h" => format!("constant, ε = {e}·E*/h"),
            "delta" => format!("{} (δ)", self.method),
            _ => self.method.clone(),
        }
    }
}

/// The fitted exponents of one curve over the levels: cond ∝ h^−p, error ∝ h^s (least squares
/// in log–log over the levels with a positive finite value; errors above [`ERR_FLOOR`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Slope {
    /// Discretization.
    pub discretization: String,
    /// Rule.
    pub method: String,
    /// Schedule.
    pub schedule: String,
    /// ε_rel of a `constant` schedule.
    pub eps_rel: Option<f64>,
    /// Levels with a solution. Each fit uses those of them whose value is positive and finite
    /// (errors: above [`ERR_FLOOR`]), at least two, else it is `None`.
    pub levels: usize,
    /// p of cond₂(system).
    pub p_cond2: Option<f64>,
    /// p of cond₂(Jacobi-scaled).
    pub p_cond2_jacobi: Option<f64>,
    /// s of `err_u`.
    pub s_err_u: Option<f64>,
    /// s of `err_penalty`.
    pub s_err_penalty: Option<f64>,
}

/// Errors at or below this are rounding (the mortar patch test under Lagrange) and are not
/// fitted: their slope would describe the rounding, not the method.
pub const ERR_FLOOR: f64 = 1e-10;

/// Slope of `value` against h in log–log over the `rows` where it exceeds `floor`, times
/// `sign`.
fn fit(rows: &[&Row], value: impl Fn(&Row) -> Option<f64>, sign: f64, floor: f64) -> Option<f64> {
    let (h, v): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| {
            value(r)
                .filter(|v| *v > floor && v.is_finite())
                .map(|v| (r.h, v))
        })
        .unzip();
    if h.len() < 2 {
        return None;
    }
    loglog_slope(&h, &v).map(|s| sign * s)
}

/// The slopes of every curve, in row order.
pub fn slopes(rows: &[Row]) -> Vec<Slope> {
    let mut keys = Vec::new();
    for r in rows {
        let k = r.curve();
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .map(|k| {
            let g: Vec<&Row> = rows
                .iter()
                .filter(|r| r.curve() == k && r.err_u.is_some())
                .collect();
            Slope {
                discretization: k.0,
                method: k.1,
                schedule: k.2,
                eps_rel: k.3.map(f64::from_bits),
                levels: g.len(),
                p_cond2: fit(&g, |r| r.cond2_system, -1.0, 0.0),
                p_cond2_jacobi: fit(&g, |r| r.cond2_jacobi, -1.0, 0.0),
                s_err_u: fit(&g, |r| r.err_u, 1.0, ERR_FLOOR),
                s_err_penalty: fit(&g, |r| r.err_penalty, 1.0, ERR_FLOOR),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit recovers the exponents of exact power laws (cond = 3h^−2, err = 0.5h).
    #[test]
    fn slopes_of_power_laws() {
        let rows: Vec<Row> = [0.5, 0.25, 0.125]
            .iter()
            .map(|&h: &f64| Row {
                discretization: "mortar".into(),
                method: "constant".into(),
                schedule: "eps-fixed".into(),
                eps_rel: Some(1.0),
                h,
                err_u: Some(0.5 * h),
                cond2_system: Some(3.0 * h.powi(-2)),
                ..Row::default()
            })
            .collect();
        let s = slopes(&rows);
        assert_eq!(s.len(), 1);
        assert!((s[0].p_cond2.unwrap() - 2.0).abs() < 1e-12);
        assert!((s[0].s_err_u.unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(s[0].s_err_penalty, None);
        assert_eq!(s[0].levels, 3);
    }
}
