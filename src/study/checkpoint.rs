//! Checkpoints of a long study: every finished unit of work (a mesh, a mesh level, a
//! (mesh, μ) pair) is written to `OUT/<dir>/<key>.json` the moment it finishes, so that an
//! interrupted run keeps it; `--resume` reads it back instead of computing it again.
//!
//! A checkpoint holds the build ([`crate::provenance::git_commit`]), the study's configuration
//! (as JSON), its key and its value. It is reused only when all three match the running build,
//! configuration and key exactly (a `-dirty` build matches another `-dirty` build of the same
//! commit: rebuild from a clean tree for records); any other is computed again and
//! overwritten. After the record is saved, [`Checkpoints::remove_in`] deletes the checkpoint files
//! (only files that parse as one) and the folder if that left it empty.
//!
//! Studies that checkpoint: `contact_bench` (per case and mesh, `meshes/`), `solver_cost`
//! (per family and level, `levels/`), `friction_bench` (per Cattaneo–Mindlin mesh and μ,
//! `cattaneo-mindlin/`).

use crate::error::{Error, Result};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Where a study keeps its checkpoints, and whether it reuses them (`--resume`).
#[derive(Clone, Debug)]
pub struct Checkpoints {
    /// The directory (created on the first write).
    pub dir: PathBuf,
    /// Reuse matching checkpoints instead of computing.
    pub resume: bool,
    /// The configuration they must match.
    config: serde_json::Value,
}

/// One checkpoint file (`V`: the value read, or a reference to the one written).
#[derive(Serialize, Deserialize)]
struct Envelope<V> {
    git_commit: String,
    config: serde_json::Value,
    key: String,
    value: V,
}

impl Checkpoints {
    /// The checkpoints of a run of `config` in `out/dir`.
    pub fn new(out: &Path, dir: &str, config: &impl Serialize, resume: bool) -> Result<Self> {
        let config = serde_json::to_value(config)
            .map_err(|e| Error::Numerical(format!("cannot write the config as JSON: {e}")))?;
        Ok(Checkpoints {
            dir: out.join(dir),
            resume,
            config,
        })
    }

    fn path(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}.json"))
    }

    /// The value of `key` if `--resume` was given and a checkpoint of this build and
    /// configuration holds it; a malformed file is a parse error ([`Error::Parse`]) naming it,
    /// the line and the column.
    pub fn read<V: DeserializeOwned>(&self, key: &str) -> Result<Option<V>> {
        let path = self.path(key);
        if !self.resume || !path.exists() {
            return Ok(None);
        }
        let c: Envelope<V> = crate::provenance::read_json(&path)?;
        let fits = c.git_commit == crate::provenance::git_commit()
            && c.config == self.config
            && c.key == key;
        Ok(fits.then_some(c.value))
    }

    /// Writes the checkpoint of `key` (atomically).
    pub fn write<V: Serialize>(&self, key: &str, value: &V) -> Result<()> {
        std::fs::create_dir_all(&self.dir).map_err(|e| Error::io(self.dir.display(), e))?;
        let c = Envelope {
            git_commit: crate::provenance::git_commit(),
            config: self.config.clone(),
            key: key.to_string(),
            value,
        };
        crate::provenance::write_json(&self.path(key), &c)
    }

    /// The value of `key`: read back (with `--resume`, module doc) or computed by `f` and
    /// checkpointed at once. The flag says whether it was read back.
    pub fn get_or<V, F>(&self, key: &str, f: F) -> Result<(V, bool)>
    where
        V: Serialize + DeserializeOwned,
        F: FnOnce() -> Result<V>,
    {
        if let Some(v) = self.read(key)? {
            return Ok((v, true));
        }
        let v = f()?;
        self.write(key, &v)?;
        Ok((v, false))
    }

    /// [`Checkpoints::get_or`] for a run that may keep none (`None`: `f` runs, nothing is
    /// kept).
    pub fn get_or_maybe<V, F>(checkpoints: Option<&Self>, key: &str, f: F) -> Result<(V, bool)>
    where
        V: Serialize + DeserializeOwned,
        F: FnOnce() -> Result<V>,
    {
        match checkpoints {
            Some(c) => c.get_or(key, f),
            None => Ok((f()?, false)),
        }
    }

    /// Removes the checkpoint files of `out/dir` once the record is saved: the `.json` files
    /// that parse as a checkpoint of any build, then the directory if that left it empty.
    /// Anything else a user keeps there stays.
    pub fn remove_in(out: &Path, dir: &str) -> Result<()> {
        let dir = out.join(dir);
        let Ok(entries) = std::fs::read_dir(&dir) else {
            return Ok(());
        };
        for e in entries.flatten() {
            let path = e.path();
            let is_file = e.file_type().is_ok_and(|t| t.is_file());
            if !is_file || path.extension().is_none_or(|x| x != "json") {
                continue;
            }
            let checkpoint =
                crate::provenance::read_json::<Envelope<serde::de::IgnoredAny>>(&path).is_ok();
            if checkpoint {
                std::fs::remove_file(&path).map_err(|err| Error::io(path.display(), err))?;
            }
        }
        let _ = std::fs::remove_dir(&dir); // only if empty
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::study::checkpoint::Checkpoints;

    /// A checkpoint is read back only with `--resume` and only for the same configuration;
    /// removing them keeps every other file, and the folder while it holds one.
    #[test]
    fn checkpoints_round_trip_and_removal_keeps_other_files() {
        let dir = tempfile::tempdir().unwrap();
        let cfg = serde_json::json!({ "levels": 3 });
        let fresh = Checkpoints::new(dir.path(), "levels", &cfg, false).unwrap();
        let (v, read) = fresh.get_or("a-level0", || Ok(vec![1.5, 2.0])).unwrap();
        assert_eq!((v, read), (vec![1.5, 2.0], false));
        // Without --resume the value is computed again.
        let (_, read) = fresh.get_or("a-level0", || Ok(vec![0.0])).unwrap();
        assert!(!read);
        let resumed = Checkpoints::new(dir.path(), "levels", &cfg, true).unwrap();
        let (v, read) = resumed
            .get_or("a-level0", || -> crate::error::Result<Vec<f64>> {
                panic!("a matching checkpoint is read, not computed")
            })
            .unwrap();
        assert_eq!((v, read), (vec![0.0], true));
        let other = serde_json::json!({ "levels": 4 });
        let other = Checkpoints::new(dir.path(), "levels", &other, true).unwrap();
        assert_eq!(other.read::<Vec<f64>>("a-level0").unwrap(), None);
        assert_eq!(resumed.read::<Vec<f64>>("b-level0").unwrap(), None);

        let levels = dir.path().join("levels");
        std::fs::write(levels.join("notes.txt"), "mine").unwrap();
        std::fs::write(levels.join("other.json"), "{\"a\": 1}").unwrap();
        Checkpoints::remove_in(dir.path(), "levels").unwrap();
        assert!(!levels.join("a-level0.json").exists());
        assert!(levels.join("notes.txt").exists() && levels.join("other.json").exists());
        std::fs::remove_file(levels.join("notes.txt")).unwrap();
        std::fs::remove_file(levels.join("other.json")).unwrap();
        resumed.write("a-level1", &1).unwrap();
        Checkpoints::remove_in(dir.path(), "levels").unwrap();
        assert!(!levels.exists(), "an emptied folder is removed");
    }
}
