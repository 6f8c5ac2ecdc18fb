//! Outputs are never mixed: a study run into an `--out` that holds another run's record is
//! refused, unless `--resume` (finish that same run) or `--force` (replace it whole).
//!
//! Every run that saves writes [`MARKER`] into `--out` before it starts: the study's name, its
//! configuration (as JSON) and, once it has finished, the data files it wrote (`.csv`,
//! `.json`, `.png`, `.svg`, `.mtx`, `.jsonl`: what studies write). A later run into that folder
//! - with the **same study and configuration** re-runs in place (so a command works twice) or,
//!   with `--resume`, picks up its checkpoints;
//! - with **another study or configuration** is refused with one line naming `--resume` (where
//!   the study resumes) and `--force`; with `--force` the files the old run listed are removed
//!   first — nothing else in the folder is touched (a hand-written `README.md` stays);
//! - into a folder that is **not empty and has no marker** (an older output, or anything else)
//!   is refused likewise; with `--force` only the data files directly in the folder and in the
//!   study's figures folder are removed first.
//!
//! What is never touched: a listed entry that is absolute, holds `..`, is not a data file or
//! lies under a symbolic link (a hand-edited or foreign marker cannot reach outside `--out`);
//! a subfolder holding another run's marker (a nested run); hidden folders (`.git`) and
//! `target/`. Only folders emptied by the removal are removed. A run that fails before writing
//! anything into a folder it found empty takes its marker away again, so the corrected command
//! is not refused; one that wrote something leaves its marker, incomplete, listing it.
//! `--render-only` reads and never writes the marker.

use crate::error::{Error, Result};
use crate::provenance::{remove_if_present, write_atomic};
use serde::{Deserialize, Serialize};
use std::path::{Component, Path, PathBuf};
use std::time::SystemTime;

/// The run record's file name in `--out`.
pub const MARKER: &str = "penalty-lab-run.json";

/// Extensions of the files a study writes (the only files a record lists or `--force` removes).
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
/// completes it, [`Guard::abandon`] withdraws it after a failure).
pub struct Guard {
    out: PathBuf,
    marker: Marker,
    started: SystemTime,
    /// The folder held nothing before this run (new or empty).
    fresh: bool,
}

/// What the study is, for [`claim`].
pub struct Claimant<'a> {
    /// The study's name.
    pub study: &'a str,
    /// Its configuration as JSON (what identifies the run).
    pub config: serde_json::Value,
    /// Where under `--out` it draws (`""`: `--out` itself).
    pub figures_dir: &'a str,
    /// Whether it takes `--resume`.
    pub resumable: bool,
}

/// Checks `out` for the claimant (module doc) and writes the marker of the new run.
pub fn claim(out: &Path, who: Claimant<'_>, resume: bool, force: bool) -> Result<Guard> {
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
        study: who.study.into(),
        config: who.config,
        complete: false,
        files: Vec::new(),
    };
    let path = out.join(MARKER);
    let old: Option<Marker> = match std::fs::read_to_string(&path) {
        Ok(text) => match serde_json::from_str(&text) {
            Ok(m) => Some(m),
            Err(_) if force => None, // replaced below like a folder without a record
            Err(e) => {
                return Err(Error::bad_file(
                    path.display(),
                    format!("not a run record ({e}); --force replaces it, or choose another --out"),
                ))
            }
        },
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(Error::io(path.display(), format!("cannot read: {e}"))),
    };
    let nonempty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
    let resume_hint = if who.resumable {
        "finish that run with its own options and --resume, "
    } else {
        ""
    };
    match old {
        Some(old) if old.study == marker.study && old.config == marker.config => {
            // The same run: again in place (or resumed); keep the files it listed.
            marker.files = old.files.into_iter().filter(|f| safe_entry(f)).collect();
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
                        "holds the record of {what}; not mixing them: {resume_hint}replace it \
                         whole with --force, or choose another --out"
                    )
                };
                return Err(Error::bad_file(out.display(), msg));
            }
            let listed: Vec<PathBuf> = old
                .files
                .iter()
                .filter(|f| safe_entry(f) && inside(out, f))
                .map(|f| out.join(f))
                .collect();
            remove_all(out, &listed)?;
            remove_if_present(&path)?;
        }
        None if nonempty => {
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
            if !who.figures_dir.is_empty() && inside(out, who.figures_dir) {
                files.extend(data_files(&out.join(who.figures_dir), true));
            }
            remove_all(out, &files)?;
            remove_if_present(&path)?;
        }
        None => {}
    }
    let fresh = !nonempty;
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    let guard = Guard {
        out: out.to_path_buf(),
        marker,
        started,
        fresh,
    };
    guard.write()?;
    Ok(guard)
}

