//! `contact_bench` end to end: a small suite writes rows, summary and figures; `--render-only`
//! redraws them; bad options exit 2 with one line naming the problem.

use crate::common::{self, assert_render_only};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_contact_bench"))
}

#[test]
fn small_suite_writes_rows_summary_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let o = common::run_ok(
        bin()
            .args([
                "--cases",
                "hertz-axi,flat-punch",
                "--meshes",
                "0.2",
                "--quiet",
                "--json",
            ])
            .args(["--methods", "lagrange,constant,condensed", "--out"])
            .arg(dir.path()),
    );
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // lagrange, 7 ε values, 4 δ values per case, then two values between the grid values
    // where a rule crosses the leaderboard's margin (refinement).
    let rows = s["rows"].as_array().unwrap();
    let grid = |r: &&serde_json::Value| {
        let k = r["knob_rel"].as_f64();
        k.is_none_or(|k| (k.log10() - k.log10().round()).abs() < 1e-9)
    };
    assert_eq!(rows.iter().filter(grid).count(), 2 * 12);
    assert_eq!((rows.len() - 2 * 12) % 2, 0, "refined values come in pairs");
    assert!(s["leaderboard"].as_array().unwrap().len() >= 4);
    let csv = std::fs::read_to_string(dir.path().join("rows.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "case",
        "method",
        "knob",
        "h",
        "n_dofs",
        "load",
        "radius",
        "young",
        "poisson",
        "a_exact",
        "a_num",
        "p0_exact",
        "p0_num",
        "p_err_rel",
        "err_penalty",
        "err_discretization",
        "err_domain",
        "max_penetration",
        "cond2_system",
        "converged",
        "kappa_rule",
        "seconds",
    ] {
        assert!(header.split(',').any(|c| c == col), "column {col} missing");
    }
    assert_render_only(
        env!("CARGO_BIN_EXE_contact_bench"),
        dir.path(),
        "figures/leaderboard_hertz-axi.png",
        "summary.json",
        &[],
    );
}

/// The knob grids are the user's: `--eps-rel`, `--factors`, `--deltas-rel` replace the
/// defaults row for row, and `--optimal-max-n` moves where `optimal` is skipped.
#[test]
fn knob_grids_and_the_optimal_limit_are_options() {
    let dir = tempfile::tempdir().unwrap();
    let o = common::run_ok(
        bin()
            .args(["--cases", "patch", "--meshes", "0.2", "--quiet", "--json"])
            .args(["--methods", "constant,scaled,condensed,optimal"])
            .args([
                "--eps-rel",
                "1,10",
                "--factors",
                "3",
                "--deltas-rel",
                "1e-3",
            ])
            .args(["--optimal-max-n", "59", "--out"])
            .arg(dir.path()),
    );
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = s["rows"].as_array().unwrap();
    let knobs = |m: &str| -> Vec<f64> {
        rows.iter()
            .filter(|r| r["method"] == m)
            .map(|r| r["knob_rel"].as_f64().unwrap())
            .collect()
    };
    // `patch`, the flat punch's former name, still reads.
    assert!(rows.iter().all(|r| r["case"] == "flat-punch"));
    assert_eq!(knobs("constant"), [1.0, 10.0]);
    assert_eq!(knobs("scaled"), [3.0]);
    assert_eq!(knobs("condensed"), [1e-3]);
    // The 60-DOF mesh is above 59: optimal's row says it was skipped.
    let opt: Vec<_> = rows.iter().filter(|r| r["method"] == "optimal").collect();
    assert_eq!(opt.len(), 1);
    let err = opt[0]["error"].as_str().unwrap();
    assert!(err.contains("optimal_max_n = 59"), "{err}");
}

