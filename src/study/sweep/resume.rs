//! Resuming an interrupted run, and writing each scene's rows as soon as it completes.
//!
//! Rows land in rows.csv in completion order, one write and flush per scene, and the scene's
//! position in the run (its index among the shard's scenes) is appended to [`ORDER_FILE`]
//! after them; at the end of the run rows.csv is put in scene order and the order file
//! removed. A killed run thus keeps every scene that finished, and `--resume` pairs the k-th
//! complete chunk of rows with the k-th index of the order file (a chunk without its index, or
//! an index without its whole chunk, is dropped and solved again). A folder without an order
//! file (a complete run, or an older version's in-order rows) holds scenes 0, 1, … in order.

use super::rows::{self, Row};
use super::{run_scene, LoadedScene, RunOptions, SceneSpec, SetupSeconds, SweepConfig, Timing};
use crate::error::{Error, Result};
use crate::provenance::{remove_if_present, write_atomic};
use crate::scene;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::Path;

/// The order file of a running sweep: `scene_index` and one line per scene written.
pub const ORDER_FILE: &str = "scenes_done.csv";

/// The order file's header line.
const ORDER_HEADER: &str = "scene_index\n";

/// The scenes an interrupted run kept, by their index in the shard.
#[derive(Clone, Debug, Default)]
pub(super) struct Kept {
    /// Indices in rows.csv's order (one chunk of rows per index).
    pub order: Vec<usize>,
    /// The same, as a set.
    pub done: BTreeSet<usize>,
}

/// Where a `--resume` run picks up: the complete scenes an existing rows.csv holds (it and
/// the order file are cut back to them), after checking that the manifest was written with
/// the same config and shard; `None` for a fresh run (nothing written).
pub(super) fn resume_point(
    opts: &RunOptions,
    config_json: &serde_json::Value,
    (k, n): (usize, usize),
    per_scene: usize,
) -> Result<Option<Kept>> {
    let rows_path = opts.out.join("rows.csv");
    let manifest_path = opts.out.join("manifest.json");
    if !(opts.resume && rows_path.exists()) {
        return Ok(None);
    }
    let old: serde_json::Value = std::fs::read_to_string(&manifest_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .ok_or_else(|| {
            Error::io(
                manifest_path.display(),
                "cannot resume: manifest.json missing or unreadable",
            )
        })?;
    if old.get("config") != Some(config_json)
        || old.get("shard") != Some(&serde_json::json!([k, n]))
    {
        return Err(Error::bad_file(
            opts.out.display(),
            "cannot resume here: it was produced with a different config or shard; use another --out",
        ));
    }
    let (rows, _) = rows::read_rows(&rows_path, true)?;
    let chunks = rows.len() / per_scene.max(1);
    let order_path = opts.out.join(ORDER_FILE);
    let order: Vec<usize> = if order_path.exists() {
        read_order(&order_path)?
    } else {
        (0..chunks).collect()
    };
    // The k-th chunk belongs to the k-th index; a repeated index (never written twice by a
    // run) ends what can be trusted.
    let mut kept = Kept::default();
    for &i in order.iter().take(chunks) {
        if !kept.done.insert(i) {
            break;
        }
        kept.order.push(i);
    }
    let keep = &rows[..kept.order.len() * per_scene];
    let mut text = rows::header();
    text.push_str(&rows::format_rows(keep));
    write_atomic(&rows_path, text.as_bytes())?;
    write_atomic(&order_path, order_text(&kept.order).as_bytes())?;
    Ok(Some(kept))
}

/// The indices of a complete order file's whole lines (a torn last line is dropped); a line
/// that is not an index is a parse error naming the file and the line.
fn read_order(path: &Path) -> Result<Vec<usize>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
    let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
    if lines.last().is_some_and(|l| !l.ends_with('\n')) {
        lines.pop();
    }
    if lines.first().map(|l| l.trim()) != Some(ORDER_HEADER.trim()) {
        return Err(Error::io(
            path.display(),
            "not a sweep order file (no header)",
        ));
    }
    lines[1..]
        .iter()
        .enumerate()
        .map(|(k, l)| {
            l.trim()
                .parse::<usize>()
                .map_err(|_| Error::parse(path.display(), k + 2, format!("bad scene index {l:?}")))
        })
        .collect()
}

