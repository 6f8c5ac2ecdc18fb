//! The printed report of a sweep folder: one line from its manifest, then the rows solved,
//! failed and skipped per method with the first error of each.

use crate::study::outcomes::Tally;

/// Characters of a method's first error shown in the summary (the whole message is in the
/// row's `warnings` cell).
const ERROR_WIDTH: usize = 90;

/// `sweep: S scenes (R resumed), N rows in W s (X rows/s)`, or for a merged folder
/// `sweep merge: K shards, S scenes, N rows`, from the folder's manifest and its row count
/// (a folder without a manifest: its row count alone); then `tally` as a table.
pub fn text(m: &serde_json::Value, rows: usize, tally: &Tally) -> String {
    format!("{}{}", headline(m, rows), tally.text(ERROR_WIDTH))
}

fn headline(m: &serde_json::Value, rows: usize) -> String {
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
