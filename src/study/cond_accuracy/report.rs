//! The printed report of `cond_accuracy`: the per-route summary.

use super::{summary, Row};

/// The per-route summary as a Markdown table.
pub fn table(rows: &[Row]) -> String {
    let mut t = String::from(
        "| route | median time (s) | median error | largest error | within max(1e-12, 4ε·cond₂) | bounds within target |\n\
         |---|---:|---:|---:|---:|---:|\n",
    );
    for s in summary(rows) {
        let tight = s
            .tight
            .map_or("—".to_string(), |(k, n)| format!("{k} / {n}"));
        t.push_str(&format!(
            "| `{}` | {:.2e} | {:.1e} | {:.1e} | {} / {} | {tight} |\n",
            s.route, s.median_seconds, s.median_error, s.max_error, s.within, s.total
        ));
    }
    t
}
