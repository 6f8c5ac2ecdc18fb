//! `cond_accuracy` end to end on a small panel: every route measured on every matrix, the
//! certified route within the accuracy contract against the double-double reference, the data
//! and figure written, `--render-only` re-rendering, and bad input rejected with exit code 2.

use crate::common;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cond_accuracy"))
}

#[test]
fn small_run_measures_every_route_and_the_certified_one_meets_the_contract() {
    let tmp = common::tmp_dir("cond-accuracy");
    let dir = tmp.path().join("out");
    common::run_ok(
        bin()
            .args(["--per-family", "1", "--factors", "0,1e9", "--scenes", ""])
            .args(["--repeats", "1", "--quiet", "--out"])
            .arg(&dir),
    );
    let text = std::fs::read_to_string(dir.join("cond_accuracy.json")).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = doc["rows"].as_array().unwrap();
    // 3 families × 1 scene × 2 factors × 5 routes.
    assert_eq!(rows.len(), 30);
    for r in rows.iter().filter(|r| r["route"] == "certified") {
        let (err, contract) = (
            r["rel_error"].as_f64().unwrap(),
            r["contract"].as_f64().unwrap(),
        );
        assert!(err <= contract, "{r}");
        assert!(r["bounds_width"].as_f64().unwrap() >= 0.0, "{r}");
    }
    common::assert_files(
        &dir,
        &[
            "cond_accuracy.json",
            "cond_accuracy.csv",
            "cond_accuracy.png",
            "cond_accuracy.svg",
        ],
    );
    std::fs::remove_file(dir.join("cond_accuracy.png")).unwrap();
    common::run_ok(bin().args(["--render-only", "--out"]).arg(&dir));
    assert!(dir.join("cond_accuracy.png").is_file());
}

#[test]
fn bad_input_exits_2() {
    let tmp = common::tmp_dir("cond-accuracy-bad");
    let never = tmp.path().join("never");
    for args in [
        vec!["--repeats", "0", "--scenes", ""],
        vec!["--factors", "-1", "--scenes", ""],
        vec!["--scenes", "/nonexistent/x.scene.json"],
    ] {
        let out = bin()
            .args(&args)
            .args(["--quiet", "--out"])
            .arg(&never)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}
