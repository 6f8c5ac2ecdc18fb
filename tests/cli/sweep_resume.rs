//! Kill and resume: a `sweep` killed mid-run resumes to the uninterrupted rows, refuses a
//! resume with another config or shard, and repairs a torn last line.

use crate::sweep_support::{
    assert_well_formed, rows_of, s, stderr, sweep_in, sweep_ok, with, work_dir, SWEEP,
};
use penalty_lab::study::sweep::rows::{self, Row};
use penalty_lab::study::sweep::SweepConfig;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

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
    let (_tmp, d) = work_dir("resume");
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
    // The order file pairs each chunk of rows.csv with its scene (rows land as scenes
    // complete).
    for f in [
        "rows.csv",
        "manifest.json",
        "penalty-lab-run.json",
        "scenes_done.csv",
    ] {
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
    // Every whole chunk on disk is kept, but one whose index the kill cut off (the index is
    // written right after its rows).
    let chunks = on_disk / cfg.rows_per_scene();
    assert!(
        resumed == chunks || resumed + 1 == chunks,
        "{resumed} of {chunks}: {}",
        stderr(&o)
    );
    assert!(
        !out.join("scenes_done.csv").exists(),
        "order file left behind"
    );
    assert_eq!(
        m["rows_written"].as_u64().unwrap() as usize,
        expected - resumed * cfg.rows_per_scene()
    );
    // The rows the manifest says rows.csv holds (what the report prints) are the file's.
    let in_file = rows::tally_rows(&out.join("rows.csv")).unwrap().rows();
    assert_eq!(in_file, expected);
    assert_eq!(m["rows_in_file"].as_u64().unwrap() as usize, in_file);
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(
        report.contains(&format!(" {in_file} in rows.csv")),
        "{report}"
    );
    // Resuming a complete run changes nothing.
    sweep_ok(&d, &with(&args, &["--resume"]));
    assert_eq!(rows_of(&out), reference);

    assert_torn_write_repaired(
        &d, &cfg_path, &torn, &full, on_disk, good, expected, &reference,
    );
}

/// Ctrl-C in the middle of a sweep: exit status 130 and one line naming the folder and the
/// command that finishes the run (the same command with `--resume`), which then completes it
/// to the uninterrupted rows.
#[cfg(unix)]
#[test]
fn ctrl_c_names_the_command_that_finishes_the_run() {
    let (_tmp, d) = work_dir("ctrl-c");
    let mut count = 24;
    loop {
        let (cfg_path, cfg) = write_big_config(&d, count);
        let out = d.join(format!("int{count}"));
        let args = [
            "--config",
            s(&cfg_path),
            "--threads",
            "2",
            "--no-figures",
            "--quiet",
            "--out",
            s(&out),
        ];
        let child = Command::new(SWEEP)
            .args(args)
            .current_dir(&d)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn sweep");
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(20));
            let n = std::fs::read_to_string(out.join("rows.csv"))
                .map(|t| t.lines().count())
                .unwrap_or(0);
            if n > cfg.rows_per_scene() {
                break;
            }
        }
        let sent = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .expect("kill -INT");
        let o = child.wait_with_output().expect("wait");
        if !sent.success() || o.status.code() == Some(0) {
            // Finished before the signal: a longer run.
            assert!(
                count < 400,
                "cannot interrupt the sweep with {count} scenes"
            );
            count *= 2;
            continue;
        }
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "{err}");
        let line = err.trim().lines().last().unwrap_or_default();
        assert!(
            line.starts_with("interrupted: what finished is kept in")
                && line.contains(s(&out))
                && line.ends_with(&format!("--out {} --resume", s(&out))),
            "{err}"
        );
        sweep_ok(&d, &with(&args, &["--resume"]));
        let full = d.join(format!("full{count}"));
        sweep_ok(
            &d,
            &["--config", s(&cfg_path), "--no-figures", "--out", s(&full)],
        );
        assert_eq!(rows_of(&out), rows_of(&full));
        return;
    }
}
