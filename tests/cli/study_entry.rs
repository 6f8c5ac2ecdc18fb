//! The shared study entry (`study::main`, issue 46): every binary built on it takes the same
//! `--out`, `--render-only`, `--json` and `--quiet`, refuses `--resume` where it keeps no
//! checkpoints, and `--render-only --json` prints the very record the run printed.

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
    ]
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
