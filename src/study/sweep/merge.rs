//! `sweep merge OUT DIR...`: the shards of one run (`--shard K/N`, e.g. the tasks of a Slurm
//! job array) into one `rows.csv` and one manifest, as if the run had not been split.
//!
//! Shards are contiguous blocks of the scene order, so their rows concatenated in shard order
//! are the unsharded rows (all columns but the `seconds*` ones). Before writing anything the
//! merge checks that the folders describe exactly one run, and refuses with one line naming
//! the folder otherwise:
//!
//! * every folder holds a complete shard (`manifest.json` with `status: complete`, a
//!   `rows.csv` with the manifest's `scenes × rows_per_scene` rows);
//! * the same config, seed, git commit and shard count N in every manifest;
//! * each shard `K/N` present exactly once, none missing;
//! * OUT is none of the shard folders.
//!
//! The merged manifest is the one an unsharded run writes (shard `[1, 1]`, so `--resume` on
//! OUT finds it complete and `--render-only` draws from it), plus `merged_from` (folder,
//! shard, commit and wall time of each shard) and the timing of the shards summed.

use super::rows;
use crate::error::{Error, Result};
use crate::provenance::{write_atomic, Provenance};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// What a merge did.
#[derive(Clone, Debug)]
pub struct MergeSummary {
    /// Shards merged.
    pub shards: usize,
    /// Scenes in the merged run.
    pub scenes: usize,
    /// Rows written.
    pub rows: usize,
}

struct Shard {
    dir: PathBuf,
    manifest: Value,
    k: usize,
    n: usize,
}

fn read_shard(dir: &Path) -> Result<Shard> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        Error::bad_file(
            dir.display(),
            format!("no readable manifest.json ({e}): not a sweep output folder"),
        )
    })?;
    let manifest: Value = serde_json::from_str(&text)
        .map_err(|e| Error::bad_file(dir.display(), format!("manifest.json is not JSON ({e})")))?;
    let shard = manifest
        .get("shard")
        .and_then(|s| s.as_array())
        .and_then(|a| Some((a.first()?.as_u64()?, a.get(1)?.as_u64()?)))
        .ok_or_else(|| {
            Error::bad_file(
                dir.display(),
                "manifest.json has no shard [K, N]: not a sweep manifest",
            )
        })?;
    if manifest.get("status").and_then(Value::as_str) != Some("complete") {
        return Err(Error::bad_file(
            dir.display(),
            format!(
                "shard {}/{} is not complete (status {}); finish it with --resume first",
                shard.0,
                shard.1,
                manifest.get("status").unwrap_or(&Value::Null)
            ),
        ));
    }
    Ok(Shard {
        dir: dir.to_path_buf(),
        k: shard.0 as usize,
        n: shard.1 as usize,
        manifest,
    })
}

/// The first of `config`, `seed`, `git_commit` and the shard count where `b` differs from `a`.
fn differs(a: &Shard, b: &Shard) -> Option<&'static str> {
    for key in ["config", "seed", "git_commit"] {
        if a.manifest.get(key) != b.manifest.get(key) {
            return Some(key);
        }
    }
    (a.n != b.n).then_some("shard count")
}

/// Checks the shard folders and returns them in shard order.
fn check(out: &Path, dirs: &[PathBuf]) -> Result<Vec<Shard>> {
    if dirs.is_empty() {
        return Err(Error::none_given("sweep merge: shard folders", ""));
    }
    let same_dir = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    };
    if let Some(d) = dirs.iter().find(|d| same_dir(d, out)) {
        return Err(Error::bad_file(
            d.display(),
            "sweep merge: OUT is one of the shard folders; merge into another folder",
        ));
    }
    let shards = dirs
        .iter()
        .map(|d| read_shard(d))
        .collect::<Result<Vec<_>>>()?;
    let first = &shards[0];
    for s in &shards[1..] {
        if let Some(what) = differs(first, s) {
            return Err(Error::bad_file(
                s.dir.display(),
                format!(
                    "sweep merge: belongs to another run ({what} differs from {})",
                    first.dir.display()
                ),
            ));
        }
    }
    let n = first.n;
    let mut by_k: Vec<Option<Shard>> = (0..n).map(|_| None).collect();
    for s in shards {
        if s.k == 0 || s.k > n {
            return Err(Error::bad_file(
                s.dir.display(),
                format!("shard {}/{n} is out of range", s.k),
            ));
        }
        if let Some(other) = &by_k[s.k - 1] {
            return Err(Error::duplicate(
                "sweep merge: shard",
                format!(
                    "{}/{n} ({} and {})",
                    s.k,
                    other.dir.display(),
                    s.dir.display()
                ),
            ));
        }
        let k = s.k;
        by_k[k - 1] = Some(s);
    }
    if let Some(k) = by_k.iter().position(Option::is_none) {
        return Err(Error::none_given(
            format!("sweep merge: shard {}/{n}", k + 1),
            format!(
                " (got {} of {n} shards; every shard of the run is needed)",
                by_k.iter().flatten().count()
            ),
        ));
    }
    Ok(by_k.into_iter().flatten().collect())
}

