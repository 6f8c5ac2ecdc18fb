//! The `cond` record as a readable table.

use super::CondRecord;

fn num(x: Option<f64>) -> String {
    x.map_or("∞".into(), |v| format!("{v:.6e}"))
}

/// The record as a table: the value, its bounds and what they prove, the route, warnings.
pub fn table(r: &CondRecord) -> String {
    let mut t = format!(
        "matrix {}  (N = {}, {} stored entries, symmetry {})\n",
        r.matrix, r.n, r.nnz, r.symmetry
    );
    let rows = [
        ("cond2", num(r.cond2)),
        ("cond2_lo", num(r.cond2_lo)),
        ("cond2_hi", num(r.cond2_hi)),
        ("cond2_bounds_proven", r.cond2_bounds_proven.to_string()),
        ("cond2_within_contract", r.cond2_within_contract.to_string()),
        ("cond2_error_bound", num(r.cond2_error_bound)),
        ("cond_route", r.cond_route.clone()),
        ("sigma_max", format!("{:.6e}", r.sigma_max)),
        ("sigma_min", format!("{:.6e}", r.sigma_min)),
        ("seconds", format!("{:.3}", r.seconds)),
    ];
    for (k, v) in rows {
        t += &format!("{k:>22}: {v}\n");
    }
    if r.warnings.is_empty() {
        t += "warnings: none\n";
    }
    for w in &r.warnings {
        t += &format!("warning: {w}\n");
    }
    t
}
