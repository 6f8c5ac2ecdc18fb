//! The `solve` object as a readable table.

use serde_json::Value;

fn fmt_vec(v: &Value) -> String {
    match v.as_array() {
        Some(a) if a.len() <= 12 => a
            .iter()
            .map(|x| x.as_f64().map_or("null".into(), |f| format!("{f:.6}")))
            .collect::<Vec<_>>()
            .join("  "),
        Some(a) => format!("[{} values]", a.len()),
        None => v.to_string(),
    }
}

/// The `solve` object as a readable table (NOT CONVERGED in capitals when it did not).
pub fn table(v: &Value) -> String {
    let mut t = String::new();
    t += &format!("scene {}  (N = {}, m = {})\n", v["scene"], v["n"], v["m"]);
    t += &format!("method {}  {}\n", v["method"], v["knob"]);
    if v["converged"] == Value::Bool(false) {
        t += "NOT CONVERGED (see the warnings below)\n";
    }
    for key in ["penalties", "gaps", "forces", "u"] {
        t += &format!("{key:>18}: {}\n", fmt_vec(&v[key]));
    }
    for key in [
        "max_penetration",
        "cond2_K",
        "cond2_system",
        "cond_route_system",
        "cond2_system_lo",
        "cond2_system_hi",
        "cond2_bounds_proven",
        "cond2_within_contract",
        "log10_det_K",
        "log10_det_system",
        "log10_det_ratio",
        "linear_solves",
        "factorizations",
        "iterations",
        "converged",
        "optimality",
        "starts_agreeing",
        "cond2_lower_bound",
        "seconds",
    ] {
        if v[key].is_null() && matches!(key, "optimality" | "starts_agreeing" | "cond2_lower_bound")
        {
            continue;
        }
        let s = match &v[key] {
            Value::Number(n) if n.is_f64() => format!("{:.6e}", n.as_f64().unwrap_or(f64::NAN)),
            other => other.to_string(),
        };
        t += &format!("{key:>18}: {s}\n");
    }
    match v["warnings"].as_array() {
        Some(w) if !w.is_empty() => {
            for x in w {
                t += &format!("warning: {}\n", x.as_str().unwrap_or_default());
            }
        }
        _ => t += "warnings: none\n",
    }
    t
}
