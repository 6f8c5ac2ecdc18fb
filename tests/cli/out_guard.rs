//! Outputs are never mixed (`study::out_guard`): the data-loss sequence of a newcomer —
//! `sweep --families beam --out X`, then `sweep --families membrane --out X` — is refused with
//! one line naming `--resume` and `--force` and leaves the first run intact; the same command
//! runs twice; `--force` replaces the run whole; `solve --write-system` never overwrites.

use crate::common;
use crate::sweep_support::{SOLVE, SWEEP};
use std::process::Command;

fn sweep(out: &std::path::Path, family: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "--families",
        family,
        "--count",
        "1",
        "--methods",
        "constant",
        "--eps",
        "1e2:1e4:2",
        "--no-figures",
        "--quiet",
        "--out",
    ];
    args.push(out.to_str().unwrap());
    args.extend_from_slice(extra);
    Command::new(SWEEP).args(&args).output().expect("run sweep")
}

#[test]
fn another_run_into_the_same_out_is_refused_and_the_first_kept() {
    let tmp = common::tmp_dir("out-guard");
    let out = tmp.path().join("X");
    assert!(sweep(&out, "beam", &[]).status.success());
    // The same command again runs in place.
    let again = sweep(&out, "beam", &[]);
    assert!(again.status.success(), "{}", common::stderr(&again));
    let rows = std::fs::read_to_string(out.join("rows.csv")).unwrap();
    // Another configuration: refused with one line, the first run untouched.
    let other = sweep(&out, "membrane", &[]);
    assert_eq!(other.status.code(), Some(2), "{}", common::stderr(&other));
    let err = common::stderr(&other);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("--resume") && err.contains("--force"), "{err}");
    assert_eq!(std::fs::read_to_string(out.join("rows.csv")).unwrap(), rows);
    // --force replaces it whole.
    let forced = sweep(&out, "membrane", &["--force"]);
    assert!(forced.status.success(), "{}", common::stderr(&forced));
    let now = std::fs::read_to_string(out.join("rows.csv")).unwrap();
    assert!(now.contains("membrane") && !now.contains("beam"), "{now}");
}

#[test]
fn write_system_refuses_existing_files() {
    let tmp = common::tmp_dir("out-guard-system");
    let scene = tmp.path().join("s.scene.json");
    std::fs::write(
        &scene,
        r#"{"name": "s", "stiffness": {"dense": [[2, -1], [-1, 2]]}, "load": [0, -1],
            "constraints": [{"dof": 1, "limit": -0.1, "kind": "lower"}]}"#,
    )
    .unwrap();
    let dir = tmp.path().join("sys");
    let run = |extra: &[&str]| {
        let mut args = vec![
            scene.to_str().unwrap(),
            "--method",
            "lagrange",
            "--quiet",
            "--write-system",
            dir.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        Command::new(SOLVE).args(&args).output().expect("run solve")
    };
    assert!(run(&[]).status.success());
    let again = run(&[]);
    assert_eq!(again.status.code(), Some(2));
    assert!(
        common::stderr(&again).contains("A.mtx"),
        "{}",
        common::stderr(&again)
    );
    assert!(dir.join("x_hat.mtx").exists());
    // --force replaces the three files as a whole: no earlier x_hat.mtx beside a new A.
    assert!(run(&["--force", "--no-solver-metrics"]).status.success());
    assert!(dir.join("A.mtx").exists() && !dir.join("x_hat.mtx").exists());
}
