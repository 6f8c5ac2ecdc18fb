//! End-to-end tests of the `sweep` binary (and its agreement with `solve`): determinism across
//! thread counts, shards, kill-and-resume (including a torn write), the default run's files,
//! bad configuration (exit 2, one line, nothing written), and `--scenes-dir` reproducing a
//! generated run row for row.
//!
//! Every test uses small configs and its own folder under `std::env::temp_dir()`.

use penalty_lab::generate::DEFAULT_FAMILIES as FAMILY_NAMES;
use penalty_lab::study::sweep::rows::{self, Row};
use penalty_lab::study::sweep::{self, figures::FIGURE_KINDS, SweepConfig};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SWEEP: &str = env!("CARGO_BIN_EXE_sweep");
const SOLVE: &str = env!("CARGO_BIN_EXE_solve");

/// A fresh, empty folder for one test.
fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "penalty_lab_sweep_cli_{}_{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create temp dir");
    d
}

fn sweep_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(SWEEP)
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .output()
        .expect("run sweep")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs the sweep and requires success.
fn sweep_ok(cwd: &Path, args: &[&str]) -> Output {
    let o = sweep_in(cwd, args);
    assert!(
        o.status.success(),
        "sweep {args:?} failed ({:?}):\n{}",
        o.status,
        stderr(&o)
    );
    o
}

/// Rows of `dir/rows.csv` (strict parse), without timing.
fn rows_of(dir: &Path) -> Vec<Row> {
    let (rows, _) = rows::read_rows(&dir.join("rows.csv"), false)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    rows.iter().map(Row::without_timing).collect()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 temp path")
}

/// A small config: three families, two scenes each, every method, three ε, one factor, one δ.
const SMALL: [&str; 12] = [
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

fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
    base.iter().chain(extra).copied().collect()
}

/// The config SMALL describes (for row counts).
fn small_config() -> SweepConfig {
    SweepConfig {
        families: vec!["beam".into(), "membrane".into(), "spectrum".into()],
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
fn assert_well_formed(rows: &[Row], cfg: &SweepConfig, scenes: usize) {
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

// ---------------------------------------------------------------------------------------------
// 1. Determinism across thread counts
// ---------------------------------------------------------------------------------------------

#[test]
fn rows_are_identical_for_one_and_two_threads() {
    let d = tmp_dir("threads");
    let (o1, o2) = (d.join("t1"), d.join("t2"));
    sweep_ok(
        &d,
        &with(&SMALL, &["--threads", "1", "--no-figures", "--out", s(&o1)]),
    );
    sweep_ok(
        &d,
        &with(&SMALL, &["--threads", "2", "--no-figures", "--out", s(&o2)]),
    );
    let (r1, r2) = (rows_of(&o1), rows_of(&o2));
    assert_well_formed(&r1, &small_config(), 6);
    assert_eq!(r1, r2, "rows differ between --threads 1 and --threads 2");
    // Timing is the only column allowed to differ: every row has one.
    let (raw, _) = rows::read_rows(&o2.join("rows.csv"), false).expect("rows");
    assert!(raw.iter().all(|r| r.seconds.is_some_and(|t| t >= 0.0)));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(o1.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["threads"], 1);
}

// ---------------------------------------------------------------------------------------------
// 2. Shards
// ---------------------------------------------------------------------------------------------

#[test]
fn shards_concatenate_into_the_unsharded_rows() {
    let d = tmp_dir("shards");
    let (all, a, b) = (d.join("all"), d.join("s1"), d.join("s2"));
    sweep_ok(&d, &with(&SMALL, &["--no-figures", "--out", s(&all)]));
    sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--shard", "1/2", "--out", s(&a)]),
    );
    sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--shard", "2/2", "--out", s(&b)]),
    );
    let mut cat = rows_of(&a);
    let second = rows_of(&b);
    assert!(!cat.is_empty() && !second.is_empty());
    cat.extend(second);
    assert_eq!(cat, rows_of(&all), "shard 1/2 ++ shard 2/2 ≠ unsharded");

    // A 3-way split of the same 6 scenes, too.
    let mut cat3 = Vec::new();
    for k in 1..=3 {
        let o = d.join(format!("t{k}"));
        let shard = format!("{k}/3");
        sweep_ok(
            &d,
            &with(&SMALL, &["--no-figures", "--shard", &shard, "--out", s(&o)]),
        );
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(o.join("manifest.json")).unwrap())
                .unwrap();
        assert_eq!(m["shard"], serde_json::json!([k, 3]));
        assert_eq!(m["scenes"], 2);
        cat3.extend(rows_of(&o));
    }
    assert_eq!(cat3, rows_of(&all), "shards 1..3 of 3 ≠ unsharded");

    // `sweep merge` of 4 shards given in any order: the unsharded rows and a complete
    // manifest that --resume accepts and --render-only draws from.
    let shards = four_shards(&d);
    let merged = d.join("merged");
    let mut args = vec!["merge", s(&merged)];
    args.extend([3, 1, 4, 2].map(|k| s(&shards[k - 1])));
    sweep_ok(&d, &args);
    assert_eq!(
        rows_of(&merged),
        rows_of(&all),
        "merged 4 shards ≠ unsharded"
    );
    let m = manifest(&merged);
    assert_eq!(m["status"], "complete");
    assert_eq!(m["shard"], serde_json::json!([1, 1]));
    assert_eq!(m["merged_from"].as_array().unwrap().len(), 4);
    let o = sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--resume", "--out", s(&merged)]),
    );
    assert_eq!(rows_of(&merged), rows_of(&all), "{}", stderr(&o));
    sweep_ok(&d, &["--render-only", "--out", s(&merged)]);
    assert!(merged.join("figures").read_dir().unwrap().count() > 0);
}