/// For a study that guards its own output (`sweep merge`): whether `out` is new, empty, or
/// holds the record of this same run (study and configuration).
pub fn is_new_or_same(out: &Path, study: &str, config: &serde_json::Value) -> bool {
    let nonempty = std::fs::read_dir(out).is_ok_and(|mut d| d.next().is_some());
    !nonempty
        || std::fs::read_to_string(out.join(MARKER))
            .ok()
            .and_then(|t| serde_json::from_str::<Marker>(&t).ok())
            .is_some_and(|m| m.study == study && &m.config == config)
}

/// Records in `out` a finished run of `study` with `config` that a study wrote under its own
/// checks (`sweep merge`), with the files it wrote (relative to `out`).
pub fn record_complete(
    out: &Path,
    study: &str,
    config: serde_json::Value,
    files: &[&str],
) -> Result<()> {
    Guard {
        out: out.to_path_buf(),
        marker: Marker {
            study: study.into(),
            config,
            complete: true,
            files: files.iter().map(|f| f.to_string()).collect(),
        },
        started: SystemTime::now(),
        fresh: false,
    }
    .write()
}

impl Guard {
    fn write(&self) -> Result<()> {
        let text = crate::provenance::json_text("run record", &self.marker)?;
        write_atomic(&self.out.join(MARKER), text.as_bytes())
    }

    /// Marks the run complete, listing every data file under `out` written since it started
    /// (nested runs, hidden folders and `target/` left out), and those an earlier pass of the
    /// same run listed: a README or notes a user keeps there are never listed, so never
    /// removed by `--force`.
    pub fn finish(mut self) -> Result<()> {
        self.list_written();
        self.marker.complete = true;
        self.write()
    }

    /// After a failed run: where it found the folder empty and wrote nothing, its marker goes
    /// again (the corrected command is then not refused); otherwise the marker stays,
    /// incomplete, listing what the run wrote (`--resume` continues it, `--force` removes it).
    pub fn abandon(mut self) {
        let only_marker = std::fs::read_dir(&self.out)
            .is_ok_and(|d| d.flatten().all(|e| e.file_name() == MARKER));
        if self.fresh && only_marker {
            let _ = std::fs::remove_file(self.out.join(MARKER));
        } else {
            self.list_written();
            let _ = self.write();
        }
    }

    /// The marker's list: what it had, plus every data file written since the run started.
    fn list_written(&mut self) {
        let mut files = self.marker.files.clone();
        for f in data_files(&self.out, true) {
            let fresh = std::fs::metadata(&f)
                .and_then(|m| m.modified())
                .is_ok_and(|t| t >= self.started);
            let Some(rel) = relative(&self.out, &f) else {
                continue;
            };
            if fresh && rel != MARKER && !files.contains(&rel) {
                files.push(rel);
            }
        }
        files.retain(|f| self.out.join(f).is_file());
        files.sort();
        self.marker.files = files;
    }
}

/// `f` relative to `out`, `/`-separated.
fn relative(out: &Path, f: &Path) -> Option<String> {
    let rel = f.strip_prefix(out).ok()?;
    let parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    Some(parts.join("/"))
}

/// A listed entry that may be touched: relative, plain names only (no `..`, `.`, root or
/// prefix), a data file's extension.
fn safe_entry(rel: &str) -> bool {
    let p = Path::new(rel);
    !rel.is_empty()
        && p.components().all(|c| matches!(c, Component::Normal(_)))
        && p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| DATA_EXTENSIONS.contains(&e))
}

/// Whether every folder between `out` and `rel` is a real folder (no symbolic link on the way:
/// removing `rel` cannot reach outside `out`).
fn inside(out: &Path, rel: &str) -> bool {
    let mut p = out.to_path_buf();
    let comps: Vec<_> = Path::new(rel).components().collect();
    comps[..comps.len().saturating_sub(1)].iter().all(|c| {
        p.push(c);
        std::fs::symlink_metadata(&p).is_ok_and(|m| m.is_dir())
    })
}

/// Removes `files` (regular files or links to files; folders are skipped), then the folders
/// under `out` this left empty.
fn remove_all(out: &Path, files: &[PathBuf]) -> Result<()> {
    for f in files {
        if std::fs::symlink_metadata(f).is_ok_and(|m| !m.is_dir()) {
            remove_if_present(f)?;
        }
    }
    for f in files {
        let mut d = f.parent();
        while let Some(dir) = d {
            if dir == out || !dir.starts_with(out) || std::fs::remove_dir(dir).is_err() {
                break;
            }
            d = dir.parent();
        }
    }
    Ok(())
}

/// Every file under `dir` (recursively), not following symbolic links (not even `dir`
/// itself) and not entering a nested run (a subfolder with its own [`MARKER`]), a hidden
/// folder or `target/`.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    if !std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        return out;
    }
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let Ok(t) = e.file_type() else { continue };
            let name = e.file_name();
            let name = name.to_string_lossy();
            if t.is_dir() {
                let nested = e.path().join(MARKER).exists();
                if !(nested || name.starts_with('.') || name == "target") {
                    stack.push(e.path());
                }
            } else if t.is_file() {
                out.push(e.path());
            }
        }
    }
    out
}

