//! The printed report of `friction_bench`: one line per row, grouped by μ.

use super::FrictionRow;
use crate::study::text::{fmt_e, table as aligned};

fn opt(v: Option<f64>) -> String {
    v.filter(|x| x.is_finite())
        .map_or("—".into(), |x| fmt_e(x, 2))
}

/// The rows as an aligned table: method and knob, onset (T/N and travel error), the friction
/// force's history error, the patch test's traction error, Newton steps, cond₂.
pub fn table(rows: &[FrictionRow]) -> String {
    let headers = [
        "case",
        "μ",
        "method",
        "rule",
        "ε_T",
        "δ_T",
        "T/N − μ at onset",
        "onset travel err",
        "history err",
        "traction err",
        "Newton",
        "converged",
        "cond₂",
    ];
    let body: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            let case = match (&r.discretization, r.theta) {
                (Some(d), _) => format!("patch {d}"),
                (None, Some(t)) => format!("incline {t}°"),
                (None, None) => "block".into(),
            };
            let traction = r
                .pressure_err_max
                .zip(r.shear_err_max)
                .map(|(a, b)| a.max(b));
            vec![
                case,
                format!("{}", r.mu),
                r.method.clone(),
                r.tangent_rule.clone(),
                opt(r.eps_t),
                opt(r.delta_t),
                r.onset_ratio
                    .map_or("no full slip".into(), |x| fmt_e((x - r.mu) / r.mu, 1)),
                opt(r.onset_travel_err),
                opt(r.history_err),
                opt(traction),
                r.newton_iters.to_string(),
                if r.converged { "yes" } else { "NO" }.into(),
                opt(r.cond2_system),
            ]
        })
        .collect();
    let right = [
        false, true, false, false, true, true, true, true, true, true, true, false, true,
    ];
    let mut t = aligned(&headers, &body, &right);
    t.push_str(
        "T/N − μ at onset: (|T|/N − μ)/μ at the first increment in full slip (0 to rounding \
         for a converged method); \
         onset travel err: relative to Lagrange, resolved to one increment; history err: \
         max |T − T_lagrange|/(μN); traction err (patch): the largest relative deviation of \
         a row's pressure or shear from the rows' mean; cond₂: the system of the last increment with a contact \
         in stick (penalty: the consistent tangent).\n",
    );
    t
}
