//! The printed report of `cond_cost`: one table row per matrix.

use super::Row;

/// The rows as a Markdown table.
pub fn table(rows: &[Row]) -> String {
    let mut t = String::new();
    t.push_str(
        "| family | n | cond₂ | bracket | Cholesky (s) | sparse exact (s) | ratio | dense eigen (s) | dense SVD (s) | vs SVD |\n",
    );
    t.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    let f = |v: Option<f64>| v.map_or("—".to_string(), |t| format!("{t:.3e}"));
    for r in rows {
        t.push_str(&format!(
            "| {} | {} | {:.4e} | {:.0e} | {:.3e} | {:.3e} | {:.1} | {} | {} | {} |\n",
            r.family,
            r.n,
            r.cond2,
            r.cond2_bracket,
            r.cholesky_s,
            r.sparse_exact_s,
            r.sparse_exact_s / r.cholesky_s,
            f(r.dense_eigen_s),
            f(r.dense_svd_s),
            r.rel_diff_vs_svd.map_or("—".into(), |d| format!("{d:.0e}")),
        ));
    }
    t
}
