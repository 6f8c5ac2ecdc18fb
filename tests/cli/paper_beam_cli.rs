//! End-to-end test of the `paper_beam` binary: JSON output, data files, figures, and
//! `--render-only` regenerating the figures from the saved data.

use crate::common;
use std::path::{Path, PathBuf};
use std::process::Command;

const FIGURES: [&str; 3] = [
    "fig3_deflection_free",
    "fig4_deflection_contact",
    "cond_vs_eps",
];

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_paper_beam"))
        .args(args)
        .output()
        .expect("paper_beam runs")
}

fn figure_files(dir: &Path) -> Vec<PathBuf> {
    FIGURES
        .iter()
        .flat_map(|f| ["png", "svg"].map(|ext| dir.join(format!("{f}.{ext}"))))
        .collect()
}

#[test]
fn json_marks_exactly_the_misprints_and_render_only_regenerates_figures() {
    let tmp = common::tmp_dir("paper-beam-main");
    let dir = tmp.path();
    let out = dir.to_str().unwrap();
    let o = run(&["--out", out, "--json"]);
    assert!(
        o.status.success(),
        "exit {:?}, stderr: {}",
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");

    // The same document is saved, plus the CSVs.
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("paper_beam.json")).unwrap())
            .unwrap();
    assert_eq!(v, saved);
    for f in ["deflection.csv", "cond_vs_eps.csv"] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(text.lines().count() > 10, "{f} is too short");
    }
    let cond_csv = std::fs::read_to_string(dir.join("cond_vs_eps.csv")).unwrap();
    assert_eq!(
        cond_csv
            .lines()
            .filter(|l| l.starts_with("uniform,"))
            .count(),
        100
    );

    // Every printed number of Eq. 31–37 is compared; exactly the two misprints disagree.
    let rows = v["paper_comparison"].as_array().expect("paper_comparison");
    assert!(rows.len() >= 29, "only {} rows", rows.len());
    for eq in ["Eq. 31", "Eq. 33", "Eq. 35", "Eq. 36", "Eq. 37"] {
        assert!(rows.iter().any(|r| r["equation"] == eq), "no row for {eq}");
    }
    let mut differing: Vec<&str> = Vec::new();
    for r in rows {
        let id = r["id"].as_str().unwrap();
        match r["agree"].as_bool() {
            Some(true) => {}
            Some(false) => differing.push(id),
            None => panic!("row {id} has no agreement verdict"),
        }
        assert!(r["ours"].as_f64().is_some(), "row {id} has no value");
    }
    differing.sort_unstable();
    assert_eq!(differing, ["eq33.u7", "eq37.g3"]);
    let row = |id: &str| rows.iter().find(|r| r["id"] == id).unwrap();
    assert!((row("eq33.u7")["ours"].as_f64().unwrap() + 50.0 * 30.0 / 2100.0).abs() < 1e-9);
    assert!(row("eq37.g3")["ours"].as_f64().unwrap() < 0.0);
    assert!(!row("eq33.u7")["note"].as_str().unwrap().is_empty());
    assert!(!row("eq37.g3")["note"].as_str().unwrap().is_empty());

    // Condensed: the methods.md numbers and the exact |g| = δ.
    let crows = v["condensed_comparison"].as_array().expect("condensed");
    for r in crows.iter().filter(|r| !r["agree"].is_null()) {
        assert_eq!(r["agree"], true, "condensed row {} disagrees", r["id"]);
    }
    assert!(crows.iter().any(|r| r["id"] == "condensed.cond"));

    // Strategy lines, provenance, notes.
    let names: Vec<&str> = v["strategies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    for n in common::METHODS {
        assert!(names.contains(&n), "no strategy line for {n}");
    }
    assert_eq!(v["experiment"], "paper_beam");
    assert!(v["git_commit"].as_str().is_some());
    assert!(v["command"].as_str().unwrap().contains("paper_beam"));
    assert_eq!(
        v["crate_versions"]["penalty-lab"],
        env!("CARGO_PKG_VERSION")
    );
    assert_eq!(v["delta"], 0.1);
    assert!(v["notes"].as_array().unwrap().len() >= 5);

    // Figures exist; --render-only regenerates them from the saved data.
    let figs = figure_files(dir);
    for f in &figs {
        let len = std::fs::metadata(f)
            .unwrap_or_else(|_| panic!("{} missing", f.display()))
            .len();
        assert!(len > 1000, "{} is too small", f.display());
    }
    for f in &figs {
        std::fs::remove_file(f).unwrap();
    }
    let o = run(&["--out", out, "--render-only"]);
    assert!(
        o.status.success(),
        "render-only failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    for f in &figs {
        assert!(
            f.exists(),
            "--render-only did not regenerate {}",
            f.display()
        );
    }
    // The table mode prints the comparison.
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("4.597e11") && stdout.contains("NO"));
}

#[test]
fn render_only_without_saved_data_fails_cleanly() {
    let tmp = common::tmp_dir("paper-beam-empty");
    let o = run(&["--out", tmp.path().to_str().unwrap(), "--render-only"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("paper_beam.json"), "stderr: {err}");
}
