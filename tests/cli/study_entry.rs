//! The shared study entry (`study::main`): every study binary takes the same
//! `--out`, `--render-only`, `--json`, `--quiet` and `--no-figures`, refuses `--resume` where
//! it keeps no checkpoints, and `--render-only --json` prints the very record the run printed;
//! `solve`, which keeps no record, refuses `--out` and `--render-only` with one line.

use crate::common;
use std::path::Path;
use std::process::{Command, Output};

/// The binaries on the shared entry, each with a run small enough for a test; the last
/// field says whether it keeps checkpoints (`--resume`).
type Entry = (&'static str, &'static str, Vec<&'static str>, bool);

fn binaries() -> Vec<Entry> {
    vec![
        (
            "cond_accuracy",
            env!("CARGO_BIN_EXE_cond_accuracy"),
            vec![
                "--per-family",
                "1",
                "--factors",
                "0",
                "--scenes",
                "",
                "--repeats",
                "1",
            ],
            false,
        ),
        (
            "cond_cost",
            env!("CARGO_BIN_EXE_cond_cost"),
            vec!["--sides", "4", "--elements", "4", "--repeats", "1"],
            false,
        ),
        (
            "contact_bench",
            env!("CARGO_BIN_EXE_contact_bench"),
            vec![
                "--cases",
                "flat-punch",
                "--meshes",
                "0.2",
                "--methods",
                "lagrange",
            ],
            true,
        ),
        (
            "penalty_scaling",
            env!("CARGO_BIN_EXE_penalty_scaling"),
            vec![
                "--discretizations",
                "mortar",
                "--levels",
                "2",
                "--eps-rel",
                "1",
                "--delta-methods",
                "condensed",
            ],
            false,
        ),
        (
            "sweep",
            env!("CARGO_BIN_EXE_sweep"),
            vec![
                "--families",
                "beam",
                "--count",
                "1",
                "--methods",
                "constant",
                "--eps",
                "1e2:1e4:2",
            ],
            true,
        ),
        (
            "paper_beam",
            env!("CARGO_BIN_EXE_paper_beam"),
            vec![],
            false,
        ),
        (
            "deep_drawing",
            env!("CARGO_BIN_EXE_deep_drawing"),
            vec!["--steps", "4", "--elements", "12", "--travel", "0.04"],
            false,
        ),
        (
            "stretch_test",
            env!("CARGO_BIN_EXE_stretch_test"),
            vec!["--steps", "4", "--elements", "12", "--travel", "0.04"],
            false,
        ),
        (
            "engine_scale",
            env!("CARGO_BIN_EXE_engine_scale"),
            vec!["--sizes", "100", "--methods", "lagrange", "--no-cond"],
            false,
        ),
        (
            "runtime_vs_error",
            env!("CARGO_BIN_EXE_runtime_vs_error"),
            vec![
                "--smoke",
                "--sizes",
                "100",
                "--families",
                "beam",
                "--methods",
                "lagrange,constant",
            ],
            false,
        ),
        (
            "solver_cost",
            env!("CARGO_BIN_EXE_solver_cost"),
            vec![
                "--families",
                "beam",
                "--levels",
                "2",
                "--methods",
                "constant",
            ],
            true,
        ),
        (
            "stress",
            env!("CARGO_BIN_EXE_stress"),
            vec!["--families", "none", "--eps", "1:1e4:3"],
            false,
        ),
    ]
}

/// The image files under `dir`, at any depth.
fn images(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(images(&p));
        } else if p.extension().is_some_and(|x| x == "png" || x == "svg") {
            out.push(p);
        }
    }
    out
}

fn run(bin: &str, args: &[&str], out: &Path) -> Output {
    Command::new(bin)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("binary runs")
}

