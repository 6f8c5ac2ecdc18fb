//! Helpers of the `sweep` end-to-end tests (`sweep_*`): running the binary in a test's own
//! temporary folder, the small configuration most tests use, reading rows and manifests, and
//! the scene-file runs.

use crate::common;
pub(crate) use crate::common::stderr;
use penalty_lab::generate::Family;
use penalty_lab::study::sweep::rows::{self, Row};
use penalty_lab::study::sweep::{self, SweepConfig};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use tempfile::TempDir;

pub(crate) const SWEEP: &str = env!("CARGO_BIN_EXE_sweep");
pub(crate) const SOLVE: &str = env!("CARGO_BIN_EXE_solve");

/// A fresh, empty folder for one test (the guard, removed when it drops) and its path.
pub(crate) fn work_dir(name: &str) -> (TempDir, PathBuf) {
    let tmp = common::tmp_dir(&format!("sweep-{name}"));
    let d = tmp.path().to_path_buf();
    (tmp, d)
}

/// `sweep ARGS` run in `cwd`, stdin closed.
fn sweep_cmd(cwd: &Path, args: &[&str]) -> Command {
    let mut cmd = Command::new(SWEEP);
    cmd.args(args).current_dir(cwd).stdin(Stdio::null());
    cmd
}

pub(crate) fn sweep_in(cwd: &Path, args: &[&str]) -> Output {
    sweep_cmd(cwd, args).output().expect("run sweep")
}

/// Runs the sweep and requires success.
#[track_caller]
pub(crate) fn sweep_ok(cwd: &Path, args: &[&str]) -> Output {
    common::run_ok(&mut sweep_cmd(cwd, args))
}

/// Runs the sweep with `args` into `d/out` (no figures, quiet), writing its scenes into
/// `d/scenes`: its rows and the scene folder.
#[track_caller]
pub(crate) fn sweep_writing_scenes(d: &Path, args: &[&str]) -> (Vec<Row>, PathBuf) {
    let (out, scenes) = (d.join("out"), d.join("scenes"));
    let tail = [
        "--no-figures",
        "--quiet",
        "--out",
        s(&out),
        "--write-scenes",
        s(&scenes),
    ];
    sweep_ok(d, &with(args, &tail));
    (rows_of(&out), scenes)
}

/// Rows of `dir/rows.csv` (strict parse), without timing.
pub(crate) fn rows_of(dir: &Path) -> Vec<Row> {
    let (rows, _) = rows::read_rows(&dir.join("rows.csv"), false)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    rows.iter().map(Row::without_timing).collect()
}

pub(crate) fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 temp path")
}

/// A small config: three families, two scenes each, every method, three ε, one factor, one δ.
pub(crate) const SMALL: [&str; 12] = [
    "--families",
    "beam,membrane,spectrum",
    "--count",
    "2",
    "--eps",
    "1e0:1e8:3",
    "--factors",
    "10",
    "--deltas-rel",
    "1e-2",
    "--seed",
    "77",
];

pub(crate) fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(extra).copied().collect()
}

/// The config SMALL describes (for row counts).
pub(crate) fn small_config() -> SweepConfig {
    SweepConfig {
        families: vec![Family::Beam, Family::Membrane, Family::Spectrum],
        count: 2,
        seed: 77,
        eps: sweep::LogGrid {
            lo: 1.0,
            hi: 1e8,
            n: 3,
        },
        factors: vec![10.0],
        deltas: vec![],
        deltas_rel: vec![1e-2],
        ..SweepConfig::default()
    }
}

/// Rows must come in complete scenes, each scene once, in plan order, no duplicate keys.
pub(crate) fn assert_well_formed(rows: &[Row], cfg: &SweepConfig, scenes: usize) {
    let per = cfg.rows_per_scene();
    assert_eq!(rows.len(), scenes * per, "rows = scenes × rows_per_scene");
    let mut seen = std::collections::BTreeSet::new();
    for chunk in rows.chunks(per) {
        assert!(chunk.iter().all(|r| r.scene == chunk[0].scene));
        assert!(
            seen.insert(chunk[0].scene.clone()),
            "scene {} appears twice",
            chunk[0].scene
        );
        assert_eq!(chunk[0].method, "lagrange", "lagrange row first");
    }
}

pub(crate) fn manifest(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap()
}

pub(crate) fn write_toml(d: &Path, name: &str, text: &str) -> PathBuf {
    let p = d.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

/// The knobs of the scene-file runs.
pub(crate) const FILE_RUN_KNOBS: [&str; 7] = [
    "--eps",
    "1e0:1e8:3",
    "--factors",
    "10",
    "--deltas-rel",
    "1e-2",
    "--no-figures",
];

/// Writes the scenes of a small 2-family run and reruns them from the files. Returns the
/// test's folder (the guard), the generated rows, the file rows and the scenes folder. The
/// beams have at most 30 elements: `optimal` (in the default rules) costs seconds per solve
/// from about a hundred elements, and five tests share this run.
pub(crate) fn generated_and_file_runs(tag: &str) -> (TempDir, Vec<Row>, Vec<Row>, PathBuf) {
    let (tmp, d) = work_dir(tag);
    let (gen, files, scenes) = (d.join("gen"), d.join("files"), d.join("scenes"));
    let cfg = write_toml(
        &d,
        "small",
        "families = [\"beam\", \"spectrum\"]\ncount = 2\nseed = 31\n\
         [generator]\nbeam_elements = [3, 30]\n",
    );
    let knobs = FILE_RUN_KNOBS;
    sweep_ok(
        &d,
        &with(
            &knobs,
            &[
                "--config",
                s(&cfg),
                "--out",
                s(&gen),
                "--write-scenes",
                s(&scenes),
            ],
        ),
    );
    let names: Vec<String> = {
        let mut v: Vec<String> = std::fs::read_dir(&scenes)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".scene.json"))
            .collect();
        v.sort();
        v
    };
    assert_eq!(
        names,
        [
            "beam-0000.scene.json",
            "beam-0001.scene.json",
            "spectrum-0000.scene.json",
            "spectrum-0001.scene.json"
        ]
    );
    sweep_ok(
        &d,
        &with(&knobs, &["--scenes-dir", s(&scenes), "--out", s(&files)]),
    );
    (tmp, rows_of(&gen), rows_of(&files), scenes)
}
