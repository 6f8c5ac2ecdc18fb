//! The record of a `runtime_vs_error` run: CSV and JSON rows and the manifest.

use super::{PerfConfig, PerfRow};
use crate::error::{Error, Result};
use crate::provenance::{self, csv_opt, Provenance};
use serde::{Deserialize, Serialize};
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

/// What a run records: the manifest (provenance, configuration, counts by status, wall time)
/// and the rows; `--json` prints it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Record {
    /// `manifest.json`.
    pub manifest: Value,
    /// `rows.json`.
    pub rows: Vec<PerfRow>,
}

/// The record of `rows` measured with `cfg` in `wall` seconds, with `provenance`.
pub fn record(
    cfg: &PerfConfig,
    smoke: bool,
    rows: Vec<PerfRow>,
    wall: f64,
    provenance: &Provenance,
) -> Record {
    let count = |s: &str| rows.iter().filter(|r| r.status == s).count();
    let manifest = provenance.record(json!({
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
    Record { manifest, rows }
}

/// Writes `rows.csv`, `rows.json` and `manifest.json` into `out`.
pub fn save(out: &Path, rec: &Record) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    provenance::write_atomic(&out.join("rows.csv"), csv(&rec.rows).as_bytes())?;
    provenance::write_atomic(
        &out.join("rows.json"),
        serde_json::to_string(&rec.rows)
            .expect("JSON value")
            .as_bytes(),
    )?;
    provenance::write_json(&out.join("manifest.json"), &rec.manifest)
}

/// Reads what [`save`] wrote.
pub fn load(out: &Path) -> Result<Record> {
    Ok(Record {
        rows: provenance::read_json(&out.join("rows.json"))?,
        manifest: provenance::read_json(&out.join("manifest.json"))?,
    })
}