#[test]
fn every_study_binary_shares_the_entry_flags() {
    for (name, bin, small, resumable) in binaries() {
        let help = Command::new(bin).arg("--help").output().unwrap();
        let help = String::from_utf8_lossy(&help.stdout);
        for flag in ["--out", "--render-only", "--json", "--quiet"] {
            assert!(help.contains(flag), "{name} --help lacks {flag}");
        }
        // `--out`'s entry: its line and, in clap's long format, the lines below it.
        let entry: String = help
            .lines()
            .skip_while(|l| !l.trim_start().starts_with("--out"))
            .take_while(|l| !l.trim_start().starts_with("--render-only"))
            .collect();
        assert!(
            entry.contains("[default: "),
            "{name}: --out default not shown"
        );
        assert_eq!(help.contains("--resume"), resumable, "{name} --resume");

        let dir = tempfile::tempdir().unwrap();
        let mut args = small.clone();
        args.extend(["--quiet", "--json"]);
        let first = run(bin, &args, dir.path());
        assert!(
            first.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&first.stderr)
        );
        assert!(first.stderr.is_empty(), "{name} --quiet wrote to stderr");
        let record: serde_json::Value =
            serde_json::from_slice(&first.stdout).unwrap_or_else(|e| panic!("{name} --json: {e}"));
        let again = run(bin, &["--render-only", "--json", "--quiet"], dir.path());
        assert!(again.status.success(), "{name}");
        let reread: serde_json::Value = serde_json::from_slice(&again.stdout).unwrap();
        assert_eq!(
            record, reread,
            "{name}: --render-only --json differs from the run's"
        );
        let report = run(bin, &["--render-only"], dir.path());
        assert!(
            report.status.success() && !report.stdout.is_empty(),
            "{name}"
        );
        assert!(serde_json::from_slice::<serde_json::Value>(&report.stdout).is_err());

        // The figures: drawn by the run, skipped with --no-figures, redrawn by --render-only.
        let drawn = images(dir.path());
        assert!(!drawn.is_empty(), "{name}: no figures");
        for f in &drawn {
            std::fs::remove_file(f).unwrap();
        }
        let none = run(
            bin,
            &["--render-only", "--no-figures", "--quiet"],
            dir.path(),
        );
        assert!(none.status.success(), "{name}");
        assert!(images(dir.path()).is_empty(), "{name}: --no-figures drew");
        let redrawn = run(bin, &["--render-only", "--quiet"], dir.path());
        assert!(redrawn.status.success(), "{name}");
        assert_eq!(images(dir.path()).len(), drawn.len(), "{name}: redrawn");

        if resumable {
            continue;
        }
        let resume = run(bin, &["--resume"], dir.path());
        assert_eq!(resume.status.code(), Some(2), "{name} --resume");
        let err = String::from_utf8_lossy(&resume.stderr);
        assert!(
            err.contains("keeps no checkpoints") && err.lines().count() == 1,
            "{name}: {err}"
        );
    }
}

/// `solve` runs through the same entry but keeps no record: `--json` and `--quiet` work,
/// `--out`, `--render-only` and `--resume` are refused with one line and status 2.
#[test]
fn solve_shares_the_entry_and_refuses_a_record() {
    let bin = env!("CARGO_BIN_EXE_solve");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper_beam.scene.json");
    let base = [scene, "--method", "lagrange", "--no-metrics"];
    let o = common::run_ok(Command::new(bin).args(base).args(["--json", "--quiet"]));
    assert!(o.stderr.is_empty());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["method"], "lagrange");
    let tmp = common::tmp_dir("solve-entry");
    let never = tmp.path().join("never-written");
    let never_arg = never.to_str().expect("utf-8 temp path");
    for extra in [
        vec!["--out", never_arg],
        vec!["--render-only"],
        vec!["--resume"],
    ] {
        let o = Command::new(bin).args(base).args(&extra).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{extra:?}: {err}");
        assert!(o.stdout.is_empty(), "{extra:?}");
    }
    assert!(!never.exists());
}

/// Every study binary refuses a command line clap cannot parse (an unknown flag, a value of
/// the wrong type) with one line on stderr and status 2, as any other bad input; and
/// `--render-only` on a folder with no saved record says so and how to get one.
#[test]
fn command_line_errors_and_a_missing_record_are_one_line() {
    let mut all = binaries();
    all.push(("solve", env!("CARGO_BIN_EXE_solve"), vec![], false));
    for (name, bin, _, _) in all {
        for args in [&["--no-such-flag"][..], &["--quiet=maybe"][..]] {
            let o = Command::new(bin).args(args).output().unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{name} {args:?}: {err}");
            assert!(
                err.starts_with("error:") && err.trim_end().lines().count() == 1,
                "{name} {args:?}: not one line:\n{err}"
            );
        }
        if name == "solve" {
            continue;
        }
        let empty = tempfile::tempdir().unwrap();
        let o = run(bin, &["--render-only", "--quiet"], empty.path());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains("run without --render-only first") && err.trim_end().lines().count() == 1,
            "{name}: {err}"
        );
    }
}

/// `--out` naming a file (not a folder) is refused with one line before anything runs.
#[test]
fn out_naming_a_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "keep me").unwrap();
    for (name, bin, small, _) in binaries() {
        let o = run(bin, &small, &file);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains("--out names a file") && err.trim_end().lines().count() == 1,
            "{name}: {err}"
        );
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me", "{name}");
    }
}
