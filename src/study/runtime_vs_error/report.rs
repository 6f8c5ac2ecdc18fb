//! The printed report of `runtime_vs_error`: one line of counts.

use super::record::Record;

/// `runtime_vs_error: N rows (k ok, e errors, s skipped) in W s`.
pub fn text(rec: &Record) -> String {
    let m = &rec.manifest;
    format!(
        "runtime_vs_error: {} rows ({} ok, {} errors, {} skipped) in {:.1} s\n",
        rec.rows.len(),
        m["ok"],
        m["errors"],
        m["skipped"],
        m["wall_seconds"].as_f64().unwrap_or(f64::NAN)
    )
}
