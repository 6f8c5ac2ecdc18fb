//! Resuming an interrupted run and writing rows in scene order as scenes finish (reorder buffer).

use super::rows::{self, Row};
use super::{run_scene, LoadedScene, RunOptions, SceneSpec, SetupSeconds, SweepConfig, Timing};
use crate::error::{Error, Result};
use crate::provenance::write_atomic;
use crate::scene;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// Where a `--resume` run picks up: the number of complete scenes at the head of an existing
/// rows.csv (which is cut back to them), after checking that the manifest was written with
/// the same config and shard; `None` for a fresh run (nothing written).
pub(super) fn resume_point(
    opts: &RunOptions,
    config_json: &serde_json::Value,
    (k, n): (usize, usize),
    per_scene: usize,
) -> Result<Option<usize>> {
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
    let done = rows.len() / per_scene;
    let keep = &rows[..done * per_scene];
    let mut text = rows::header();
    text.push_str(&rows::format_rows(keep));
    write_atomic(&rows_path, text.as_bytes())?;
    Ok(Some(done))
}

/// The reorder buffer: scenes finish in any order on the workers; whichever worker completes
/// the next scene in order appends it and every completed scene after it to rows.csv (one
/// write and flush per scene), so rows land in scene order with no thread of their own.
pub(super) struct InOrder<'a> {
    /// rows.csv open for appending, once its header and the manifest are written.
    file: Option<std::fs::File>,
    rows_path: &'a Path,
    /// Finished scenes waiting for an earlier one (or for the file).
    pending: BTreeMap<usize, Finished>,
    next: usize,
    rows_written: usize,
    times: &'a mut Timing,
    /// The error of the earliest failed scene (or of a write); nothing is written after it.
    error: Option<(usize, Error)>,
}

/// A solved scene: its rows, their CSV text and its shared work.
type Finished = (Vec<Row>, String, SetupSeconds);

impl<'a> InOrder<'a> {
    /// Nothing written yet; rows go to `rows_path` once it is opened, their timing to `times`.
    pub(super) fn new(rows_path: &'a Path, times: &'a mut Timing) -> Self {
        InOrder {
            file: None,
            rows_path,
            pending: BTreeMap::new(),
            next: 0,
            rows_written: 0,
            times,
            error: None,
        }
    }

    /// Files scene `i`'s outcome and writes the complete prefix.
    fn finish(&mut self, i: usize, done: Result<Finished>) {
        match done {
            Ok(f) => {
                self.pending.insert(i, f);
            }
            Err(e) => self.fail(i, e),
        }
        self.write_prefix();
    }

    /// Records the error of scene `i` (0 for the start: it precedes every scene's).
    fn fail(&mut self, i: usize, e: Error) {
        if self.error.as_ref().is_none_or(|(j, _)| i < *j) {
            self.error = Some((i, e));
        }
    }

    /// Appends the finished scenes that follow the last written one.
    fn write_prefix(&mut self) {
        let Some(file) = self.file.as_mut() else {
            return;
        };
        while let Some((rows, text, setup)) = self.pending.remove(&self.next) {
            self.times.add(&rows, &setup);
            if self.error.as_ref().is_some_and(|(j, _)| *j <= self.next) {
                break;
            }
            self.next += 1;
            match file.write_all(text.as_bytes()).and_then(|_| file.flush()) {
                Ok(()) => self.rows_written += rows.len(),
                Err(e) => {
                    self.error = Some((0, Error::io(self.rows_path.display(), e)));
                    break;
                }
            }
        }
    }
}

/// Solves `todo` on `pool` and appends each scene's rows to rows.csv in scene order as soon
/// as the prefix is complete ([`InOrder`]), writing scene files where asked; returns the
/// number of rows written or the first error. `start` (rows.csv's header, the running
/// manifest) runs on one worker while the others begin the first scenes; no row is written
/// before it is done. After an error, scenes after the failed one are not started. The rows are
/// formatted on the workers; the calling thread only waits.
pub(super) fn solve_in_order(
    todo: &[(usize, SceneSpec)],
    cfg: &SweepConfig,
    opts: &RunOptions,
    pool: &rayon::ThreadPool,
    bar: &crate::progress::Progress,
    writer: InOrder<'_>,
    start: impl FnOnce() -> Result<()> + Send,
) -> Result<usize> {
    use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
    use std::sync::{Mutex, PoisonError};
    let rows_path = writer.rows_path;
    let state = Mutex::new(writer);
    // The earliest failed scene (0 when the start failed): later scenes are not started.
    let failed = AtomicUsize::new(usize::MAX);
    let open = || {
        let opened = start().and_then(|()| {
            std::fs::OpenOptions::new()
                .append(true)
                .open(rows_path)
                .map_err(|e| Error::io(rows_path.display(), e))
        });
        let mut state = state.lock().unwrap_or_else(PoisonError::into_inner);
        match opened {
            Ok(file) => {
                state.file = Some(file);
                state.write_prefix();
            }
            Err(e) => {
                failed.store(0, Relaxed);
                state.fail(0, e);
            }
        }
    };
    let solve = || {
        use rayon::prelude::*;
        todo.par_iter()
            .enumerate()
            .with_max_len(1)
            .for_each(|(i, (_, spec))| {
                if i > failed.load(Relaxed) {
                    return; // nothing after the failed scene would be written
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
        None => Ok(state.rows_written),
    }
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
