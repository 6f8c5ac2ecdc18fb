//! `solver_cost` end to end on the membrane and beam families (3 levels): the rows, the knob
//! matches, the first-order error bounds the direct solve must meet, the slopes the analytic
//! spectra predict, the files and figures, and bad input rejected with exit code 2.

use crate::common;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_solver_cost"))
}

#[test]
fn small_run_matches_rules_and_meets_the_error_bounds() {
    let tmp = common::tmp_dir("solver-cost");
    let dir = tmp.path().join("out");
    let out = common::run_ok(
        bin()
            .args([
                "--families",
                "membrane,beam",
                "--levels",
                "3",
                "--json",
                "--quiet",
            ])
            .arg("--out")
            .arg(&dir),
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = rows.as_array().unwrap();
    // 2 families × 3 levels × (lagrange + 7 rules × 2 accuracies), and the ε map: 11 values
    // of ε on level 2 of each family.
    assert_eq!(rows.len(), 2 * 3 * 15 + 2 * 11);
    let map: Vec<_> = rows.iter().filter(|r| r["accuracy"] == "eps-map").collect();
    assert_eq!(map.len(), 2 * 11);
    assert!(map
        .iter()
        .all(|r| r["level"] == 2 && r["method"] == "constant" && r["matched"] == false));
    let f = |r: &serde_json::Value, k: &str| r[k].as_f64();
    for r in rows {
        let what = format!(
            "{} {} {} level {}",
            r["family"], r["method"], r["accuracy"], r["level"]
        );
        if r["matched"] == true && r["accuracy"] != "exact" {
            let (a, t) = (f(r, "achieved").unwrap(), f(r, "target").unwrap());
            assert!((a / t - 1.0).abs() <= 0.05 + 1e-12, "{what}: {a} vs {t}");
        }
        if r["accuracy"] == "penetration" && r["matched"] == true {
            let p = f(r, "max_penetration").unwrap();
            assert!(
                (p / f(r, "target").unwrap() - 1.0).abs() <= 0.05 + 1e-12,
                "{what}"
            );
        }
        let (Some(cond), Some(fe), Some(be)) = (
            f(r, "cond2_system"),
            f(r, "forward_err_u"),
            f(r, "backward_err"),
        ) else {
            continue;
        };
        // A backward-stable direct solve: backward error ~ n·ε_mach, forward error within the
        // first-order bound cond₂·(backward error) (with room for the norms' √n).
        let n = r["n_dofs"].as_f64().unwrap() + 1.0;
        assert!(
            be <= 10.0 * n * f64::EPSILON,
            "{what}: backward error {be:e}"
        );
        assert!(
            fe <= 10.0 * n * f64::EPSILON * cond,
            "{what}: forward error {fe:e}, cond {cond:e}"
        );
        if r["method"] == "lagrange" {
            assert!(
                r["minres_iters"].as_u64().is_some() && r["pcg_iters_ic0"].is_null(),
                "{what}"
            );
        } else {
            assert!(r["pcg_iters_jacobi"].as_u64().is_some(), "{what}");
            assert!(r["pcg_iters_ic0"].as_u64().is_some(), "{what}");
            // The counts to 1e-6 of u: every run here reaches it.
            for key in [
                "pcg_iters_jacobi_to_err",
                "pcg_iters_ic0_to_err",
                "pcg_iters_amg_scalar_to_err",
            ] {
                assert!(r[key].as_u64().is_some(), "{what}: {key}");
                assert_eq!(r[format!("{key}_converged")], true, "{what}: {key}");
            }
        }
    }
    // h halves from level to level.
    for fam in ["membrane", "beam"] {
        let h: Vec<f64> = (0..3)
            .map(|l| {
                rows.iter()
                    .find(|r| r["family"] == fam && r["level"] == l)
                    .and_then(|r| f(r, "h"))
                    .unwrap()
            })
            .collect();
        assert!(
            (h[0] / h[1] - 2.0).abs() < 0.15 && (h[1] / h[2] - 2.0).abs() < 0.15,
            "{fam}: {h:?}"
        );
    }
    // Slopes the spectra predict: the Jacobi-scaled 5-point Laplacian has cond ∝ h⁻², the
    // Euler–Bernoulli beam ∝ h⁻⁴.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let slopes = summary["slopes"].as_array().unwrap();
    let p = |fam: &str| {
        slopes
            .iter()
            .find(|s| {
                s["family"] == fam && s["method"] == "constant" && s["accuracy"] == "discretization"
            })
            .and_then(|s| s["p_cond2_jacobi"].as_f64())
            .unwrap()
    };
    assert!(
        (1.5..=2.5).contains(&p("membrane")),
        "membrane p = {}",
        p("membrane")
    );
    assert!((3.3..=4.5).contains(&p("beam")), "beam p = {}", p("beam"));
    common::assert_files(
        &dir,
        &["solver_cost.csv", "solver_cost.json", "summary.json"],
    );
    for fig in [
        "iterations_ic0",
        "iterations_jacobi",
        "digits_lost",
        "raw_vs_jacobi",
        "leaderboard_pcg",
        "eps_map",
    ] {
        assert!(
            dir.join("figures").join(format!("{fig}.png")).exists(),
            "{fig}"
        );
    }
}

#[test]
fn bad_input_exits_2() {
    for (args, needle) in [
        (vec!["--levels", "1"], "--levels"),
        (vec!["--methods", "bogus"], "bogus"),
        (vec!["--krylov-tol", "2"], "--krylov-tol"),
        (vec!["--krylov-err", "0"], "--krylov-err"),
        (vec!["--hertz-h0", "0.9"], "--hertz-h0"),
        // A family's own flag without the family (it was ignored).
        (
            vec!["--families", "membrane", "--hertz-h0", "0.2"],
            "--hertz-h0 needs the family hertz-plane or hertz-axi",
        ),
        (
            vec!["--families", "beam", "--membrane-side0", "5"],
            "--membrane-side0",
        ),
        (
            vec!["--families", "membrane", "--beam-el0", "4"],
            "--beam-el0",
        ),
        (
            vec!["--families", "membrane", "--sphere-h0", "1"],
            "--sphere-h0 needs the family hertz-3d",
        ),
        (
            vec!["--families", "hertz-3d", "--sphere-h0", "5"],
            "--sphere-h0",
        ),
        (
            vec!["--families", "hertz-3d", "--sphere-h0", "NaN"],
            "--sphere-h0",
        ),
    ] {
        let tmp = common::tmp_dir("solver-cost-bad");
        let o = bin()
            .args(&args)
            .arg("--out")
            .arg(tmp.path())
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = common::stderr(&o);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(
            !tmp.path().join("solver_cost.csv").exists(),
            "{args:?} wrote rows"
        );
    }
}
