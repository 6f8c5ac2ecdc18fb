//! Provenance for result files: git commit, crate versions, atomic writes.

use crate::error::{Error, Result};
use std::path::Path;

/// `git rev-parse HEAD` of the working directory, or `"unknown"` outside a git checkout.
pub fn git_commit() -> String {
    std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

/// Versions of penalty-lab and its main dependencies, read from Cargo.lock at build time.
pub fn crate_versions() -> serde_json::Value {
    let mut m = serde_json::Map::new();
    m.insert("penalty-lab".into(), env!("CARGO_PKG_VERSION").into());
    for line in env!("PENALTY_LAB_DEP_VERSIONS").split(';') {
        if let Some((k, v)) = line.split_once('=') {
            m.insert(k.into(), v.into());
        }
    }
    serde_json::Value::Object(m)
}

/// Writes `bytes` to `path` through a temporary file and a rename, so a reader never sees a
/// half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).map_err(|e| Error::io(tmp.display(), e))?;
    std::fs::rename(&tmp, path).map_err(|e| Error::io(path.display(), e))
}

/// Writes `rows` as CSV (header from the field names, the `csv` crate's serde mapping) to
/// `path`, atomically.
pub fn write_csv<T: serde::Serialize>(path: &Path, rows: &[T]) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.serialize(r)
            .map_err(|e| Error::Numerical(format!("CSV row for {}: {e}", path.display())))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| Error::Numerical(format!("CSV for {}: {e}", path.display())))?;
    write_atomic(path, &bytes)
}
