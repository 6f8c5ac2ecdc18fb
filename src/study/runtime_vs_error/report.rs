//! The record of a `runtime_vs_error` run: CSV and JSON rows, the manifest, the figures
//! rendered from `rows.json`.

use super::{figures, PerfConfig, PerfRow};
use crate::error::{Error, Result};
use crate::plot;
use crate::provenance::{self, csv_opt, Provenance};
use serde_json::{json, Value};
use std::path::Path;

/// The rows as CSV (for spreadsheets; `rows.json` keeps every field exactly).
pub fn csv(rows: &[PerfRow]) -> String {
    let mut t = String::from(
        "family,size,n,m,method,knob,value,value_rel,status,seconds,seconds_all,\
         max_penetration,penetration_rel,error_vs_ref,reference,iterations,factorizations,\
         linear_solves,converged,n_warnings,reason\n",
    );
    for r in rows {
        let cells = [
            r.family.clone(),
            r.size.to_string(),
            r.n.to_string(),
            r.m.to_string(),
            r.method.clone(),
            r.knob.clone(),
            format!("{:e}", r.value),
            format!("{:e}", r.value_rel),
            r.status.clone(),
            csv_opt(r.seconds),
            r.seconds_all
                .iter()
                .map(|s| format!("{s:e}"))
                .collect::<Vec<_>>()
                .join(" "),
            csv_opt(r.max_penetration),
            csv_opt(r.penetration_rel),
            csv_opt(r.error_vs_ref),
            r.reference.clone(),
            r.iterations.map_or(String::new(), |v| v.to_string()),
            r.factorizations.map_or(String::new(), |v| v.to_string()),
            r.linear_solves.map_or(String::new(), |v| v.to_string()),
            r.converged.map_or(String::new(), |v| v.to_string()),
            r.warnings.len().to_string(),
            r.reason.clone(),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

/// Writes `rows.csv`, `rows.json` and `manifest.json` (provenance, configuration, counts by
/// status, wall time) into `out`; returns the manifest.
pub fn save(
    out: &Path,
    cfg: &PerfConfig,
    smoke: bool,
    rows: &[PerfRow],
    wall: f64,
) -> Result<Value> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    provenance::write_atomic(&out.join("rows.csv"), csv(rows).as_bytes())?;
    provenance::write_atomic(
        &out.join("rows.json"),
        serde_json::to_string(rows).expect("JSON value").as_bytes(),
    )?;
    let count = |s: &str| rows.iter().filter(|r| r.status == s).count();
    let manifest = Provenance::new("runtime_vs_error").record(json!({
        "smoke": smoke,
        "config": cfg,
        "threads": 1,
        "timing": "wall time (std::time::Instant) of complete strategy::solve calls, release build, median of the repeats",
        "rows": rows.len(),
        "ok": count("ok"),
        "errors": count("error"),
        "skipped": count("skipped"),
        "wall_seconds": wall,
    }));
    provenance::write_json(&out.join("manifest.json"), &manifest)?;
    Ok(manifest)
}

/// Renders every figure into `OUT/figures` from `OUT/rows.json`; returns the number of files.
pub fn render(out: &Path) -> Result<usize> {
    let path = out.join("rows.json");
    let rows: Vec<PerfRow> = crate::provenance::read_json(&path)?;
    let dir = out.join("figures");
    let mut files = 0;
    for (name, panels) in figures(&rows) {
        let cols = panels.len().min(3);
        let nrows = panels.len().div_ceil(cols) as u32;
        files += plot::render_panels(
            &panels,
            cols,
            &dir.join(&name),
            (560 * cols as u32, 460 * nrows),
        )?
        .len();
    }
    Ok(files)
}
