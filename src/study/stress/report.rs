//! The printed report of a stress run: one line of counts.

use super::record::Record;

/// `stress: S scenes, P ε points, R strategy runs (ok, clean errors, non-finite, panics) in W s`.
pub fn text(rec: &Record) -> String {
    let m = &rec.manifest;
    let s = &m["summary"];
    format!(
        "stress: {} scenes, {} ε points, {} strategy runs ({} ok, {} clean errors, {} non-finite, {} panics) in {:.1} s\n",
        m["scenes"].as_array().map_or(0, Vec::len),
        rec.eps_study.len(),
        rec.strategies.len(),
        s["ok"],
        s["clean_errors"],
        s["non_finite"],
        s["panics"],
        m["wall_seconds"].as_f64().unwrap_or(f64::NAN)
    )
}