/// The data files (by extension) in `dir`, and in its subfolders where `deep` ([`walk`]).
fn data_files(dir: &Path, deep: bool) -> Vec<PathBuf> {
    let files = if deep {
        walk(dir)
    } else if std::fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        std::fs::read_dir(dir)
            .map(|d| {
                d.flatten()
                    .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
                    .map(|e| e.path())
                    .collect()
            })
            .unwrap_or_default()
    } else {
        Vec::new()
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

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn who(config: serde_json::Value) -> Claimant<'static> {
        Claimant {
            study: "sweep",
            config,
            figures_dir: "figures",
            resumable: true,
        }
    }

    #[test]
    fn same_run_again_other_run_refused_force_replaces_only_its_files() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let run = |family: &str, force: bool| {
            claim(&out, who(json!({ "families": [family] })), false, force)
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
        assert!(claim(&out, who(json!({})), true, true).is_err());
    }

    #[test]
    fn a_folder_without_a_record_is_refused_unless_forced() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path();
        std::fs::write(out.join("solver_cost.csv"), "a\n").unwrap();
        std::fs::write(out.join("README.md"), "mine").unwrap();
        std::fs::create_dir_all(out.join("figures/nested-run")).unwrap();
        std::fs::create_dir_all(out.join("nested")).unwrap();
        std::fs::write(out.join("figures/a.png"), "p").unwrap();
        std::fs::write(out.join("figures/nested-run/rows.csv"), "x").unwrap();
        std::fs::write(out.join("figures/nested-run").join(MARKER), "{}").unwrap();
        std::fs::write(out.join("nested/rows.csv"), "x").unwrap();
        let e = claim(out, who(json!(1)), false, false)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("--force"), "{e}");
        claim(out, who(json!(1)), false, true).unwrap();
        assert!(!out.join("solver_cost.csv").exists() && !out.join("figures/a.png").exists());
        assert!(out.join("README.md").exists() && out.join(MARKER).exists());
        assert!(out.join("nested/rows.csv").exists(), "another folder stays");
        assert!(
            out.join("figures/nested-run/rows.csv").exists(),
            "a nested run stays"
        );
    }

    /// A marker cannot reach outside `--out`: entries with `..`, absolute paths, non-data
    /// files and paths through a symbolic link are never removed; nor is a symlinked figures
    /// folder followed.
    #[cfg(unix)]
    #[test]
    fn force_never_reaches_outside_out() {
        let dir = tempfile::tempdir().unwrap();
        let (out, elsewhere) = (dir.path().join("out"), dir.path().join("elsewhere"));
        std::fs::create_dir_all(&out).unwrap();
        std::fs::create_dir_all(&elsewhere).unwrap();
        let victims = ["victim.csv", "abs.csv", "keep.txt"].map(|f| elsewhere.join(f));
        for v in &victims {
            std::fs::write(v, "x").unwrap();
        }
        std::os::unix::fs::symlink(&elsewhere, out.join("link")).unwrap();
        let marker = json!({"study": "other", "config": null, "complete": true, "files": [
            "../elsewhere/victim.csv", victims[1].to_str().unwrap(), "link/victim.csv",
            "notes.txt", "link"]});
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        std::fs::write(out.join(MARKER), marker.to_string()).unwrap();
        claim(&out, who(json!(2)), false, true).unwrap();
        assert!(
            victims.iter().all(|v| v.exists()),
            "outside --out untouched"
        );
        assert!(out.join("notes.txt").exists() && out.join("link").exists());

        // No record, figures a link to elsewhere: not followed.
        let out2 = dir.path().join("out2");
        std::fs::create_dir_all(&out2).unwrap();
        std::os::unix::fs::symlink(&elsewhere, out2.join("figures")).unwrap();
        std::fs::write(out2.join("rows.csv"), "x").unwrap();
        claim(&out2, who(json!(2)), false, true).unwrap();
        assert!(
            victims.iter().all(|v| v.exists()),
            "a linked figures folder is not followed"
        );
    }

    #[test]
    fn a_failed_run_in_an_empty_folder_takes_its_marker_away() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new");
        claim(&out, who(json!("typo")), false, false)
            .unwrap()
            .abandon();
        assert!(!out.join(MARKER).exists());
        claim(&out, who(json!("fixed")), false, false)
            .unwrap()
            .finish()
            .unwrap();
        // In a folder that held a run, the marker stays (incomplete) after a failure.
        claim(&out, who(json!("fixed")), false, false)
            .unwrap()
            .abandon();
        assert!(out.join(MARKER).exists());
        // A failed run that wrote something keeps its marker, listing it.
        let out2 = dir.path().join("partial");
        let g = claim(&out2, who(json!("p")), false, false).unwrap();
        std::fs::write(out2.join("rows.csv"), "x").unwrap();
        g.abandon();
        let m: Marker =
            serde_json::from_str(&std::fs::read_to_string(out2.join(MARKER)).unwrap()).unwrap();
        assert_eq!((m.complete, m.files), (false, vec!["rows.csv".to_string()]));
    }
}
