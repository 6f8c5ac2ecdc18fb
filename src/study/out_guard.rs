//! Outputs are never mixed: a study run into an `--out` that holds another run's record is
//! refused, unless `--resume` (finish that same run) or `--force` (replace it whole).
//!
//! Every run that saves writes [`MARKER`] into `--out` before it starts: the study's name, its
//! configuration (as JSON) and, once it has finished, the data files it wrote (`.csv`,
//! `.json`, `.png`, `.svg`, `.mtx`, `.jsonl`: what studies write). A later run into
//! that folder
//! - with the **same study and configuration** re-runs in place (so a command works twice) or,
//!   with `--resume`, picks up its checkpoints;
//! - with **another study or configuration** is refused with one line naming `--resume` and
//!   `--force`; with `--force` the files the old run wrote (the marker's list) are removed
//!   first — nothing else in the folder is touched (a hand-written `README.md` stays);
//! - into a folder that is **not empty and has no marker** (an older output, or anything else)
//!   is refused likewise (with `--resume`, the study's own resume checks decide); with `--force` only the data files there (`.csv`, `.json`, `.png`,
//!   `.svg`, `.mtx`, `.jsonl`) directly in the folder and in the study's figures folder are
//!   removed first (other subfolders, e.g. another run's output nested inside, stay).
//!
//! `--render-only` reads and never writes the marker.

use crate::error::{Error, Result};
use crate::provenance::write_atomic;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The run record's file name in `--out`.
pub const MARKER: &str = "penalty-lab-run.json";

/// Extensions of the files a study writes (removed by `--force` where no marker lists them).
const DATA_EXTENSIONS: [&str; 6] = ["csv", "json", "png", "svg", "mtx", "jsonl"];

/// The marker's content.
#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
struct Marker {
    study: String,
    config: serde_json::Value,
    /// Whether the run finished (its record saved and drawn).
    complete: bool,
    /// The files the run wrote, relative to `--out` (`/`-separated).
    files: Vec<String>,
}

/// A run about to write into `out`: checked, and its marker written ([`Guard::finish`]
/// completes it).
pub struct Guard {
    out: PathBuf,
    marker: Marker,
    started: SystemTime,
}

/// Checks `out` for `study` with `config` (module doc) and writes the marker of the new run.
pub fn claim(
    out: &Path,
    study: &str,
    config: serde_json::Value,
    figures_dir: &str,
    resume: bool,
    force: bool,
) -> Result<Guard> {
    if resume && force {
        return Err(Error::input(
            "--resume and --force exclude each other: --resume finishes the run in --out, \
             --force replaces it",
        ));
    }
    // File times come from the kernel's coarse clock, which can lag `SystemTime::now()` by a
    // tick: a file written just after the claim may carry an earlier time. A margin keeps it
    // (what else it catches was written by the run this one replaces or continues).
    let started = SystemTime::now() - std::time::Duration::from_secs(2);
    let mut marker = Marker {
        study: study.into(),
        config,
        complete: false,
        files: Vec::new(),
    };
    let path = out.join(MARKER);
    let old: Option<Marker> = match std::fs::read_to_string(&path) {
        Ok(text) => Some(serde_json::from_str(&text).map_err(|e| {
            Error::bad_file(
                path.display(),
                format!("not a run record ({e}); remove it or choose another --out"),
            )
        })?),
        Err(_) => None,
    };
    let nonempty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
    match old {
        Some(old) if old.study == marker.study && old.config == marker.config => {
            // The same run: again in place (or resumed); keep the files it listed.
            marker.files = old.files;
        }
        Some(old) => {
            if !force {
                let what = if old.study == marker.study {
                    format!("a {} run with a different config", old.study)
                } else {
                    format!("a {} run", old.study)
                };
                let msg = if resume {
                    format!(
                        "cannot resume here: it holds {what}; resume with that run's options, \
                         replace it whole with --force, or choose another --out"
                    )
                } else {
                    format!(
                        "holds the record of {what}; not mixing them: finish that run with its \
                         own options and --resume, replace it whole with --force, or choose \
                         another --out"
                    )
                };
                return Err(Error::bad_file(out.display(), msg));
            }
            for f in &old.files {
                remove_file(&out.join(f))?;
            }
            remove_file(&path)?;
            prune_empty_dirs(out);
        }
        // `--resume` into a folder of an older version (no record): the study's own resume
        // checks (the sweep's manifest, contact_bench's checkpoints) decide.
        None if nonempty && !resume => {
            if !force {
                return Err(Error::bad_file(
                    out.display(),
                    format!(
                        "is not empty and holds no run record ({MARKER}); not writing into it: \
                         choose a new or empty --out, or --force to replace its data files \
                         (.csv, .json, .png, .svg, .mtx, .jsonl)"
                    ),
                ));
            }
            let mut files = data_files(out, false);
            if !figures_dir.is_empty() {
                files.extend(data_files(&out.join(figures_dir), true));
            }
            for f in files {
                remove_file(&f)?;
            }
            prune_empty_dirs(out);
        }
        None => {}
    }
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    let guard = Guard {
        out: out.to_path_buf(),
        marker,
        started,
    };
    guard.write()?;
    Ok(guard)
}

