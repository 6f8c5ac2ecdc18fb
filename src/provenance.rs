//! Provenance for result files: git commit, crate versions, atomic writes.

use crate::error::{Error, Result};
use std::path::Path;

/// `--version` of every binary: the crate version and the git commit it was built from
/// (`-dirty` when tracked files differed from it).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("PENALTY_LAB_GIT_COMMIT"),
    ")"
);

/// The git commit this binary was built from (captured at build time by `build.rs`), with a
/// `-dirty` suffix when tracked files differed from it; `"unknown"` when built outside a git
/// checkout. Independent of the directory the binary runs in.
pub fn git_commit() -> String {
    env!("PENALTY_LAB_GIT_COMMIT").to_string()
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

/// One CSV record (no line end) from its fields, quoted by the `csv` crate where a field needs
/// it (delimiter, quote, line break): for tables whose columns are built by hand.
pub fn csv_line(fields: &[String]) -> String {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(fields).expect("writing to memory");
    let bytes = w.into_inner().expect("writing to memory");
    let mut s = String::from_utf8(bytes).expect("fields are UTF-8");
    s.pop(); // the terminator
    s
}
