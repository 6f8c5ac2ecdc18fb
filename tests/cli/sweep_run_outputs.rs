//! What a `sweep` run writes: the same rows for one and two threads, timing columns that add
//! up, the default run's rows, manifest and figures (and `--render-only`), and the elastic
//! families with the barrier.

use crate::sweep_support::{
    assert_well_formed, manifest, rows_of, s, small_config, stderr, sweep_in, sweep_ok,
    sweep_writing_scenes, with, work_dir, SMALL,
};
use penalty_lab::generate::DEFAULT_FAMILIES as FAMILY_NAMES;
use penalty_lab::study::sweep::rows::{self, Row};
use penalty_lab::study::sweep::{figures::FIGURE_KINDS, SweepConfig};
use std::path::PathBuf;

#[test]
fn rows_are_identical_for_one_and_two_threads() {
    let (_tmp, d) = work_dir("threads");
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
/// The timing columns: each part non-negative and no larger than the row's total, empty where
/// the metric was not requested; the manifest's per-method sums are the rows' sums, and it
/// reports rows/s and a parallel efficiency in (0, 1].
#[test]
fn timing_columns_add_up_in_rows_and_manifest() {
    let (_tmp, d) = work_dir("timing");
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
fn default_run_writes_rows_manifest_and_figures() {
    let (_tmp, d) = work_dir("default");
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
/// The elastic families (`hertz`, `flat-punch`): every constraint unilateral, so `barrier`
/// runs on them beside the penalties; it never penetrates, every rule solves, and the scenes
/// export like any other family's. The flat punch is asked for by its old name `patch`,
/// which still reads.
#[test]
fn elastic_families_run_every_rule_and_the_barrier_never_penetrates() {
    let (_tmp, d) = work_dir("elastic");
    let (rows, scenes) = sweep_writing_scenes(
        &d,
        &[
            "--families",
            "hertz,patch",
            "--count",
            "2",
            "--methods",
            "constant,scaled,condensed,lagrange,barrier",
        ],
    );
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

/// `--metrics solver` (opt-in) fills the solver-cost columns; the default leaves them empty
/// and every other column of every row unchanged.
#[test]
fn solver_metrics_are_opt_in_and_change_no_other_column() {
    let (_g, d) = work_dir("solver-metrics");
    let plain = d.join("plain");
    let with = d.join("with");
    sweep_ok(
        &d,
        &[&SMALL[..], &["--quiet", "--no-figures", "--out", s(&plain)]].concat(),
    );
    let args = [
        "--metrics",
        "cond,det,solver",
        "--quiet",
        "--no-figures",
        "--out",
        s(&with),
    ];
    sweep_ok(&d, &[&SMALL[..], &args[..]].concat());
    let (a, b) = (rows_of(&plain), rows_of(&with));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(x.cond2_jacobi.is_none() && x.pcg_iters_ic0.is_none() && x.forward_err_u.is_none());
        let stripped = Row {
            cond2_jacobi: None,
            pcg_iters_jacobi: None,
            pcg_iters_ic0: None,
            pcg_converged: None,
            minres_iters: None,
            pcg_iters_jacobi_to_err: None,
            pcg_iters_jacobi_to_err_converged: None,
            pcg_iters_ic0_to_err: None,
            pcg_iters_ic0_to_err_converged: None,
            minres_iters_to_err: None,
            minres_iters_to_err_converged: None,
            pcg_iters_amg_scalar_to_err: None,
            pcg_iters_amg_scalar_to_err_converged: None,
            pcg_iters_amg_nodal_to_err: None,
            pcg_iters_amg_nodal_to_err_converged: None,
            forward_err_u: None,
            forward_err_force: None,
            warnings: x.warnings.clone(),
            ..y.clone()
        };
        assert_eq!(x, &stripped, "{} {}", x.scene, x.method);
        // Rows without a solve (an error, `optimal` outside its families) have no metrics.
        if y.warnings.contains("error") || y.cond2_system.is_none() {
            continue;
        }
        assert!(
            y.cond2_jacobi.is_some_and(|c| c >= 1.0),
            "{} {}",
            y.scene,
            y.method
        );
        if y.method == "lagrange" {
            assert!(
                y.minres_iters.is_some()
                    && y.minres_iters_to_err.is_some()
                    && y.pcg_iters_ic0.is_none(),
                "{}",
                y.scene
            );
        } else {
            assert!(
                y.pcg_iters_jacobi.is_some()
                    && y.pcg_iters_ic0.is_some()
                    && y.pcg_iters_jacobi_to_err.is_some()
                    && y.pcg_iters_ic0_to_err_converged.is_some()
                    && y.pcg_iters_amg_scalar_to_err.is_some()
                    && y.pcg_iters_amg_scalar_to_err_converged.is_some(),
                "{} {}",
                y.scene,
                y.method
            );
        }
        let (fe, cond) = (y.forward_err_u.unwrap(), y.cond2_system.unwrap());
        let n = y.n as f64 + y.m as f64;
        assert!(
            fe <= 10.0 * n * f64::EPSILON * cond,
            "{} {}: {fe:e} vs cond {cond:e}",
            y.scene,
            y.method
        );
    }
}

/// A method that fails on every scene it runs on is said out loud: the summary table names it
/// with its first error, the run exits 4 with one line on stderr, and the rows are written
/// (barrier refuses the beam's bilateral ties). With a method that solves beside it, the
/// failing rows are in the summary and the exit status still 4.
#[test]
fn a_method_failing_everywhere_exits_4_with_its_first_error() {
    let (_tmp, d) = work_dir("all-failed");
    let out = d.join("out");
    let o = sweep_in(
        &d,
        &[
            "--families",
            "beam",
            "--count",
            "1",
            "--methods",
            "lagrange,barrier",
            "--no-figures",
            "--quiet",
            "--out",
            s(&out),
        ],
    );
    let (stdout, err) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(4), "{stdout}{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("barrier (") && !err.contains("lagrange ("),
        "{err}"
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("barrier"))
        .expect("a summary line for barrier");
    let rows = rows_of(&out);
    let failed = rows.iter().filter(|r| r.method == "barrier").count();
    assert!(failed > 0 && rows.iter().any(|r| r.method == "lagrange"));
    // barrier: 0 solved, every row failed, the first error shown.
    let cells: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(cells[1..4], ["0", &failed.to_string(), "0"], "{line}");
    assert!(
        stdout.lines().any(|l| l.starts_with("lagrange")),
        "{stdout}"
    );
}
