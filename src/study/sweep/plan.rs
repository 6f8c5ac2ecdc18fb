//! The sweep's plan: the scenes of a run in global order, their shards, and loading one.

use super::SweepConfig;
use crate::error::{Error, Result};
use crate::generate::{self, Family};
use crate::scene;
use crate::system::Problem;
use std::path::PathBuf;

/// Where a scene comes from.
#[derive(Clone, Debug)]
pub enum SceneSpec {
    /// Generated from (family, index).
    Generated {
        /// Family.
        family: Family,
        /// Index within the family.
        index: usize,
    },
    /// Read from a scene file.
    File(PathBuf),
}

/// The ordered list of scenes of a config.
pub fn plan(cfg: &SweepConfig) -> Result<Vec<SceneSpec>> {
    if let Some(dir) = &cfg.scenes_dir {
        let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir.display(), e))?;
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.ends_with(".scene.json"))
            })
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(Error::io(dir.display(), "no *.scene.json files found"));
        }
        return Ok(files.into_iter().map(SceneSpec::File).collect());
    }
    let mut out = Vec::new();
    for &family in &cfg.families {
        out.extend((0..cfg.count).map(|index| SceneSpec::Generated { family, index }));
    }
    Ok(out)
}

/// The contiguous block of `0..total` that shard `k` of `n` (1-based) owns.
pub fn shard_range(total: usize, k: usize, n: usize) -> std::ops::Range<usize> {
    (total * (k - 1) / n)..(total * k / n)
}

/// Parses `K/N` (1 ≤ K ≤ N).
pub fn parse_shard(s: &str) -> Result<(usize, usize)> {
    let bad = || Error::out_of_range("shard", format!("'{s}'"), "K/N with 1 ≤ K ≤ N");
    let (a, b) = s.split_once('/').ok_or_else(bad)?;
    let k: usize = a.trim().parse().map_err(|_| bad())?;
    let n: usize = b.trim().parse().map_err(|_| bad())?;
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// A loaded scene.
pub struct LoadedScene {
    /// Name.
    pub name: String,
    /// Family name.
    pub family: String,
    /// Problem.
    pub problem: Problem,
    /// Provenance.
    pub meta: serde_json::Value,
}

/// Builds or reads a scene.
pub fn load(spec: &SceneSpec, cfg: &SweepConfig) -> Result<LoadedScene> {
    match spec {
        SceneSpec::Generated { family, index } => {
            let g = generate::generate(*family, *index, cfg.seed, &cfg.generator)?;
            Ok(LoadedScene {
                name: g.name,
                family: family.name().to_string(),
                problem: g.problem,
                meta: g.meta,
            })
        }
        SceneSpec::File(path) => {
            let s = scene::read_scene_preferred(path)?;
            let family = s
                .meta
                .as_ref()
                .and_then(|m| m.get("generator"))
                .and_then(|g| g.as_str())
                .unwrap_or("file")
                .to_string();
            Ok(LoadedScene {
                name: s.name,
                family,
                problem: s.problem,
                meta: s.meta.unwrap_or(serde_json::Value::Null),
            })
        }
    }
}