#[test]
fn bad_options_exit_2_with_one_line() {
    for args in [
        &["--cases", "hertz-3d"][..],
        &["--meshes", "0"],
        &["--meshes", "nan"],
        &["--methods", "nonsense"],
        &["--cond-tol", "2"],
        &["--eps-rel", "-1"],
        &["--factors", "inf"],
        &["--deltas-rel", "0"],
        &["--optimal-max-n", "20001"],
        &["--block-over-a", "1"],
        &["--block-over-a", "nan"],
        // A case's own flag with none of its cases (it was ignored).
        &["--cases", "flat-punch", "--block-over-a", "20"],
        &["--cases", "hertz-plane,inclined-30", "--mesh-ratio", "3:2"],
        // --vtk writes single-body cases only.
        &[
            "--cases",
            "inclined-30",
            "--vtk",
            "/tmp/penalty-lab-vtk-refused",
        ],
    ] {
        let o = bin().args(args).arg("--quiet").output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.trim().is_empty(), "{args:?}: no message");
        assert!(o.stdout.is_empty(), "{args:?}: wrote to stdout");
        if args.len() == 4 {
            let flag = args[2];
            assert!(
                err.contains(&format!("{flag} needs one of the cases")),
                "{args:?}: {err}"
            );
        }
    }
}

/// `patch-two-body-nts-2` (two-pass node-to-segment, on request only) runs through the binary:
/// its rows say `nts-2`; Lagrange's row carries its refusal of the dependent rows (singular)
/// and the run goes on; the penalties' rows have a finite `p_err_rel` against the exact
/// uniform pressure and no `err_penalty` or `err_discretization` (no Lagrange reference); the
/// report says so, and the pressure figure is drawn (no leaderboard figure: nothing to draw).
#[test]
fn two_pass_patch_case_runs_without_a_lagrange_reference() {
    let dir = tempfile::tempdir().unwrap();
    let o = bin()
        .args([
            "--cases",
            "patch-two-body-nts-2",
            "--meshes",
            "0.2",
            "--quiet",
        ])
        .args(["--methods", "lagrange,constant,scaled", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    // Lagrange failed on every mesh it ran on: said on stderr, exit status 4, the rows, the
    // report and the figures written all the same.
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("lagrange (1 of 1 rows"), "{err}");
    let read: Vec<std::collections::HashMap<String, String>> =
        csv::Reader::from_path(dir.path().join("rows.csv"))
            .unwrap()
            .deserialize()
            .map(|r| r.unwrap())
            .collect();
    // lagrange, 7 ε values, 5 factors (no refinement: nothing is admissible without Lagrange).
    assert_eq!(read.len(), 1 + 7 + 5);
    for r in &read {
        let what = format!("{} {}", r["method"], r["knob_rel"]);
        assert_eq!(r["case"], "patch-two-body-nts-2", "{what}");
        assert_eq!(r["discretization"], "nts-2", "{what}");
        for col in ["err_penalty", "err_discretization"] {
            assert!(
                r[col].is_empty() || r[col] == "NaN",
                "{what}: {col} = {}",
                r[col]
            );
        }
        if r["method"] == "lagrange" {
            assert!(r["error"].contains("singular"), "{what}: {}", r["error"]);
        } else {
            assert!(r["error"].is_empty(), "{what}: {}", r["error"]);
            let e: f64 = r["p_err_rel"].parse().unwrap();
            assert!(e.is_finite() && e > 0.0 && e < 0.2, "{what}: p_err_rel {e}");
        }
    }
    let report = String::from_utf8_lossy(&o.stdout);
    assert!(report.contains("Lagrange failed"), "{report}");
    assert!(report.contains("no Lagrange reference"), "{report}");
    // The rows per method: lagrange 0 solved, 1 failed; the penalties solved every knob.
    let line = |m: &str| {
        report
            .lines()
            .find(|l| l.starts_with(m) && l.split_whitespace().count() >= 4)
            .map(|l| l.split_whitespace().take(4).collect::<Vec<_>>())
    };
    assert_eq!(
        line("lagrange "),
        Some(vec!["lagrange", "0", "1", "0"]),
        "{report}"
    );
    assert_eq!(
        line("constant "),
        Some(vec!["constant", "7", "0", "0"]),
        "{report}"
    );
    let figures = dir.path().join("figures");
    assert!(figures.join("pressure_patch-two-body-nts-2.png").is_file());
    assert!(!figures
        .join("leaderboard_patch-two-body-nts-2.png")
        .exists());
}

/// The barrier's κ study: `kappa.csv` holds fixed-κ rows spanning both
/// rules' clamps and one row per rule and d̂; the benchmark's own barrier rows use the `ipc`
/// rule (the scene carries its surface); the figure is drawn.
#[test]
fn barrier_rows_name_their_kappa_rule_and_the_kappa_study_is_written() {
    let dir = tempfile::tempdir().unwrap();
    common::run_ok(
        bin()
            .args(["--cases", "hertz-plane", "--meshes", "0.2", "--quiet"])
            .args([
                "--methods",
                "lagrange,barrier",
                "--deltas-rel",
                "1e-3",
                "--out",
            ])
            .arg(dir.path()),
    );
    let read = |f: &str| -> Vec<std::collections::HashMap<String, String>> {
        csv::Reader::from_path(dir.path().join(f))
            .unwrap()
            .deserialize()
            .map(|r| r.unwrap())
            .collect()
    };
    for r in read("rows.csv").iter().filter(|r| r["method"] == "barrier") {
        assert_eq!(r["kappa_rule"], "ipc");
    }
    let kappa = read("kappa.csv");
    for dhat in ["0.001", "0.0001"] {
        let at = |rule: &str| -> Vec<f64> {
            kappa
                .iter()
                .filter(|r| r["knob_rel"] == dhat && r["kappa_rule"] == rule)
                .map(|r| r["kappa_final"].parse().unwrap())
                .collect()
        };
        let fixed = at("fixed");
        let (ipc, balanced) = (at("ipc"), at("balanced"));
        assert_eq!((ipc.len(), balanced.len()), (1, 1), "d̂ = {dhat}");
        let lo = fixed.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = fixed.iter().copied().fold(0.0, f64::max);
        assert!(fixed.len() >= 10, "d̂ = {dhat}: {fixed:?}");
        assert!(
            lo <= ipc[0] && balanced[0] <= hi,
            "{lo} {ipc:?} {balanced:?} {hi}"
        );
    }
    assert!(dir.path().join("figures/kappa_sensitivity.png").is_file());
}

/// Reads rows.csv of `dir` as (header, rows), each row its fields.
fn csv_rows(dir: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(dir.join("rows.csv")).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(String::from).collect::<Vec<_>>());
    let header = lines.next().unwrap();
    (header, lines.collect())
}

