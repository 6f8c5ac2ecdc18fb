//! `solve` on the scene files a sweep wrote reproduces the sweep's rows bit for bit and
//! counts the same linear solves.

use crate::common;
use crate::sweep_support::{generated_and_file_runs, SOLVE};
use penalty_lab::study::sweep::rows::Row;
use std::path::Path;
use std::process::Command;

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

/// `solve --json` for a row, on `threads` threads (`RAYON_NUM_THREADS`; None: the default).
fn solve_json(scenes: &Path, row: &Row, threads: Option<&str>) -> String {
    let file = scenes.join(format!("{}.scene.json", row.scene));
    let mut cmd = Command::new(SOLVE);
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    let o = common::run_ok(cmd.arg(&file).args(solve_args(row)));
    String::from_utf8(o.stdout).unwrap()
}

/// Bit for bit, with `solve` on another number of threads than the sweep (1 and 3 against the
/// machine's): `optimal`'s dense kernels once split over faer's pool and differed in the 8th
/// digit.
#[test]
fn solve_reproduces_sweep_rows_exactly() {
    let (_tmp, gen, _, scenes) = generated_and_file_runs("solve_rows");
    for (i, row) in rows_for_solve(&gen).into_iter().enumerate() {
        let j = solve_json(&scenes, row, Some(["1", "3"][i % 2]));
        let what = format!("{} {} {:?}", row.scene, row.method, solve_args(row));
        let finite = |x: Option<f64>| x.filter(|v| v.is_finite());
        for (key, want) in [
            ("max_penetration", row.max_penetration),
            ("cond2_system", finite(row.cond2_system)),
            ("cond2_K", finite(row.cond2_k)),
            ("log10_det_ratio", finite(row.log10_det_ratio)),
        ] {
            assert_eq!(
                top_level_number(&j, key).map(f64::to_bits),
                want.map(f64::to_bits),
                "{key}: {what}"
            );
        }
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
    let (_tmp, gen, _, scenes) = generated_and_file_runs("solve_counts");
    let mut mismatches = Vec::new();
    for row in rows_for_solve(&gen) {
        let j = solve_json(&scenes, row, None);
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

/// With `--cond-tol`, `solve` still reproduces a sweep row: the sweep's analysis of K (whose
/// Ritz vectors start every row's) runs at the tolerance asked, as `solve`'s does. A membrane
/// (the sparse route) at ε over eleven decades, the top start from the active block included.
#[test]
fn solve_reproduces_sweep_rows_at_a_loose_cond_tol() {
    use crate::sweep_support::{sweep_writing_scenes, work_dir};
    let (_tmp, d) = work_dir("solve_rows_tol");
    let (rows, scenes) = sweep_writing_scenes(
        &d,
        &[
            "--families",
            "membrane",
            "--count",
            "1",
            "--methods",
            "constant",
            "--eps",
            "1e-1:1e10:3",
            "--cond-tol",
            "1e-6",
        ],
    );
    let constant: Vec<&Row> = rows.iter().filter(|r| r.method == "constant").collect();
    assert_eq!(constant.len(), 3);
    for row in constant {
        let mut args = solve_args(row);
        args.extend(["--cond-tol".into(), "1e-6".into()]);
        let file = scenes.join(format!("{}.scene.json", row.scene));
        let o = common::run_ok(Command::new(SOLVE).arg(&file).args(&args));
        let j = String::from_utf8(o.stdout).unwrap();
        for (key, want) in [("cond2_system", row.cond2_system), ("cond2_K", row.cond2_k)] {
            assert_eq!(
                top_level_number(&j, key).map(f64::to_bits),
                want.map(f64::to_bits),
                "{key}: ε {:?}",
                row.eps
            );
        }
    }
}
