//! `cond_accuracy` end to end on a small panel: every route measured on every matrix, the
//! certified route within the accuracy contract against the double-double reference, the data
//! and figure written, `--render-only` re-rendering, and bad input rejected with exit code 2.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cond_accuracy"))
}

#[test]
fn small_run_measures_every_route_and_the_certified_one_meets_the_contract() {
    let dir = std::env::temp_dir().join(format!("cond_accuracy_cli_{}", std::process::id()));
    let out = bin()
        .args(["--per-family", "1", "--factors", "0,1e9", "--scenes", ""])
        .args(["--repeats", "1", "--quiet", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
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
    for f in [
        "cond_accuracy.json",
        "cond_accuracy.csv",
        "cond_accuracy.png",
        "cond_accuracy.svg",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    std::fs::remove_file(dir.join("cond_accuracy.png")).unwrap();
    let st = bin()
        .args(["--render-only", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(st.status.success());
    assert!(dir.join("cond_accuracy.png").is_file());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_exits_2() {
    for args in [
        vec!["--repeats", "0", "--scenes", ""],
        vec!["--factors", "-1", "--scenes", ""],
        vec!["--scenes", "/nonexistent/x.scene.json"],
    ] {
        let out = bin()
            .args(&args)
            .args(["--quiet", "--out", "/tmp/cond_accuracy_never"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}