/// The order file's text for `order` (`&[]`: the header a fresh run starts with).
pub(super) fn order_text(order: &[usize]) -> String {
    let mut t = String::from(ORDER_HEADER);
    for i in order {
        t.push_str(&format!("{i}\n"));
    }
    t
}

/// Writes the scenes as they complete: rows.csv and the order file, one write and flush each
/// per scene, in completion order; scenes that finish before the files are open wait.
pub(super) struct Completed<'a> {
    /// rows.csv and the order file, open for appending once the start files are written.
    files: Option<(std::fs::File, std::fs::File)>,
    rows_path: &'a Path,
    order_path: std::path::PathBuf,
    /// Finished scenes waiting for the files.
    pending: Vec<(usize, Finished)>,
    /// The indices written by this run, in file order.
    pub order: Vec<usize>,
    rows_written: usize,
    times: &'a mut Timing,
    /// The error of the earliest failed scene (or of a write, or of the start: index 0).
    error: Option<(usize, Error)>,
}

/// A solved scene: its rows, their CSV text and its shared work.
type Finished = (Vec<Row>, String, SetupSeconds);

impl<'a> Completed<'a> {
    /// Nothing written yet; rows go to `rows_path` (and the indices to the order file beside
    /// it) once they are opened, their timing to `times`.
    pub(super) fn new(rows_path: &'a Path, times: &'a mut Timing) -> Self {
        Completed {
            files: None,
            rows_path,
            order_path: rows_path.with_file_name(ORDER_FILE),
            pending: Vec::new(),
            order: Vec::new(),
            rows_written: 0,
            times,
            error: None,
        }
    }

    /// Files scene `i`'s outcome and writes what is finished.
    fn finish(&mut self, i: usize, done: Result<Finished>) {
        match done {
            Ok(f) => self.pending.push((i, f)),
            Err(e) => self.fail(i, e),
        }
        self.write_pending();
    }

    /// Records the error of scene `i` (0 for the start: it precedes every scene's).
    fn fail(&mut self, i: usize, e: Error) {
        if self.error.as_ref().is_none_or(|(j, _)| i < *j) {
            self.error = Some((i, e));
        }
    }

    /// Appends the finished scenes not yet written: the rows, then the index.
    fn write_pending(&mut self) {
        let Some((rows_file, order_file)) = self.files.as_mut() else {
            return;
        };
        for (i, (rows, text, setup)) in std::mem::take(&mut self.pending) {
            self.times.add(&rows, &setup);
            let written = rows_file
                .write_all(text.as_bytes())
                .and_then(|_| rows_file.flush())
                .map_err(|e| Error::io(self.rows_path.display(), e))
                .and_then(|()| {
                    order_file
                        .write_all(format!("{i}\n").as_bytes())
                        .and_then(|_| order_file.flush())
                        .map_err(|e| Error::io(self.order_path.display(), e))
                });
            match written {
                Ok(()) => {
                    self.rows_written += rows.len();
                    self.order.push(i);
                }
                Err(e) => {
                    self.error = Some((0, e));
                    return;
                }
            }
        }
    }
}