/// `--resume` through the binary: a run killed once its coarse mesh is checkpointed resumes
/// from that checkpoint (its rows are the checkpoint's: a timing planted there comes back)
/// and ends with the rows of an uninterrupted run (timings aside) and no checkpoints left.
#[test]
fn killed_run_resumes_from_its_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--cases",
        "flat-punch",
        "--meshes",
        "0.2,0.02",
        "--methods",
        "lagrange,constant",
        "--quiet",
        "--no-figures",
        "--out",
    ];
    let full = dir.path().join("full");
    common::run_ok(bin().args(args).arg(&full));

    let out = dir.path().join("killed");
    let checkpoint = out.join("meshes").join("flat-punch-h0.2.json");
    let mut child = bin()
        .args(args)
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !checkpoint.exists() && t0.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        running && checkpoint.exists(),
        "the run ended before its fine mesh (≈ 1 s of work) could be interrupted"
    );
    assert!(
        !out.join("rows.csv").exists(),
        "a killed run wrote its rows"
    );

    // Plant a timing in the checkpoint: a resumed run that reuses it reports it.
    const PLANTED: f64 = 12345.0;
    let mut c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&checkpoint).unwrap()).unwrap();
    let rows = c["value"]["rows"].as_array_mut().unwrap();
    assert!(!rows.is_empty());
    for r in rows.iter_mut() {
        r["seconds"] = PLANTED.into();
    }
    std::fs::write(&checkpoint, serde_json::to_string(&c).unwrap()).unwrap();

    common::run_ok(bin().args(args).arg(&out).arg("--resume"));
    assert!(
        !out.join("meshes").exists(),
        "checkpoints left after the run"
    );
    let (header, resumed) = csv_rows(&out);
    let (header_full, reference) = csv_rows(&full);
    assert_eq!(header, header_full);
    assert_eq!(resumed.len(), reference.len());
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    let (h, seconds) = (col("h"), col("seconds"));
    let planted = resumed
        .iter()
        .filter(|r| r[seconds].parse::<f64>().unwrap() == PLANTED)
        .count();
    let coarse = resumed.iter().filter(|r| r[h] == "0.2").count();
    assert!(
        coarse > 0 && planted == coarse,
        "{planted} planted of {coarse} coarse rows"
    );
    // Every other column as in the uninterrupted run.
    let timing = |name: &str| name.starts_with("seconds");
    for (a, b) in resumed.iter().zip(&reference) {
        for (i, name) in header.iter().enumerate() {
            if !timing(name) {
                assert_eq!(a[i], b[i], "column {name}");
            }
        }
    }
}