fn count(manifest: &Value, key: &str) -> usize {
    manifest.get(key).and_then(Value::as_u64).unwrap_or(0) as usize
}

/// Sums the shards' per-method and scene-setup timing.
fn summed_timing(shards: &[Shard]) -> Value {
    fn add(acc: &mut Value, v: &Value) {
        match (acc, v) {
            (Value::Object(a), Value::Object(b)) => {
                for (k, x) in b {
                    add(a.entry(k.clone()).or_insert(Value::Null), x);
                }
            }
            (acc @ Value::Null, x) => *acc = x.clone(),
            (Value::Number(a), Value::Number(b)) => {
                let s = a.as_f64().unwrap_or(0.0) + b.as_f64().unwrap_or(0.0);
                *a = serde_json::Number::from_f64(s).unwrap_or_else(|| 0.into());
            }
            _ => {}
        }
    }
    let mut acc = serde_json::json!({});
    for s in shards {
        if let Some(t) = s.manifest.get("timing") {
            for key in ["per_method", "scene_setup", "busy_seconds"] {
                if let Some(v) = t.get(key) {
                    add(
                        acc.as_object_mut()
                            .unwrap()
                            .entry(key)
                            .or_insert(Value::Null),
                        v,
                    );
                }
            }
        }
    }
    acc
}

/// What identifies a sweep run in its output folder: its configuration (as the manifest
/// writes it) and its shard.
pub fn run_identity(config: serde_json::Value, shard: Option<(usize, usize)>) -> serde_json::Value {
    serde_json::json!({"run": {"config": config, "shard": shard}})
}

/// Merges the shard folders `dirs` (any order) into `out`: `rows.csv` in scene order and one
/// manifest. Nothing is written unless every check passes and every shard's rows read back.
/// The merged manifest records `provenance`.
pub fn merge(out: &Path, dirs: &[PathBuf], provenance: &Provenance) -> Result<MergeSummary> {
    let shards = check(out, dirs)?;
    let config = shards[0]
        .manifest
        .get("config")
        .cloned()
        .unwrap_or(Value::Null);
    if !crate::study::out_guard::is_new_or_same(out, "sweep", &run_identity(config.clone(), None)) {
        return Err(Error::bad_file(
            out.display(),
            "sweep merge: OUT is not empty and holds no record of this merge; merge into a new \
             or empty folder",
        ));
    }
    let mut text = rows::header();
    let mut total_rows = 0;
    let mut scenes = 0;
    for s in &shards {
        let path = s.dir.join("rows.csv");
        let (rs, _) = rows::read_rows(&path, false)?;
        let expected = count(&s.manifest, "scenes") * count(&s.manifest, "rows_per_scene");
        if rs.len() != expected {
            return Err(Error::bad_file(
                path.display(),
                format!("{} rows, but its manifest promises {expected}", rs.len()),
            ));
        }
        text.push_str(&rows::format_rows(&rs));
        total_rows += rs.len();
        scenes += count(&s.manifest, "scenes");
    }
    let first = &shards[0].manifest;
    let merged_from: Vec<Value> = shards
        .iter()
        .map(|s| {
            serde_json::json!({
                "dir": s.dir.display().to_string(),
                "shard": [s.k, s.n],
                "git_commit": s.manifest.get("git_commit"),
                "wall_seconds": s.manifest.get("wall_seconds"),
            })
        })
        .collect();
    let mut manifest = provenance.record(serde_json::json!({
        "config": first.get("config"),
        "seed": first.get("seed"),
        "shard": [1, 1],
        "scenes": scenes,
        "rows_per_scene": first.get("rows_per_scene"),
        "status": "complete",
        "rows_written": total_rows,
        "rows_in_file": total_rows,
        "resumed_scenes": 0,
        "merged_from": merged_from,
        "timing": summed_timing(&shards),
    }));
    // The rows were computed by the shards' build: keep its commit as the data's commit.
    manifest["git_commit"] = first.get("git_commit").cloned().unwrap_or(Value::Null);
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    write_atomic(&out.join("rows.csv"), text.as_bytes())?;
    let m = serde_json::to_string_pretty(&manifest).expect("a JSON value serializes");
    write_atomic(&out.join("manifest.json"), m.as_bytes())?;
    // The merged folder is the unsharded run: `sweep --resume` of its config accepts it.
    crate::study::out_guard::record_complete(
        out,
        "sweep",
        run_identity(config, None),
        &["rows.csv", "manifest.json"],
    )?;
    Ok(MergeSummary {
        shards: shards.len(),
        scenes,
        rows: total_rows,
    })
}
