//! The engine study's printed table: one line per size and method.

use super::ScaleRow;

/// N, method, iterations, factorizations, CG iterations, seconds, peak memory, cond₂ of K and
/// of the system; `NOT CONVERGED` where the solve did not converge.
pub fn table(rows: &[ScaleRow]) -> String {
    let mut out = format!(
        "{:>8} {:<10} {:>5} {:>5} {:>5} {:>9} {:>9} {:>9} {:>11} {:>11}\n",
        "N", "method", "its", "fact", "CG", "solve s", "cond s", "peak MB", "cond2 K", "cond2 sys"
    );
    let e = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.4e}"));
    let f = |v: Option<f64>| v.map_or("—".to_string(), |x| format!("{x:.2}"));
    for r in rows {
        out.push_str(&format!(
            "{:>8} {:<10} {:>5} {:>5} {:>5} {:>9.2} {:>9} {:>9} {:>11} {:>11}{}\n",
            r.n,
            r.method,
            r.iterations,
            r.factorizations,
            r.cg_iterations,
            r.seconds_solve,
            f(r.seconds_cond_system),
            f(r.peak_rss_mb),
            e(r.cond2_k),
            e(r.cond2_system),
            if r.converged { "" } else { "  NOT CONVERGED" }
        ));
    }
    out
}