fn manifest(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap()
}

/// Shards 1..4 of 4 of the SMALL run, in `d/q1` … `d/q4`.
fn four_shards(d: &Path) -> Vec<PathBuf> {
    (1..=4)
        .map(|k| {
            let o = d.join(format!("q{k}"));
            let shard = format!("{k}/4");
            sweep_ok(
                d,
                &with(&SMALL, &["--no-figures", "--shard", &shard, "--out", s(&o)]),
            );
            o
        })
        .collect()
}

#[test]
fn merge_refuses_missing_duplicated_foreign_and_incomplete_shards() {
    let d = tmp_dir("merge_refuses");
    let q = four_shards(&d);
    let foreign = d.join("foreign");
    let other_seed: Vec<&str> = SMALL
        .iter()
        .map(|&a| if a == "77" { "78" } else { a })
        .collect();
    sweep_ok(
        &d,
        &with(
            &other_seed,
            &["--no-figures", "--shard", "4/4", "--out", s(&foreign)],
        ),
    );
    let incomplete = d.join("incomplete");
    std::fs::create_dir_all(&incomplete).unwrap();
    std::fs::copy(q[3].join("rows.csv"), incomplete.join("rows.csv")).unwrap();
    let mut m = manifest(&q[3]);
    m["status"] = "running".into();
    std::fs::write(incomplete.join("manifest.json"), m.to_string()).unwrap();
    let out = d.join("out");
    let cases: [(Vec<&Path>, &str); 5] = [
        (vec![&q[0], &q[1], &q[3]], "shard 3/4 is missing"),
        (vec![&q[0], &q[1], &q[1], &q[2], &q[3]], "given twice"),
        (
            vec![&q[0], &q[1], &q[2], &foreign],
            "belongs to another run (config differs",
        ),
        (vec![&q[0], &q[1], &q[2], &incomplete], "is not complete"),
        (
            vec![&q[0], &q[1], &q[2], &q[3], &d],
            "no readable manifest.json",
        ),
    ];
    for (dirs, needle) in cases {
        let mut args = vec!["merge", s(&out)];
        args.extend(dirs.iter().map(|p| s(p)));
        let o = sweep_in(&d, &args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(
            e.starts_with("error:") && e.trim_end().lines().count() == 1,
            "{e}"
        );
        assert!(e.contains(needle), "{needle:?} not in {e}");
        assert!(!out.exists(), "a refused merge wrote {}", out.display());
    }
    // OUT may not be one of the shards.
    let mut args = vec!["merge", s(&q[0])];
    args.extend(q.iter().map(|p| s(p)));
    let o = sweep_in(&d, &args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is one of the shard folders"),
        "{}",
        stderr(&o)
    );
}

/// The timing columns: each part non-negative and no larger than the row's total, empty where
/// the metric was not requested; the manifest's per-method sums are the rows' sums, and it
/// reports rows/s and a parallel efficiency in (0, 1].
#[test]
fn timing_columns_add_up_in_rows_and_manifest() {
    let d = tmp_dir("timing");
    for (metrics, cond, det) in [("cond,det", true, true), ("none", false, false)] {
        let out = d.join(metrics.replace(',', "_"));
        sweep_ok(
            &d,
            &with(
                &SMALL,
                &["--metrics", metrics, "--no-figures", "--out", s(&out)],
            ),
        );
        let (rows, _) = rows::read_rows(&out.join("rows.csv"), false).unwrap();
        let m = manifest(&out);
        let t = &m["timing"];
        for r in &rows {
            let total = r.seconds.unwrap();
            let parts = [r.seconds_solve, r.seconds_cond, r.seconds_det];
            assert!(
                parts.iter().flatten().all(|&p| p >= 0.0 && p <= total),
                "{r:?}"
            );
            assert!(
                parts.iter().flatten().sum::<f64>() <= total * (1.0 + 1e-9),
                "{r:?}"
            );
            assert!(r.seconds_solve.is_some());
            // Errors and skipped `optimal` rows (outside optimal_families) measure nothing.
            let failed = r.warnings.starts_with("error") || r.warnings.starts_with("skipped:");
            for (requested, part) in [(cond, r.seconds_cond), (det, r.seconds_det)] {
                if !requested {
                    assert!(part.is_none(), "{r:?}");
                } else if !failed {
                    assert!(part.is_some(), "{r:?}");
                }
            }
        }
        for method in ["lagrange", "constant", "condensed"] {
            let of: Vec<&Row> = rows.iter().filter(|r| r.method == method).collect();
            let pm = &t["per_method"][method];
            assert_eq!(pm["rows"], of.len());
            let sum: f64 = of.iter().map(|r| r.seconds_solve.unwrap()).sum();
            let got = pm["seconds_solve"].as_f64().unwrap();
            assert!(
                (got - sum).abs() <= 1e-12 * sum.max(1e-300) * of.len() as f64,
                "{method}: {got} vs {sum}"
            );
        }
        assert!(t["rows_per_second"].as_f64().unwrap() > 0.0);
        let eff = t["parallel_efficiency"].as_f64().unwrap();
        assert!(eff > 0.0 && eff <= 1.0 + 1e-9, "efficiency {eff}");
    }
}

#[test]
fn shard_ranges_cover_every_scene_exactly_once() {
    // The example of the brief: shard 3/3 of 5 scenes.
    assert_eq!(sweep::shard_range(5, 1, 3), 0..1);
    assert_eq!(sweep::shard_range(5, 2, 3), 1..3);
    assert_eq!(sweep::shard_range(5, 3, 3), 3..5);
    for total in 0..80usize {
        for n in 1..=17usize {
            let mut next = 0;
            for k in 1..=n {
                let r = sweep::shard_range(total, k, n);
                assert_eq!(
                    r.start, next,
                    "total {total}, shard {k}/{n}: gap or overlap"
                );
                assert!(r.end >= r.start);
                // Balanced: sizes differ by at most one.
                assert!(
                    r.len() == total / n || r.len() == total / n + 1,
                    "total {total}, shard {k}/{n}: size {}",
                    r.len()
                );
                next = r.end;
            }
            assert_eq!(next, total, "total {total}, n {n}: not all covered");
        }
    }
    // Large totals do not overflow for realistic sizes.
    let r = sweep::shard_range(1_000_000_007, 1000, 1000);
    assert_eq!(r.end, 1_000_000_007);

    assert_eq!(sweep::parse_shard("3/3").unwrap(), (3, 3));
    assert_eq!(sweep::parse_shard(" 1 / 4 ").unwrap(), (1, 4));
    for bad in ["3/2", "0/2", "1/0", "x", "1/", "/2", "1/2/3", "-1/2", ""] {
        assert!(sweep::parse_shard(bad).is_err(), "'{bad}' accepted");
    }
}

#[test]
fn shard_with_no_scenes_is_not_a_failed_run() {
    // 2 scenes in 8 shards: shard 3/8 is empty. Either that is fine (exit 0, empty rows.csv)
    // or it is a configuration error reported before anything is written — not a run that
    // writes a "complete" manifest and then exits 2 because there is nothing to plot.
    let d = tmp_dir("empty_shard");
    let out = d.join("o");
    let o = sweep_in(
        &d,
        &[
            "--families",
            "beam",
            "--count",
            "2",
            "--eps",
            "1e0:1e8:3",
            "--deltas-rel",
            "1e-2",
            "--shard",
            "3/8",
            "--out",
            s(&out),
        ],
    );
    if o.status.success() {
        assert!(rows_of(&out).is_empty());
    } else {
        assert_eq!(o.status.code(), Some(2));
        assert!(
            !out.join("rows.csv").exists(),
            "exit 2 after writing rows.csv/manifest.json (stderr: {})",
            stderr(&o)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Kill and resume
// ---------------------------------------------------------------------------------------------

/// A config that takes a couple of seconds: dense beams of 100–150 elements.
fn write_big_config(dir: &Path, count: usize) -> (PathBuf, SweepConfig) {
    let path = dir.join(format!("big{count}.toml"));
    std::fs::write(
        &path,
        format!(
            "families = [\"beam\"]\ncount = {count}\nseed = 5\ndeltas_rel = [1e-2]\n\
             factors = [10.0]\neps = {{ lo = 1.0, hi = 1e8, n = 9 }}\n\
             methods = [\"constant\", \"scaled\", \"spring\", \"paper\", \"condensed\", \"augmented\"]\n\
             [generator]\nbeam_elements = [100, 150]\n"
        ),
    )
    .unwrap();
    let cfg = SweepConfig::from_toml_file(&path).expect("valid TOML");
    (path, cfg)
}

/// Starts `sweep ARGS` and kills it once some scenes are on disk (after at most 1 s). Returns
/// the rows on disk and the byte length of their whole lines, or `None` when the run finished
/// (or had written every row) before it could be killed.
fn kill_mid_run(d: &Path, args: &[&str], out: &Path, cfg: &SweepConfig) -> Option<(usize, usize)> {
    let expected = cfg.count * cfg.rows_per_scene();
    let mut child = Command::new(SWEEP)
        .args(args)
        .current_dir(d)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn sweep");
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_millis(1000) {
        std::thread::sleep(Duration::from_millis(50));
        let n = std::fs::read_to_string(out.join("rows.csv"))
            .map(|t| t.lines().count())
            .unwrap_or(0);
        if t0.elapsed() > Duration::from_millis(400) && n > cfg.rows_per_scene() * 2 {
            break;
        }
    }
    let finished = child.try_wait().expect("try_wait").is_some();
    child.kill().ok();
    child.wait().expect("wait");
    let (partial, good) = rows::read_rows(&out.join("rows.csv"), true).expect("lenient read");
    if finished || partial.len() >= expected {
        return None;
    }
    eprintln!(
        "killed after {:?}: {} of {expected} rows on disk",
        t0.elapsed(),
        partial.len()
    );
    Some((partial.len(), good))
}

/// `--resume` of the interrupted run in `out` with another config or another shard: exit 2,
/// one line, rows.csv untouched.
fn assert_foreign_resumes_refused(d: &Path, cfg_path: &Path, args: &[&str], out: &Path) {
    let before = std::fs::read(out.join("rows.csv")).unwrap();
    let o = sweep_in(
        d,
        &[
            "--config",
            s(cfg_path),
            "--count",
            "3",
            "--no-figures",
            "--resume",
            "--out",
            s(out),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "stderr: {}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.starts_with("error:") && e.trim_end().lines().count() == 1,
        "{e}"
    );
    assert!(
        e.contains("cannot resume") && e.contains("different config"),
        "{e}"
    );
    assert_eq!(std::fs::read(out.join("rows.csv")).unwrap(), before);
    let o = sweep_in(d, &with(args, &["--resume", "--shard", "1/2"]));
    assert_eq!(o.status.code(), Some(2), "stderr: {}", stderr(&o));
    assert_eq!(std::fs::read(out.join("rows.csv")).unwrap(), before);
}

/// Torn write: cuts the interrupted copy `torn` back to its `good` bytes of whole lines
/// (`on_disk` rows), appends two complete lines of the next scene from the uninterrupted run
/// `full` and half of a third, and checks that `--resume` repairs it to `reference`.
#[allow(clippy::too_many_arguments)]
fn assert_torn_write_repaired(
    d: &Path,
    cfg_path: &Path,
    torn: &Path,
    full: &Path,
    on_disk: usize,
    good: usize,
    expected: usize,
    reference: &[Row],
) {
    let torn_rows = torn.join("rows.csv");
    std::fs::OpenOptions::new()
        .write(true)
        .open(&torn_rows)
        .unwrap()
        .set_len(good as u64)
        .unwrap();
    let full_text = std::fs::read_to_string(full.join("rows.csv")).unwrap();
    let full_lines: Vec<&str> = full_text.split_inclusive('\n').skip(1).collect();
    let mut extra = String::new();
    for line in &full_lines[on_disk..(on_disk + 2).min(expected)] {
        extra.push_str(line);
    }
    if on_disk + 2 < expected {
        let third = full_lines[on_disk + 2];
        extra.push_str(&third[..third.len() / 2]);
    } else {
        extra.push_str("beam-99");
    }
    let mut f = std::fs::OpenOptions::new()
        .append(true)
        .open(&torn_rows)
        .unwrap();
    f.write_all(extra.as_bytes()).unwrap();
    drop(f);
    assert!(
        rows::read_rows(&torn_rows, false).is_err(),
        "a torn last line must not parse strictly"
    );
    sweep_ok(
        d,
        &[
            "--config",
            s(cfg_path),
            "--threads",
            "2",
            "--no-figures",
            "--resume",
            "--out",
            s(torn),
        ],
    );
    assert_eq!(
        rows_of(torn),
        reference,
        "torn write not repaired by --resume"
    );
    let raw = std::fs::read_to_string(&torn_rows).unwrap();
    assert!(raw.ends_with('\n'));
    assert_eq!(raw.matches(&rows::header()).count(), 1);
}

#[test]
fn killed_run_resumes_to_the_uninterrupted_rows() {
    let d = tmp_dir("resume");
    let mut count = 12;
    let (cfg_path, cfg, out, args, on_disk, good) = loop {
        let (cfg_path, cfg) = write_big_config(&d, count);
        let out = d.join(format!("killed{count}"));
        let args: Vec<String> = [
            "--config",
            s(&cfg_path),
            "--threads",
            "2",
            "--no-figures",
            "--out",
            s(&out),
        ]
        .map(String::from)
        .to_vec();
        let a: Vec<&str> = args.iter().map(String::as_str).collect();
        if let Some((on_disk, good)) = kill_mid_run(&d, &a, &out, &cfg) {
            break (cfg_path, cfg, out, args, on_disk, good);
        }
        assert!(
            count < 400,
            "cannot interrupt the sweep even with {count} scenes"
        );
        count *= 2;
    };
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let expected = cfg.count * cfg.rows_per_scene();

    // Uninterrupted reference (same config, another folder).
    let full = d.join(format!("full{count}"));
    sweep_ok(
        &d,
        &["--config", s(&cfg_path), "--no-figures", "--out", s(&full)],
    );
    let reference = rows_of(&full);
    assert_well_formed(&reference, &cfg, cfg.count);

    // A copy of the interrupted run, for the torn-write variant.
    let torn = d.join(format!("torn{count}"));
    std::fs::create_dir_all(&torn).unwrap();
    for f in ["rows.csv", "manifest.json"] {
        std::fs::copy(out.join(f), torn.join(f)).unwrap();
    }
    assert_foreign_resumes_refused(&d, &cfg_path, &args, &out);

    // Resume: the same rows as the uninterrupted run, none lost, none duplicated.
    let o = sweep_ok(&d, &with(&args, &["--resume"]));
    assert_eq!(
        rows_of(&out),
        reference,
        "resumed rows ≠ uninterrupted rows"
    );
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["status"], "complete");
    let resumed = m["resumed_scenes"].as_u64().unwrap() as usize;
    assert_eq!(resumed, on_disk / cfg.rows_per_scene(), "{}", stderr(&o));
    assert_eq!(
        m["rows_written"].as_u64().unwrap() as usize,
        expected - resumed * cfg.rows_per_scene()
    );
    // Resuming a complete run changes nothing.
    sweep_ok(&d, &with(&args, &["--resume"]));
    assert_eq!(rows_of(&out), reference);

    assert_torn_write_repaired(
        &d, &cfg_path, &torn, &full, on_disk, good, expected, &reference,
    );
}

// ---------------------------------------------------------------------------------------------
// 4. The default run
// ---------------------------------------------------------------------------------------------

#[test]
fn default_run_writes_rows_manifest_and_figures() {
    let d = tmp_dir("default");
    sweep_ok(&d, &[]);
    let out = d.join("results").join("sweep");
    let cfg = SweepConfig::default();
    let scenes = cfg.families.len() * cfg.count;
    assert_eq!(scenes, 24, "the documented default is 24 scenes");
    let rows = rows_of(&out);
    assert_well_formed(&rows, &cfg, scenes);
    assert_eq!(rows.len(), 24 * cfg.rows_per_scene());
    for fam in FAMILY_NAMES {
        assert!(rows.iter().any(|r| r.family == fam), "no {fam} rows");
    }
    assert!(rows
        .iter()
        .all(|r| r.warnings.is_empty() || !r.warnings.contains('\n')));

    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap())
            .expect("manifest is JSON");
    for key in [
        "git_commit",
        "config",
        "seed",
        "crate_versions",
        "threads",
        "wall_seconds",
        "rows_per_second",
        "status",
    ] {
        assert!(
            m.get(key).is_some_and(|v| !v.is_null()),
            "manifest lacks {key}"
        );
    }
    assert_eq!(m["status"], "complete");
    assert_eq!(m["seed"], cfg.seed);
    assert_eq!(m["config"], serde_json::to_value(&cfg).unwrap());
    assert!(m["crate_versions"]["penalty-lab"].is_string());
    assert!(m["threads"].as_u64().unwrap() >= 1);
    assert!(m["wall_seconds"].as_f64().unwrap() > 0.0);
    assert!(m["rows_per_second"].as_f64().unwrap() > 0.0);
    assert_eq!(m["rows_written"], rows.len());

    let figs = out.join("figures");
    let expected: Vec<PathBuf> = FIGURE_KINDS
        .iter()
        .flat_map(|k| FAMILY_NAMES.iter().map(move |f| format!("{k}_{f}")))
        .flat_map(|stem| ["png", "svg"].map(|e| figs.join(format!("{stem}.{e}"))))
        .collect();
    assert_eq!(expected.len(), 24);
    for p in &expected {
        let len = std::fs::metadata(p)
            .unwrap_or_else(|_| panic!("missing {}", p.display()))
            .len();
        assert!(len > 0, "{} is empty", p.display());
    }

    // --render-only re-renders from rows.csv (rows untouched).
    let rows_before = std::fs::read(out.join("rows.csv")).unwrap();
    std::fs::remove_dir_all(&figs).unwrap();
    let o = sweep_ok(&d, &["--render-only", "--out", s(&out)]);
    assert!(stderr(&o).contains("rendered"), "{}", stderr(&o));
    for p in &expected {
        assert!(
            p.exists(),
            "--render-only did not re-render {}",
            p.display()
        );
    }
    assert_eq!(std::fs::read(out.join("rows.csv")).unwrap(), rows_before);

    // --render-only on a folder without rows.csv: exit 2, one line.
    let o = sweep_in(&d, &["--render-only", "--out", s(&d.join("nothing"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).starts_with("error:"));
}

// ---------------------------------------------------------------------------------------------
// 5. Bad configuration
// ---------------------------------------------------------------------------------------------

/// Runs a bad config; requires exit 2, one stderr line starting with "error:" that contains
/// every `needle`, and no rows.csv written.
fn assert_rejected(d: &Path, tag: &str, args: &[&str], needles: &[&str]) {
    let out = d.join(format!("out_{tag}"));
    let all = with(args, &["--out", s(&out)]);
    let o = sweep_in(d, &all);
    let e = stderr(&o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{all:?}: status {:?}, stderr {e}",
        o.status
    );
    assert!(e.starts_with("error:"), "{all:?}: {e}");
    assert_eq!(
        e.trim_end().lines().count(),
        1,
        "{all:?}: stderr is not one line:\n{e}"
    );
    for n in needles {
        assert!(e.contains(n), "{all:?}: message lacks '{n}': {e}");
    }
    assert!(
        !out.join("rows.csv").exists(),
        "{all:?}: rows.csv written before validation"
    );
    assert!(
        !out.join("manifest.json").exists(),
        "{all:?}: manifest written"
    );
}

#[test]
fn bad_configuration_exits_2_with_one_line_and_writes_nothing() {
    let d = tmp_dir("bad");
    let methods = [
        "constant",
        "scaled",
        "spring",
        "paper",
        "condensed",
        "lagrange",
        "augmented",
    ];
    assert_rejected(
        &d,
        "method",
        &["--methods", "constant,penalty"],
        &[&["'penalty'"][..], &methods[..]].concat(),
    );
    assert_rejected(
        &d,
        "family",
        &["--families", "beam,shell"],
        &["'shell'", "beam", "membrane", "spectrum"],
    );
    assert_rejected(&d, "eps2", &["--eps", "1:2"], &["'1:2'", "LO:HI:N"]);
    assert_rejected(&d, "eps0", &["--eps", "0:1:3"], &["'0:1:3'", "LO:HI:N"]);
    assert_rejected(&d, "epsabc", &["--eps", "a:b:c"], &["'a:b:c'", "LO:HI:N"]);
    assert_rejected(&d, "epsrev", &["--eps", "1e3:1e1:3"], &["LO:HI:N"]);
    assert_rejected(&d, "eps1", &["--eps", "1:2:1"], &["LO:HI:N"]);
    assert_rejected(&d, "deltaneg", &["--deltas", "-1"], &["--deltas", "> 0"]);
    assert_rejected(&d, "delta0", &["--deltas", "0"], &["--deltas", "> 0"]);
    assert_rejected(&d, "deltarel", &["--deltas-rel", "0"], &["--deltas-rel"]);
    assert_rejected(&d, "factor", &["--factors", "-3"], &["factor"]);
    assert_rejected(&d, "shard32", &["--shard", "3/2"], &["'3/2'", "K/N"]);
    assert_rejected(&d, "shardx", &["--shard", "x"], &["'x'", "K/N"]);
    assert_rejected(&d, "shard0", &["--shard", "0/2"], &["K/N"]);
    assert_rejected(
        &d,
        "scenesdir",
        &["--scenes-dir", s(&d.join("no_such_dir"))],
        &["no_such_dir"],
    );
    let empty = d.join("empty_scenes");
    std::fs::create_dir_all(&empty).unwrap();
    assert_rejected(
        &d,
        "scenesempty",
        &["--scenes-dir", s(&empty)],
        &["empty_scenes", "scene.json"],
    );
    assert_rejected(
        &d,
        "metric",
        &["--metrics", "cond,flops"],
        &["'flops'", "cond", "det"],
    );
    assert_rejected(&d, "count0", &["--count", "0"], &["--count"]);
    assert_rejected(&d, "threads0", &["--threads", "0"], &["--threads"]);
    let nodelta = write_toml(&d, "nodelta", "deltas_rel = []\n");
    assert_rejected(
        &d,
        "nodelta",
        &["--methods", "condensed", "--config", s(&nodelta)],
        &["δ", "--deltas"],
    );
    assert_rejected(
        &d,
        "generator",
        &[
            "--config",
            s(&write_toml(
                &d,
                "gen",
                "[generator]\nbeam_elements = [2, 10]\n",
            )),
        ],
        &["beam_elements", "3 ≤ min"],
    );
    assert_rejected(
        &d,
        "noconfig",
        &["--config", s(&d.join("missing.toml"))],
        &["missing.toml"],
    );
}

fn write_toml(d: &Path, name: &str, text: &str) -> PathBuf {
    let p = d.join(format!("{name}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn toml_config_with_unknown_field_is_a_one_line_error() {
    let d = tmp_dir("bad_toml");
    let p = write_toml(&d, "typo", "famlies = [\"beam\"]\ncount = 2\n");
    assert_rejected(&d, "typo", &["--config", s(&p)], &["famlies", "families"]);
    let p = write_toml(&d, "gentypo", "[generator]\nbeam_elems = [3, 5]\n");
    assert_rejected(&d, "gentypo", &["--config", s(&p)], &["beam_elems"]);
}

// ---------------------------------------------------------------------------------------------
// 6. Scene files: `--scenes-dir` and `solve` reproduce the generated rows
// ---------------------------------------------------------------------------------------------

/// Writes the scenes of a small 2-family run and reruns them from the files.
/// The knobs of the scene-file runs.
const FILE_RUN_KNOBS: [&str; 7] = [
    "--eps",
    "1e0:1e8:3",
    "--factors",
    "10",
    "--deltas-rel",
    "1e-2",
    "--no-figures",
];

/// Returns (generated rows, file rows, scenes folder).
fn generated_and_file_runs(tag: &str) -> (Vec<Row>, Vec<Row>, PathBuf) {
    let d = tmp_dir(tag);
    let (gen, files, scenes) = (d.join("gen"), d.join("files"), d.join("scenes"));
    let knobs = FILE_RUN_KNOBS;
    sweep_ok(
        &d,
        &with(
            &knobs,
            &[
                "--families",
                "beam,spectrum",
                "--count",
                "2",
                "--seed",
                "31",
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
    (rows_of(&gen), rows_of(&files), scenes)
}

#[test]
fn scenes_dir_reproduces_the_generated_rows() {
    let (gen, files, _) = generated_and_file_runs("scenes_dir");
    assert_eq!(gen.len(), files.len());
    assert!(!gen.is_empty());
    // Scene names come from the files' "name", the family from meta.generator: the rows are
    // identical, naming included (scene file order = generated order here).
    for (g, f) in gen.iter().zip(&files) {
        assert_eq!(
            g, f,
            "row of {} differs when run from the scene file",
            g.scene
        );
    }
}

/// A malformed scene file stops the run with exit 2 and a message naming it; rows.csv then
/// holds exactly the complete scenes before it, in order (whatever the thread count), the
/// manifest still says `running`, and once the file is repaired `--resume` completes the rows.
#[test]
fn a_malformed_scene_file_keeps_the_scenes_before_it_and_resumes() {
    let (_, files, scenes) = generated_and_file_runs("malformed_scene");
    let d = scenes.parent().unwrap().to_path_buf();
    let per_scene = files.len() / 4;
    let broken = scenes.join("spectrum-0000.scene.json");
    let good = std::fs::read(&broken).unwrap();
    std::fs::write(&broken, &good[..good.len() / 2]).unwrap();
    let out = d.join("broken");
    let args = with(
        &FILE_RUN_KNOBS,
        &[
            "--threads",
            "2",
            "--scenes-dir",
            s(&scenes),
            "--out",
            s(&out),
        ],
    );
    let o = sweep_in(&d, &args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("spectrum-0000.scene.json"),
        "{}",
        stderr(&o)
    );
    assert_eq!(rows_of(&out), files[..2 * per_scene]);
    assert_eq!(manifest(&out)["status"], "running");
    std::fs::write(&broken, &good).unwrap();
    sweep_ok(&d, &with(&args, &["--resume"]));
    assert_eq!(rows_of(&out), files);
    assert_eq!(manifest(&out)["resumed_scenes"], 2);
}

/// The raw JSON number of a top-level key of `solve --json`'s pretty output, parsed with Rust's
/// correctly rounded parser (`None` for `null`).
fn top_level_number(json: &str, key: &str) -> Option<f64> {
    let pat = format!("\n  \"{key}\": ");
    let i = json
        .find(&pat)
        .unwrap_or_else(|| panic!("no '{key}' in {json}"))
        + pat.len();
    let tok = json[i..].split([',', '\n']).next().unwrap().trim();
    if tok == "null" {
        None
    } else {
        Some(
            tok.parse()
                .unwrap_or_else(|_| panic!("{key}: bad number {tok}")),
        )
    }
}

/// `solve`'s arguments for a row's method and knob (full precision).
fn solve_args(row: &Row) -> Vec<String> {
    let mut a = vec!["--method".to_string(), row.method.clone()];
    let fmt = |x: Option<f64>| format!("{:e}", x.expect("knob"));
    match row.method.as_str() {
        "constant" => a.extend(["--eps".into(), fmt(row.eps)]),
        "scaled" => a.extend(["--factor".into(), fmt(row.factor)]),
        "spring" | "paper" | "condensed" | "optimal" => {
            a.extend(["--delta".into(), fmt(row.delta)])
        }
        "augmented" => a.extend([
            "--eps".into(),
            fmt(row.eps),
            "--tol".into(),
            fmt(row.delta),
            "--adaptive".into(),
        ]),
        "lagrange" => {}
        m => panic!("unexpected method {m}"),
    }
    a.extend(["--exact-start".into(), "--json".into()]);
    a
}

/// The rows checked against `solve`: every method at its middle knob, first scene of each family.
fn rows_for_solve(rows: &[Row]) -> Vec<&Row> {
    let mut picked = Vec::new();
    for scene in ["beam-0000", "spectrum-0000"] {
        for r in rows.iter().filter(|r| r.scene == scene) {
            let keep = match r.method.as_str() {
                "constant" => r.eps == Some(1e4),
                // Not run outside `optimal_families` (beam, file): nothing to reproduce.
                "optimal" => !r.warnings.starts_with("skipped:"),
                _ => true,
            };
            if keep {
                picked.push(r);
            }
        }
    }
    // 8 methods on beam-0000; spectrum-0000 has no optimal (not in optimal_families).
    assert_eq!(picked.len(), 2 * 8 - 1);
    picked
}

fn solve_json(scenes: &Path, row: &Row) -> String {
    let file = scenes.join(format!("{}.scene.json", row.scene));
    let o = Command::new(SOLVE)
        .arg(&file)
        .args(solve_args(row))
        .output()
        .expect("run solve");
    assert!(
        o.status.success(),
        "solve {} {:?} failed: {}",
        file.display(),
        solve_args(row),
        stderr(&o)
    );
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn solve_reproduces_sweep_rows_exactly() {
    let (gen, _, scenes) = generated_and_file_runs("solve_rows");
    for row in rows_for_solve(&gen) {
        let j = solve_json(&scenes, row);
        let what = format!("{} {} {:?}", row.scene, row.method, solve_args(row));
        let finite = |x: Option<f64>| x.filter(|v| v.is_finite());
        assert_eq!(
            top_level_number(&j, "max_penetration").map(f64::to_bits),
            row.max_penetration.map(f64::to_bits),
            "max_penetration: {what}"
        );
        assert_eq!(
            top_level_number(&j, "cond2_system").map(f64::to_bits),
            finite(row.cond2_system).map(f64::to_bits),
            "cond2_system: {what}"
        );
        assert_eq!(
            top_level_number(&j, "cond2_K").map(f64::to_bits),
            finite(row.cond2_k).map(f64::to_bits),
            "cond2_K: {what}"
        );
        assert_eq!(
            top_level_number(&j, "log10_det_ratio").map(f64::to_bits),
            finite(row.log10_det_ratio).map(f64::to_bits),
            "log10_det_ratio: {what}"
        );
        assert_eq!(
            top_level_number(&j, "iterations").map(|v| v as usize),
            row.iterations,
            "iterations: {what}"
        );
    }
}

/// `linear_solves` of a sweep row vs `solve --json` for the same scene, method and knob.
///
/// The sweep solves through `strategy::solve_prepared` with a per-scene `Prepared` (K factored
/// and u0 = K⁻¹q solved once), and work done inside `Prepared` is not counted in `Stats`; `solve`
/// counts the u0 solve. So every method that uses u0 (all but `augmented` here) reports one
/// solve fewer in rows.csv than `solve` does for the same computation.
#[test]
fn solve_and_sweep_count_the_same_linear_solves() {
    let (gen, _, scenes) = generated_and_file_runs("solve_counts");
    let mut mismatches = Vec::new();
    for row in rows_for_solve(&gen) {
        let j = solve_json(&scenes, row);
        let solve_count = top_level_number(&j, "linear_solves").map(|v| v as usize);
        if solve_count != row.linear_solves {
            mismatches.push(format!(
                "{} {}: sweep {:?}, solve {:?}",
                row.scene, row.method, row.linear_solves, solve_count
            ));
        }
    }
    assert!(
        mismatches.is_empty(),
        "linear_solves differ:\n{}",
        mismatches.join("\n")
    );
}

/// A dense K with N > 400 (beams of 140–150 elements: N ≈ 430) is written by `--write-scenes`
/// as a Matrix Market file (`scene::write_scene(.., 400)` in `sweep::run`) and reads back as
/// *sparse* storage, so the file run takes other numerical routes (sparse factorization,
/// `densified_symmetric_eigen`) and its rows are no longer those of the generated run.
#[test]
fn scenes_dir_reproduces_large_dense_scenes() {
    let d = tmp_dir("large_dense");
    let (gen, files, scenes) = (d.join("gen"), d.join("files"), d.join("scenes"));
    let cfg = write_toml(
        &d,
        "large",
        "families = [\"beam\"]\ncount = 1\nseed = 2011\n[generator]\nbeam_elements = [140, 150]\n",
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
    sweep_ok(
        &d,
        &with(&knobs, &["--scenes-dir", s(&scenes), "--out", s(&files)]),
    );
    let (g, f) = (rows_of(&gen), rows_of(&files));
    assert!(
        g[0].n > 400,
        "N = {} (want a dense K above the threshold)",
        g[0].n
    );
    assert_eq!(g.len(), f.len());
    let differing: Vec<String> = g
        .iter()
        .zip(&f)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| {
            format!(
                "{} {}: cond_route {:?} vs {:?}, max_penetration {:?} vs {:?}",
                a.scene, a.method, a.cond_route, b.cond_route, a.max_penetration, b.max_penetration
            )
        })
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {} rows differ when re-run from the written scene file:\n{}",
        differing.len(),
        g.len(),
        differing.join("\n")
    );
}

/// The elastic families (`hertz`, `flat-punch`): every constraint unilateral, so `barrier`
/// runs on them beside the penalties; it never penetrates, every rule solves, and the scenes
/// export like any other family's. The flat punch is asked for by its old name `patch`,
/// which still reads.
#[test]
fn elastic_families_run_every_rule_and_the_barrier_never_penetrates() {
    let d = tmp_dir("elastic");
    let out = d.join("out");
    let scenes = d.join("scenes");
    sweep_ok(
        &d,
        &[
            "--families",
            "hertz,patch",
            "--count",
            "2",
            "--methods",
            "constant,scaled,condensed,lagrange,barrier",
            "--no-figures",
            "--quiet",
            "--out",
            s(&out),
            "--write-scenes",
            s(&scenes),
        ],
    );
    let rows = rows_of(&out);
    assert!(
        rows.iter().any(|r| r.family == "hertz") && rows.iter().any(|r| r.family == "flat-punch")
    );
    for r in &rows {
        assert!(
            !r.warnings.contains("error"),
            "{} {}: {}",
            r.scene,
            r.method,
            r.warnings
        );
    }
    let barrier: Vec<&Row> = rows.iter().filter(|r| r.method == "barrier").collect();
    assert_eq!(barrier.len(), 4 * 3, "2 scenes × 2 families × 3 δ");
    for r in barrier {
        assert_eq!(r.max_penetration, Some(0.0), "{}", r.scene);
    }
    for name in [
        "hertz-0000",
        "hertz-0001",
        "flat-punch-0000",
        "flat-punch-0001",
    ] {
        assert!(
            scenes.join(format!("{name}.scene.json")).is_file(),
            "{name} not written"
        );
    }
}