/// `--vtk DIR` writes one `.vtu` per solved row of a single-body case, read back here with
/// vtkio and checked against the run's own record and the model, independently of the
/// writer: the contact pressure at every top node is the row's profile (summary.json) bit
/// for bit; the gap at a top node is its indenter clearance x²/(2R) − u_y from the file's
/// own u (so u sits on the right nodes), 0 where Lagrange is in contact; the base nodes carry
/// the lift (u_y) and the clamp (u_x = 0). A second run into the folder is refused.
#[test]
fn vtk_files_hold_u_and_the_pressure_on_the_right_nodes() {
    let out = tempfile::tempdir().unwrap();
    let vtk = out.path().join("vtk");
    // The small run, into `run` of `out`, its `.vtu` files into `vtk`.
    let small = |run: &str| {
        let mut c = bin();
        c.args(["--cases", "hertz-plane", "--meshes", "0.2", "--quiet"])
            .args([
                "--methods",
                "lagrange,constant",
                "--eps-rel",
                "1000",
                "--vtk",
            ])
            .arg(&vtk)
            .arg("--out")
            .arg(out.path().join(run));
        c
    };
    let o = common::run_ok(small("run").arg("--json"));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = s["rows"].as_array().unwrap();
    let mut files: Vec<String> = std::fs::read_dir(&vtk)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    files.sort();
    assert_eq!(files.len(), rows.len(), "{files:?}");
    let lagrange = rows.iter().find(|r| r["method"] == "lagrange").unwrap();
    let h = lagrange["h"].as_f64().unwrap();
    let (r, lift) = (
        lagrange["radius"].as_f64().unwrap(),
        lagrange["lift"].as_f64().unwrap(),
    );
    let (points, arrays) = common::read_vtu(&vtk.join(format!("hertz-plane_h{h}_lagrange.vtu")));
    let profile = s["profiles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["rule"] == "lagrange")
        .unwrap();
    let (px, pp) = (
        profile["x"].as_array().unwrap(),
        profile["p"].as_array().unwrap(),
    );
    let (u, p, gap) = (&arrays["u"], &arrays["contact_pressure"], &arrays["gap"]);
    let top = points.iter().map(|q| q[1]).fold(f64::MIN, f64::max);
    let scale = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let pmax = p.iter().fold(0.0f64, |m, v| m.max(*v));
    let mut matched = 0;
    for (k, q) in points.iter().enumerate() {
        let uy = u[3 * k + 1];
        if q[1] == top {
            let c = px
                .iter()
                .position(|x| x.as_f64().unwrap() == q[0])
                .expect("a top node is a profile node");
            assert_eq!(p[k], pp[c].as_f64().unwrap(), "pressure at x = {}", q[0]);
            let clearance = q[0] * q[0] / (2.0 * r) - uy;
            assert!(
                (gap[k] - clearance).abs() <= 1e-12 * scale,
                "gap at x = {}",
                q[0]
            );
            // Loaded as contact_bench counts it (an open node's pressure, read from
            // equilibrium, is rounding).
            if p[k] > 1e-9 * pmax {
                assert!(
                    gap[k].abs() <= 1e-12 * scale,
                    "Lagrange in contact at {}",
                    q[0]
                );
            }
            matched += 1;
        } else {
            assert_eq!(p[k], 0.0);
            assert!(gap[k].is_nan());
        }
        if q[1] == 0.0 {
            assert_eq!((u[3 * k], uy), (0.0, lift), "base node at x = {}", q[0]);
        }
    }
    assert_eq!(matched, px.len());
    let loaded = pp.iter().filter(|v| v.as_f64().unwrap() > 1e-9 * pmax);
    assert!(loaded.count() >= 3);
    // Into the same folder again: refused before anything runs.
    let again = small("run2").output().unwrap();
    assert_eq!(again.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&again.stderr).contains(".vtu files"));
    assert!(!out.path().join("run2").exists());
}
