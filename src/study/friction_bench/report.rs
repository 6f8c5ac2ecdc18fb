//! The printed report of `friction_bench`: one line per row, grouped by μ, and the rows
//! solved and failed per method (exit status 4 where one failed on every row).

use super::FrictionRow;
use crate::study::outcomes::Tally;
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

/// Rows solved and failed per method and tangential rule (`penalty (delta)`): a row that did
/// not converge is a failure, with its `warnings` as the error.
pub fn tally(rows: &[FrictionRow]) -> Tally {
    let mut t = Tally::default();
    for r in rows {
        let method = if r.method == "penalty" {
            format!("penalty ({})", r.tangent_rule)
        } else {
            r.method.clone()
        };
        if r.converged {
            t.add(&method, "");
        } else {
            let why = if r.warnings.is_empty() {
                "did not converge"
            } else {
                &r.warnings
            };
            t.add(&method, &format!("error: {why}"));
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::tally;
    use crate::study::friction_bench::{FrictionBench, FrictionRow};
    use crate::study::shape::Study;

    fn row(method: &str, rule: &str, converged: bool) -> FrictionRow {
        serde_json::from_value(serde_json::json!({
            "case": "sliding-block", "mu": 0.3, "method": method, "tangent_rule": rule,
            "law": "coulomb", "increments": 4, "newton_iters": 9, "factorizations": 9,
            "converged": converged,
            "warnings": if converged { "" } else { "Newton did not converge in increment 2" },
        }))
        .unwrap()
    }

    /// A row that did not converge is a failure of its method and tangential rule; exit
    /// status 4 only where one failed on every row it ran.
    #[test]
    fn a_rule_that_fails_on_every_row_ends_the_run_with_status_4() {
        let mixed = vec![
            row("lagrange", "exact", true),
            row("penalty", "delta", false),
            row("penalty", "delta", true),
            row("penalty", "constant", true),
        ];
        let t = tally(&mixed);
        assert_eq!(t.rows(), 4);
        assert_eq!(t.0[1].method, "penalty (delta)");
        assert_eq!((t.0[1].solved, t.0[1].failed), (1, 1));
        assert_eq!(FrictionBench::failure(&mixed), None);
        let failing = vec![
            row("lagrange", "exact", true),
            row("penalty", "constant", false),
            row("penalty", "constant", false),
        ];
        let why = FrictionBench::failure(&failing).expect("exit status 4");
        assert!(
            why.starts_with("penalty (constant) (2 of 2 rows: Newton did not converge"),
            "{why}"
        );
    }
}