/// Records in `out` a finished run of `study` with `config` that a study wrote under its own
/// checks (`sweep merge`): every file now in `out` is listed as its.
pub fn record_complete(out: &Path, study: &str, config: serde_json::Value) -> Result<()> {
    Guard {
        out: out.to_path_buf(),
        marker: Marker {
            study: study.into(),
            config,
            complete: false,
            files: Vec::new(),
        },
        started: SystemTime::UNIX_EPOCH,
    }
    .finish()
}

impl Guard {
    fn write(&self) -> Result<()> {
        let text = crate::provenance::json_text("run record", &self.marker)?;
        write_atomic(&self.out.join(MARKER), text.as_bytes())
    }

    /// Marks the run complete, listing every data file (the extensions a study writes) under
    /// `out` written since it started, and those an earlier pass of the same run listed: a
    /// README or notes a user keeps there are never listed, so never removed by `--force`.
    pub fn finish(mut self) -> Result<()> {
        let mut files = self.marker.files.clone();
        for f in data_files(&self.out, true) {
            let fresh = std::fs::metadata(&f)
                .and_then(|m| m.modified())
                .is_ok_and(|t| t >= self.started);
            let Ok(rel) = f.strip_prefix(&self.out) else {
                continue;
            };
            let rel: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            let rel = rel.join("/");
            if fresh && rel != MARKER && !files.contains(&rel) {
                files.push(rel);
            }
        }
        files.retain(|f| self.out.join(f).exists());
        files.sort();
        self.marker.files = files;
        self.marker.complete = true;
        self.write()
    }
}

fn remove_file(p: &Path) -> Result<()> {
    match std::fs::remove_file(p) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(Error::io(p.display(), format!("cannot remove: {e}"))),
    }
}

/// Every file under `dir` (recursively; symbolic links not followed).
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let Ok(t) = e.file_type() else { continue };
            if t.is_dir() {
                stack.push(e.path());
            } else if t.is_file() {
                out.push(e.path());
            }
        }
    }
    out
}

/// The data files (by extension) in `dir`, and in its subfolders where `deep`.
fn data_files(dir: &Path, deep: bool) -> Vec<PathBuf> {
    let files = if deep {
        walk(dir)
    } else {
        std::fs::read_dir(dir)
            .map(|d| {
                d.flatten()
                    .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
                    .map(|e| e.path())
                    .collect()
            })
            .unwrap_or_default()
    };
    files
        .into_iter()
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| DATA_EXTENSIONS.contains(&e))
        })
        .collect()
}

/// Removes the empty subfolders of `dir` (deepest first), never `dir` itself.
fn prune_empty_dirs(dir: &Path) {
    fn prune(d: &Path) -> bool {
        let Ok(entries) = std::fs::read_dir(d) else {
            return false;
        };
        let mut empty = true;
        for e in entries.flatten() {
            let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
            if !(is_dir && prune(&e.path()) && std::fs::remove_dir(e.path()).is_ok()) {
                empty = false;
            }
        }
        empty
    }
    prune(dir);
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn same_run_again_other_run_refused_force_replaces_only_its_files() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let run = |family: &str, force: bool| {
            let config = json!({ "families": [family] });
            claim(&out, "sweep", config, "figures", false, force)
        };
        let g = run("beam", false).unwrap();
        std::fs::create_dir_all(out.join("figures")).unwrap();
        std::fs::write(out.join("rows.csv"), "a\n").unwrap();
        std::fs::write(out.join("figures/x.png"), "p").unwrap();
        g.finish().unwrap();
        std::fs::write(out.join("README.md"), "mine").unwrap();
        // The same configuration runs again in place.
        run("beam", false).unwrap().finish().unwrap();
        // Another configuration is refused, naming both ways out; nothing is touched.
        let e = run("membrane", false).err().unwrap().to_string();
        assert!(e.contains("--resume") && e.contains("--force"), "{e}");
        assert!(out.join("rows.csv").exists() && out.join("figures/x.png").exists());
        // --force removes the old run's files, keeps the user's.
        let g = run("membrane", true).unwrap();
        assert!(!out.join("rows.csv").exists() && !out.join("figures").exists());
        assert!(out.join("README.md").exists());
        g.finish().unwrap();
        assert!(claim(&out, "sweep", json!({}), "figures", true, true).is_err());
    }

    #[test]
    fn a_folder_without_a_record_is_refused_unless_forced() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        std::fs::write(out.join("solver_cost.csv"), "a\n").unwrap();
        std::fs::write(out.join("README.md"), "mine").unwrap();
        std::fs::create_dir_all(out.join("figures")).unwrap();
        std::fs::create_dir_all(out.join("nested")).unwrap();
        std::fs::write(out.join("figures/a.png"), "p").unwrap();
        std::fs::write(out.join("nested/rows.csv"), "x").unwrap();
        let e = claim(out, "solver_cost", json!(1), "figures", false, false)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("--force"), "{e}");
        claim(out, "solver_cost", json!(1), "figures", false, true).unwrap();
        assert!(!out.join("solver_cost.csv").exists() && !out.join("figures").exists());
        assert!(
            out.join("nested/rows.csv").exists(),
            "another run nested inside stays"
        );
        assert!(out.join("README.md").exists() && out.join(MARKER).exists());
    }
}
