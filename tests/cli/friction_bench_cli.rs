//! `friction_bench` end to end on a small sliding block: the exact law's onset T/N = μ, the
//! augmented Lagrangian's within 1e-6, penalties converging to Lagrange as ε_T grows, cond₂
//! brackets, the figure redrawn from the saved data, and bad input refused with status 2.

use crate::common;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_friction_bench");

#[test]
fn small_run_reproduces_coulombs_onset_and_converging_penalties() {
    let tmp = common::tmp_dir("friction-bench");
    let dir = tmp.path().join("out");
    let out = common::run_ok(
        Command::new(BIN)
            .args(["--mu", "0.1,0.2,0.3", "--mesh", "8x4", "--steps", "20"])
            .args([
                "--eps-t",
                "1,100,10000",
                "--delta-t",
                "0.01",
                "--json",
                "--out",
            ])
            .arg(&dir),
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = rows.as_array().unwrap();
    // Per μ and model (the block; the patch test with mortar and nts-1 rows; the incline):
    // lagrange, augmented, 3 × (constant, area), 1 delta.
    assert_eq!(rows.len(), 3 * 4 * 9);
    for r in rows {
        assert_eq!(r["converged"], true, "{r}");
        let mu = r["mu"].as_f64().unwrap();
        let ratio = r["onset_ratio"].as_f64().expect("the block slides");
        // Exact for lagrange (the law in full slip, to rounding); the contract's 1e-6 for
        // augmented; every converged penalty meets it too.
        let tol = if r["method"] == "lagrange" {
            1e-12
        } else {
            1e-6
        };
        assert!((ratio - mu).abs() <= tol * mu, "{r}");
        let (c, lo, hi) = (
            r["cond2_system"].as_f64().unwrap(),
            r["cond2_lo"].as_f64().unwrap(),
            r["cond2_hi"].as_f64().unwrap(),
        );
        assert!(lo <= c && c <= hi && c >= 1.0, "{r}");
    }
    for mu in [0.1, 0.2, 0.3] {
        let err = |rule: &str| -> Vec<f64> {
            rows.iter()
                .filter(|r| r["case"] == "sliding-block")
                .filter(|r| r["mu"].as_f64() == Some(mu) && r["tangent_rule"] == rule)
                .map(|r| r["history_err"].as_f64().unwrap())
                .collect()
        };
        for rule in ["constant", "area"] {
            let e = err(rule);
            // ε_T ×100 cuts the friction force's error at least tenfold until ε_N's floor.
            assert!(e[1] < e[0] / 10.0, "{rule}, μ = {mu}: {e:?}");
        }
        let aug = err("augmented")[0];
        assert!(aug <= 1e-9, "augmented μ = {mu}: {aug:e}");
    }
    // The patch test in full slip: mortar with Lagrange transmits p and μp to 1e-8 (issue 65),
    // one-pass node-to-segment does not.
    for r in rows
        .iter()
        .filter(|r| r["method"] == "lagrange" && r["case"] == "patch-two-body-friction")
    {
        let worst = r["pressure_err_max"]
            .as_f64()
            .unwrap()
            .max(r["shear_err_max"].as_f64().unwrap());
        match r["discretization"].as_str().unwrap() {
            "mortar" => assert!(worst <= 1e-8, "{r}"),
            _ => assert!(worst > 1e-3, "{r}"),
        }
    }
    common::assert_files(&dir, &["friction_bench.json", "friction_bench.csv"]);
    common::assert_render_only(
        BIN,
        &dir,
        "figures/friction_eps_t.png",
        "friction_bench.json",
        &[],
    );
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let outs = common::assert_bad_input_writes_nothing(
        BIN,
        &[
            vec!["--mu", "-0.1"],
            vec!["--mu", "NaN"],
            vec!["--mesh", "1x1"],
            vec!["--mesh", "eight"],
            vec!["--law", "stribeck"],
            vec!["--cases", "cattaneo"],
            vec!["--delta-t", "0"],
            vec!["--steps", "0"],
            vec!["--cases", "cattaneo-mindlin", "--q-over-mup", "1"],
            vec!["--cases", "cattaneo-mindlin", "--q-over-mup", "0.5,1.2"],
            vec!["--cases", "cattaneo-mindlin", "--mu", "0,0.2"],
            vec!["--cases", "cattaneo-mindlin", "--cm-levels", "0.5"],
            vec!["--cases", "cattaneo-mindlin", "--cm-delta-t", "-1"],
        ],
        &[],
    );
    for o in outs {
        let err = common::stderr(&o);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}
