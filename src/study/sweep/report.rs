//! The printed report of a sweep folder: one line from its manifest.

/// `sweep: S scenes (R resumed), N rows in W s (X rows/s)`, or for a merged folder
/// `sweep merge: K shards, S scenes, N rows`, from the folder's manifest and its row count
/// (a folder without a manifest: its row count alone).
pub fn text(m: &serde_json::Value, rows: usize) -> String {
    if m.is_null() {
        return format!("sweep: {rows} rows in rows.csv (no manifest.json)\n");
    }
    if let Some(from) = m["merged_from"].as_array() {
        return format!(
            "sweep merge: {} shards, {} scenes, {} rows\n",
            from.len(),
            m["scenes"],
            rows
        );
    }
    let f = |k: &str| m[k].as_f64().unwrap_or(f64::NAN);
    format!(
        "sweep: {} scenes ({} resumed), {} rows written, {} in rows.csv, in {:.2} s ({:.3e} rows/s)\n",
        m["scenes"],
        m["resumed_scenes"],
        m["rows_written"],
        rows,
        f("wall_seconds"),
        f("rows_per_second")
    )
}