/// Solves `todo` (each with its index in the shard) on `pool` and appends each scene's rows
/// to rows.csv as soon as it completes ([`Completed`]), writing scene files where asked;
/// returns the indices written (in file order) and the number of rows, or the first error.
/// `start` (the start files, the running manifest) runs on one worker while the others begin
/// the first scenes; no row is written before it is done. After an error no scene after the
/// failed one is started (those before it, and those running, finish and are kept). The rows
/// are formatted on the workers; the calling thread only waits.
pub(super) fn solve_as_completed(
    todo: &[(usize, &SceneSpec)],
    cfg: &SweepConfig,
    opts: &RunOptions,
    pool: &rayon::ThreadPool,
    bar: &crate::progress::Progress,
    writer: Completed<'_>,
    start: impl FnOnce() -> Result<()> + Send,
) -> Result<(Vec<usize>, usize)> {
    use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
    use std::sync::{Mutex, PoisonError};
    let (rows_path, order_path) = (writer.rows_path, writer.order_path.clone());
    let state = Mutex::new(writer);
    // The earliest failed scene (0 when the start failed): later scenes are not started.
    let failed = AtomicUsize::new(usize::MAX);
    let open = || {
        let append = |p: &Path| {
            std::fs::OpenOptions::new()
                .append(true)
                .open(p)
                .map_err(|e| Error::io(p.display(), e))
        };
        let opened = start().and_then(|()| Ok((append(rows_path)?, append(&order_path)?)));
        let mut state = state.lock().unwrap_or_else(PoisonError::into_inner);
        match opened {
            Ok(files) => {
                state.files = Some(files);
                state.write_pending();
            }
            Err(e) => {
                failed.store(0, Relaxed);
                state.fail(0, e);
            }
        }
    };
    let solve = || {
        use rayon::prelude::*;
        todo.par_iter().with_max_len(1).for_each(|&(i, spec)| {
            if i > failed.load(Relaxed) {
                return; // a scene after the failed one: the run ends with its error
            }
            let done = run_scene(spec, cfg).and_then(|(rows, work)| {
                if let Some(d) = &opts.write_scenes {
                    write_scene_file(d, &work.scene, opts.dense_scenes)?;
                }
                bar.message(work.scene.name.clone());
                let text = rows::format_rows(&rows);
                Ok((rows, text, work.seconds))
            });
            if done.is_err() {
                failed.fetch_min(i, Relaxed);
            }
            state
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .finish(i, done);
            bar.step("");
        });
    };
    pool.install(|| rayon::join(open, solve));
    let state = state.into_inner().unwrap_or_else(PoisonError::into_inner);
    match state.error {
        Some((_, e)) => Err(e),
        None => Ok((state.order, state.rows_written)),
    }
}

/// At the end of a complete run: rows.csv in scene order (chunks of `per_scene` rows, the
/// k-th belonging to `order[k]`), rewritten only where the completion order was not already
/// the scene order, and the order file removed.
pub(super) fn put_in_scene_order(out: &Path, order: &[usize], per_scene: usize) -> Result<()> {
    let rows_path = out.join("rows.csv");
    if order.windows(2).any(|w| w[0] > w[1]) {
        let (rows, _) = rows::read_rows(&rows_path, false)?;
        if rows.len() != order.len() * per_scene {
            return Err(Error::io(
                rows_path.display(),
                format!(
                    "{} rows where {} scenes of {per_scene} were written",
                    rows.len(),
                    order.len()
                ),
            ));
        }
        let mut chunks: Vec<(usize, &[Row])> = order
            .iter()
            .copied()
            .zip(rows.chunks(per_scene.max(1)))
            .collect();
        chunks.sort_by_key(|&(i, _)| i);
        let sorted: Vec<Row> = chunks.into_iter().flat_map(|(_, c)| c.to_vec()).collect();
        let mut text = rows::header();
        text.push_str(&rows::format_rows(&sorted));
        write_atomic(&rows_path, text.as_bytes())?;
    }
    remove_if_present(&out.join(ORDER_FILE))
}

/// Writes `scene` to `DIR/NAME.scene.json`: K as dense rows with `dense`, otherwise dense
/// inline and sparse as Matrix Market beside it.
pub(super) fn write_scene_file(dir: &Path, sc: &LoadedScene, dense: bool) -> Result<()> {
    let path = dir.join(format!("{}.scene.json", sc.name));
    let storage = if dense {
        scene::Storage::Dense
    } else {
        scene::Storage::Auto {
            mtx_threshold: usize::MAX,
        }
    };
    scene::write_scene_as(&path, &sc.name, &sc.problem, Some(&sc.meta), storage)
}
