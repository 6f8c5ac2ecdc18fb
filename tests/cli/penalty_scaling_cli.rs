//! `penalty_scaling` end to end (mortar and one-pass node-to-segment, 2 levels): the analytic
//! facts of the two-body patch test, the files, `--render-only`, and bad input rejected with
//! exit code 2.
//!
//! The mortar rows under a constant penalty ε (per unit contact length) keep the patch test's
//! uniform field, only with a contact compliance 1/ε added: the pressure is
//! `p_ε = w/(C + 1/ε)`, `C = H₁/E₁* + H₂/E₂*`, so its relative error is exactly
//! `(1/ε)/(C + 1/ε)` on every mesh (derived here, not read from the code).

use crate::common;
use penalty_lab::study::penalty_scaling::PenaltyScalingConfig;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_penalty_scaling");

#[test]
fn small_run_meets_the_patch_test_facts() {
    let tmp = common::tmp_dir("penalty-scaling");
    let dir = tmp.path().join("out");
    let out = common::run_ok(
        Command::new(BIN)
            .args([
                "--discretizations",
                "mortar,nts-1",
                "--levels",
                "2",
                "--eps-rel",
                "1,100",
                "--delta-methods",
                "condensed",
                "--json",
                "--quiet",
            ])
            .arg("--out")
            .arg(&dir),
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = rows.as_array().unwrap();
    // 2 discretizations × 2 levels × (lagrange + 2 ε × 2 schedules + condensed).
    assert_eq!(rows.len(), 2 * 2 * 6);
    let cfg = PenaltyScalingConfig::default();
    let b = cfg.blocks(0);
    let c = b.h_lower / b.lower.contact_modulus() + b.h_upper / b.upper.contact_modulus();
    let f = |r: &serde_json::Value, k: &str| r[k].as_f64();
    let delta = 1e-2 * penalty_lab::study::penalty_scaling::SQUEEZE;
    for r in rows {
        let what = format!(
            "{} {} {} level {}",
            r["discretization"], r["method"], r["schedule"], r["level"]
        );
        assert!(f(r, "cond2_system").is_some(), "{what}: {}", r["note"]);
        assert!(f(r, "cond2_jacobi").is_some(), "{what}: {}", r["note"]);
        let mortar = r["discretization"] == "mortar";
        match r["method"].as_str().unwrap() {
            "lagrange" if mortar => {
                let e = f(r, "err_u").unwrap();
                assert!(e <= 1e-8, "{what}: mortar passes the patch test, err {e:e}");
            }
            "lagrange" => assert!(f(r, "err_u").unwrap() > 1e-6, "{what}"),
            "constant" if mortar => {
                let eps = f(r, "knob_value").unwrap();
                let want = (1.0 / eps) / (c + 1.0 / eps);
                let got = f(r, "err_pressure").unwrap();
                assert!(
                    (got / want - 1.0).abs() <= 1e-6,
                    "{what}: pressure error {got:e}, derived {want:e}"
                );
            }
            "condensed" => {
                let p = f(r, "max_penetration").unwrap();
                assert!(p <= delta * (1.0 + 1e-9), "{what}: {p:e} > δ");
            }
            _ => {}
        }
    }
    // The schedules as the module doc derives them: ε fixed → the penalty error stays,
    // ε ∝ E/h → it halves with h (mortar, ε_rel = 100, where Cε ≫ 1).
    let err = |sched: &str, level: u64| {
        rows.iter()
            .find(|r| {
                r["discretization"] == "mortar"
                    && r["schedule"] == sched
                    && r["eps_rel"].as_f64() == Some(100.0)
                    && r["level"].as_u64() == Some(level)
            })
            .and_then(|r| f(r, "err_penalty"))
            .unwrap()
    };
    let fixed = err("eps-fixed", 1) / err("eps-fixed", 0);
    let scaled = err("eps-e-over-h", 1) / err("eps-e-over-h", 0);
    assert!((fixed - 1.0).abs() < 0.02, "eps-fixed ratio {fixed}");
    assert!((scaled - 0.5).abs() < 0.02, "eps-e-over-h ratio {scaled}");
    common::assert_files(
        &dir,
        &[
            "penalty_scaling.csv",
            "penalty_scaling.json",
            "summary.json",
            "figures/penalty_scaling.png",
            "figures/penalty_scaling.svg",
        ],
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["slopes"].as_array().unwrap().len(), 2 * 6);
    let again = common::assert_render_only(
        BIN,
        &dir,
        "figures/penalty_scaling.png",
        "penalty_scaling.json",
        &["--json"],
    );
    assert_eq!(
        again, out.stdout,
        "--render-only --json prints the same record"
    );
}

#[test]
fn bad_input_exits_2_naming_the_flag() {
    let cases = vec![
        vec!["--ratio", "4-7"],
        vec!["--ratio", "0:7"],
        vec!["--levels", "9"],
        vec!["--discretizations", "mortar,segment"],
        vec!["--delta-methods", "constant"],
        vec!["--eps-rel=-1"],
        vec!["--delta-rel", "2"],
        // A reviewer's inputs: r << (levels − 1) overflowed; levels that push the default
        // ratio past 256 across named only --ratio; repeats; an ε that overflows K + εDDᵀ.
        vec!["--ratio", "9223372036854775807:1"],
        vec!["--levels", "7"],
        vec!["--discretizations", "mortar,mortar"],
        vec!["--delta-methods", "condensed,condensed"],
        vec!["--eps-rel", "1,1"],
        vec!["--eps-rel", "1e300"],
    ];
    let outs = common::assert_bad_input_writes_nothing(BIN, &cases, &["--quiet"]);
    for (args, o) in cases.iter().zip(outs) {
        let err = common::stderr(&o);
        let flag = args[0].split('=').next().unwrap();
        assert!(err.contains(flag), "{args:?}: '{err}'");
    }
}
