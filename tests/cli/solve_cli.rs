//! The `solve` binary: the scene contract of methods.md on the shipped paper-beam scene, and
//! exit status 2 with one clear line on stderr for every kind of bad input.

use penalty_lab::model::beam::paper;
use penalty_lab::scene;
use std::path::Path;
use std::process::Command;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper_beam.scene.json");

fn solve(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_solve"))
        .args(args)
        .output()
        .expect("run solve");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

fn printed(a: f64, b: f64, decimals: i32) -> bool {
    (a - b).abs() <= 0.5 * 10f64.powi(-decimals) * (1.0 + 1e-12)
}

#[test]
fn shipped_scene_is_the_model_beam() {
    let s = scene::read_scene(Path::new(SCENE)).unwrap();
    let p = paper::problem();
    assert_eq!(s.problem.q, p.q);
    assert_eq!(s.problem.constraints, p.constraints);
    for i in 0..9 {
        for j in 0..9 {
            assert_eq!(s.problem.k.get(i, j), p.k.get(i, j));
        }
    }
}

#[test]
fn paper_method_reproduces_eq35_and_cond() {
    let (code, out, err) = solve(&[SCENE, "--method", "paper", "--delta", "0.1", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let eps: Vec<f64> = serde_json::from_value(v["penalties"].clone()).unwrap();
    assert!(printed(eps[0], 501.9, 1) && printed(eps[1], 1390.0, 0) && printed(eps[2], 557.0, 0));
    assert!(printed(v["cond2_system"].as_f64().unwrap(), 513.871, 3));
    // uw(K) = 4.572e4, |K| = 4.597e11, |K + ε| = 1.948e20 (4 significant digits).
    assert!((v["cond2_K"].as_f64().unwrap() - 4.572e4).abs() <= 0.5e1);
    let dk = 10f64.powf(v["log10_det_K"].as_f64().unwrap());
    assert!((dk - 4.597e11).abs() <= 0.5e8);
    let ds = 10f64.powf(v["log10_det_system"].as_f64().unwrap());
    assert!((ds - 1.948e20).abs() <= 0.5e17);
    for key in [
        "method",
        "u",
        "gaps",
        "max_penetration",
        "log10_det_ratio",
        "linear_solves",
        "iterations",
        "warnings",
    ] {
        assert!(!v[key].is_null(), "missing {key}");
    }
    assert_eq!(v["warnings"].as_array().unwrap().len(), 0);
}

#[test]
fn every_method_runs_on_the_scene_and_on_matrix_market() {
    let tmp = crate::common::tmp_dir("solve-mm");
    let d = tmp.path();
    let p = paper::problem();
    // Force the Matrix Market route (threshold 0).
    let f = d.join("beam.scene.json");
    scene::write_scene(&f, "beam-mm", &p, None, 0).unwrap();
    assert!(d.join("beam.mtx").exists());
    for file in [SCENE, f.to_str().unwrap()] {
        for args in [
            vec!["--method", "constant", "--eps", "1e4"],
            vec!["--method", "scaled", "--factor", "100"],
            vec!["--method", "spring", "--delta", "0.1"],
            vec!["--method", "paper", "--delta", "0.1"],
            vec!["--method", "condensed", "--delta", "0.1"],
            vec!["--method", "lagrange"],
            vec!["--method", "augmented", "--adaptive"],
        ] {
            let mut a = vec![file];
            a.extend(args.iter().copied());
            a.push("--json");
            let (code, out, err) = solve(&a);
            assert_eq!(code, 0, "{a:?}: {err}");
            let v: serde_json::Value = serde_json::from_str(&out).unwrap();
            assert!(v["cond2_system"].as_f64().unwrap() > 1.0);
        }
    }
    // Without --json: a readable table.
    let (code, out, _) = solve(&[SCENE, "--method", "condensed", "--delta", "0.1"]);
    assert_eq!(code, 0);
    assert!(out.contains("cond2_system") && out.contains("penalties"));
}

fn assert_bad(args: &[&str], needle: &str) {
    let (code, out, err) = solve(args);
    assert_eq!(code, 2, "{args:?}: stdout {out} stderr {err}");
    assert!(out.is_empty(), "{args:?}: stdout not empty: {out}");
    assert!(
        err.to_lowercase().contains(&needle.to_lowercase()),
        "{args:?}: stderr {err:?} lacks {needle:?}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_inputs_exit_2_with_a_clear_message() {
    let tmp = crate::common::tmp_dir("solve-bad");
    let d = tmp.path();
    let w = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    assert_bad(&[SCENE, "--method", "paper", "--delta", "0"], "> 0");
    assert_bad(&[SCENE, "--method", "paper", "--delta", "-1"], "> 0");
    assert_bad(&[SCENE, "--method", "paper", "--delta", "NaN"], "> 0");
    assert_bad(&[SCENE, "--method", "paper"], "--delta");
    assert_bad(&[SCENE, "--method", "bogus"], "condensed");
    // A knob flag the method does not take is refused, not ignored.
    assert_bad(
        &[SCENE, "--method", "lagrange", "--eps", "5"],
        "--eps needs a method that takes it (lagrange takes no knob)",
    );
    assert_bad(
        &[SCENE, "--method", "constant", "--eps", "5", "--delta", "1"],
        "constant takes --eps",
    );
    assert_bad(
        &[SCENE, "--method", "paper", "--delta", "1", "--adaptive"],
        "--adaptive",
    );
    assert_bad(
        &["/nonexistent/x.scene.json", "--method", "lagrange"],
        "nonexistent",
    );
    let malformed = w("malformed.scene.json", "{\"name\": \"x\", ");
    assert_bad(&[&malformed, "--method", "lagrange"], "line");
    let oob = w(
        "oob.scene.json",
        r#"{"name":"x","stiffness":{"dense":[[2,0],[0,2]]},"load":[1,1],
            "constraints":[{"dof":5,"limit":0,"kind":"upper"}]}"#,
    );
    assert_bad(&[&oob, "--method", "lagrange"], "out of range");
    let sizes = w(
        "sizes.scene.json",
        r#"{"name":"x","stiffness":{"dense":[[2,0],[0,2]]},"load":[1,1,1],
            "constraints":[]}"#,
    );
    assert_bad(&[&sizes, "--method", "lagrange"], "load");
    let inf = w(
        "inf.scene.json",
        r#"{"name":"x","stiffness":{"dense":[[1e999,0],[0,2]]},"load":[1,1],
            "constraints":[]}"#,
    );
    assert_bad(&[&inf, "--method", "lagrange"], "finite");
    // Singular K where the method needs K⁻¹.
    let sing = w(
        "sing.scene.json",
        r#"{"name":"x","stiffness":{"dense":[[1,-1],[-1,1]]},"load":[1,0],
            "constraints":[{"dof":0,"limit":0,"kind":"bilateral"}]}"#,
    );
    assert_bad(
        &[&sing, "--method", "condensed", "--delta", "0.1"],
        "singular",
    );
    // Malformed Matrix Market.
    w(
        "K.mtx",
        "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1\n",
    );
    let mm = w(
        "mm.scene.json",
        r#"{"name":"x","stiffness":{"matrix_market":"K.mtx"},"load":[1,1],"constraints":[]}"#,
    );
    assert_bad(&[&mm, "--method", "lagrange"], "K.mtx");
    assert_bad(
        &[SCENE, "--method", "lagrange", "--krylov-tol", "0"],
        "--krylov-tol",
    );
    assert_bad(
        &[SCENE, "--method", "lagrange", "--krylov-tol", "NaN"],
        "--krylov-tol",
    );
    assert_bad(
        &[SCENE, "--method", "lagrange", "--krylov-max-iters", "0"],
        "--krylov-max-iters",
    );
}

/// `--write-system DIR` writes the final system exactly as solved: A and b read back give,
/// by a dense solve here, the reported u (penalty and saddle point), and `x_hat.mtx` is the
/// direct solve `forward_err_u` measured. The solver-cost fields are in the JSON.
#[test]
fn write_system_round_trips_the_final_system() {
    use penalty_lab::scene::matrix_market::{parse_matrix_market_str, read_matrix_market};
    let tmp = crate::common::tmp_dir("solve-write-system");
    for (method, extra, n_sys) in [
        ("paper", vec!["--delta", "0.1"], 9),
        ("lagrange", vec![], 9 + 3),
    ] {
        let dir = tmp.path().join(method);
        let mut args = vec![SCENE, "--method", method, "--json"];
        args.extend(extra);
        args.extend(["--write-system", dir.to_str().unwrap()]);
        let (code, out, err) = solve(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let a = read_matrix_market(&dir.join("A.mtx")).unwrap();
        assert_eq!(a.n(), n_sys, "{method}");
        // b.mtx is an `array` file: one value per line after the size line.
        let b_text = std::fs::read_to_string(dir.join("b.mtx")).unwrap();
        let b: Vec<f64> = b_text.lines().skip(2).map(|l| l.parse().unwrap()).collect();
        let x_text = std::fs::read_to_string(dir.join("x_hat.mtx")).unwrap();
        let x_hat: Vec<f64> = x_text.lines().skip(2).map(|l| l.parse().unwrap()).collect();
        assert_eq!((b.len(), x_hat.len()), (n_sys, n_sys));
        let lu = a.to_dense().partial_piv_lu();
        let x = faer::linalg::solvers::Solve::solve(&lu, faer::Mat::from_fn(n_sys, 1, |i, _| b[i]));
        let u: Vec<f64> = serde_json::from_value(v["u"].clone()).unwrap();
        let scale = u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let cond = v["cond2_system"].as_f64().unwrap();
        for i in 0..9 {
            let tol = 16.0 * f64::EPSILON * cond * scale;
            assert!((x[(i, 0)] - u[i]).abs() <= tol, "{method} u[{i}]");
            assert!((x_hat[i] - u[i]).abs() <= tol, "{method} x_hat[{i}]");
        }
        for key in [
            "cond2_jacobi",
            "forward_err_u",
            "forward_err_force",
            "backward_err",
        ] {
            assert!(v[key].as_f64().is_some(), "{method}: {key} = {}", v[key]);
        }
        let iters = if method == "lagrange" {
            "minres_iters"
        } else {
            "pcg_iters_ic0"
        };
        assert!(v[iters].as_u64().is_some(), "{method}: {iters}");
        // The counts to a fixed error of u: a run that reports reaching the target stopped
        // within it (its error of u is in the output), one that did not, above it.
        let target = v["krylov_err_target"].as_f64().unwrap();
        let names: &[&str] = if method == "lagrange" {
            &["minres_iters_to_err"]
        } else {
            &[
                "pcg_iters_jacobi_to_err",
                "pcg_iters_ic0_to_err",
                "pcg_iters_amg_scalar_to_err",
            ]
        };
        for name in names {
            let reached = v[format!("{name}_converged")].as_bool().unwrap();
            let err_u = v[format!("{name}_err_u")].as_f64().unwrap();
            assert_eq!(reached, err_u <= target, "{method}: {name} {err_u:e}");
            assert!(v[*name].as_u64().is_some(), "{method}: {name}");
        }
        // The file is Matrix Market the library itself reads back.
        assert!(
            parse_matrix_market_str(&std::fs::read_to_string(dir.join("A.mtx")).unwrap(), "A")
                .is_ok()
        );
    }
}

/// `--version` names the crate version and the commit the binary was built from; an unknown
/// method is a usage error (exit 2) that lists the valid ones.
#[test]
fn version_and_method_choices() {
    let (code, out, _) = solve(&["--version"]);
    assert_eq!(code, 0);
    assert!(out.contains(env!("CARGO_PKG_VERSION")), "{out}");
    assert!(
        out.contains(&penalty_lab::provenance::git_commit()),
        "{out}"
    );
    let (code, _, err) = solve(&[SCENE, "--method", "penalty", "--eps", "1"]);
    assert_eq!(code, 2);
    for name in penalty_lab::strategy::registry::names() {
        assert!(err.contains(name), "{err} should list {name}");
    }
}

/// The command line's method choices are the registry's: `--help` lists every strategy's
/// name with its summary, and each name builds the strategy it names.
#[test]
fn method_names_are_the_strategy_names() {
    use penalty_lab::strategy::{registry, Knobs, Method};
    let (code, out, _) = solve(&["--help"]);
    assert_eq!(code, 0);
    let all = Knobs {
        eps: Some(1.0),
        factor: Some(1.0),
        delta: Some(1.0),
        tol: Some(1.0),
        adaptive: false,
        ..Knobs::NONE
    };
    for s in registry::BUILT_IN {
        let listed = out.lines().any(|l| {
            l.trim_start().starts_with(&format!("- {}:", s.name)) && l.ends_with(s.summary)
        });
        assert!(listed, "{} with its summary in {out}", s.name);
        assert_eq!(Method::from_name(s.name, all).unwrap().name(), s.name);
    }
    let mut names = registry::names();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), registry::BUILT_IN.len(), "names are unique");
}

/// A K that is not symmetric bit for bit is warned once, naming the largest asymmetry and
/// where it is: by rounding only (`Near`: LU solve, cond₂ through the symmetric part with a
/// widened bracket) or beyond (`Unsymmetric`: the SVD); a symmetric K gets no such warning.
/// The JSON carries `cond2_bounds_proven` and `cond2_within_contract` either way.
#[test]
fn unsymmetric_k_is_warned_and_the_json_says_what_is_proven() {
    let tmp = crate::common::tmp_dir("solve-unsymmetric");
    let dir = tmp.path();
    let cases = [
        ("far", "[[4, -1], [-2, 4]]", "(1, 0)", false),
        // -1 against -1 − 2ε: within 8 ε_mach·max|K|, not bit for bit.
        (
            "near",
            "[[4, -1], [-1.0000000000000004, 4]]",
            "(1, 0)",
            true,
        ),
    ];
    for (name, k, at, near) in cases {
        let path = dir.join(format!("{name}.scene.json"));
        std::fs::write(
            &path,
            format!(
                r#"{{"name": "{name}", "stiffness": {{"dense": {k}}}, "load": [1, 1],
                    "constraints": [{{"dof": 0, "limit": 0.1, "kind": "upper"}}]}}"#
            ),
        )
        .unwrap();
        let p = path.to_str().unwrap();
        for method in [vec!["constant", "--eps", "10"], vec!["lagrange"]] {
            let mut args = vec![p, "--method"];
            args.extend(method);
            args.push("--json");
            let (code, out, err) = solve(&args);
            assert_eq!(code, 0, "{err}");
            let v: serde_json::Value = serde_json::from_str(&out).unwrap();
            let w: Vec<String> = serde_json::from_value(v["warnings"].clone()).unwrap();
            let flagged: Vec<&String> = w
                .iter()
                .filter(|x| x.starts_with("K is not symmetric"))
                .collect();
            assert_eq!(flagged.len(), 1, "{name}: {w:?}");
            assert!(flagged[0].contains(at), "{name}: {}", flagged[0]);
            assert_eq!(flagged[0].contains("by rounding"), near, "{}", flagged[0]);
            assert_eq!(v["cond2_bounds_proven"], true, "{name}");
            assert!(v["cond2_within_contract"].is_boolean(), "{name}");
            let (lo, c, hi) = (
                v["cond2_system_lo"].as_f64().unwrap(),
                v["cond2_system"].as_f64().unwrap(),
                v["cond2_system_hi"].as_f64().unwrap(),
            );
            assert!(lo <= c && c <= hi, "{name}: {lo} {c} {hi}");
        }
    }
    let (code, out, _) = solve(&[SCENE, "--method", "paper", "--delta", "0.1", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(!v["warnings"].to_string().contains("not symmetric"));
    assert_eq!(v["cond2_within_contract"], true);
}

/// A symmetric K that is not positive definite is outside every strategy's energy model:
/// `solve` says so once (strategy and cond₂(K) both notice), and a positive definite K gets no
/// such warning. The JSON carries the cond₂ bounds around the value.
#[test]
fn indefinite_k_is_flagged_once() {
    let tmp = crate::common::tmp_dir("solve-indefinite");
    let dir = tmp.path();
    let path = dir.join("indefinite.scene.json");
    std::fs::write(
        &path,
        r#"{"name": "indefinite", "stiffness": {"dense": [[1, 0], [0, -1]]}, "load": [1, 1],
            "constraints": [{"dof": 0, "limit": 0.5, "kind": "upper"}]}"#,
    )
    .unwrap();
    let p = path.to_str().unwrap();
    for args in [
        vec![p, "--method", "constant", "--eps", "10", "--json"],
        vec![p, "--method", "lagrange", "--json"],
    ] {
        let (code, out, err) = solve(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let w: Vec<String> = serde_json::from_value(v["warnings"].clone()).unwrap();
        let flagged = w
            .iter()
            .filter(|x| x.contains("not positive definite"))
            .count();
        assert_eq!(flagged, 1, "{w:?}");
    }
    let (code, out, _) = solve(&[SCENE, "--method", "paper", "--delta", "0.1", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(!v["warnings"].to_string().contains("not positive definite"));
    let (lo, c, hi) = (
        v["cond2_system_lo"].as_f64().unwrap(),
        v["cond2_system"].as_f64().unwrap(),
        v["cond2_system_hi"].as_f64().unwrap(),
    );
    assert!(
        lo <= c && c <= hi && hi / lo - 1.0 < 1e-9,
        "[{lo}, {hi}] ∌ {c}"
    );
}

/// `--cond-tol`: a looser accuracy asked of cond₂ is honoured (the value within it of the
/// default one, its bounds still containing the default value), recorded in the JSON, and a
/// tolerance outside (0, 1) is bad input.
#[test]
fn cond_tol_loosens_the_value_and_keeps_the_bounds() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/bed_cantilever.scene.json"
    );
    let run = |extra: &[&str]| {
        let mut args = vec![scene, "--method", "constant", "--eps", "1e8", "--json"];
        args.extend_from_slice(extra);
        let (code, out, err) = solve(&args);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let exact = run(&[]);
    let loose = run(&["--cond-tol", "1e-4"]);
    assert_eq!(loose["cond_tol"].as_f64(), Some(1e-4));
    assert!(exact["cond_tol"].is_null());
    for key in ["cond2_K", "cond2_system"] {
        let (e, l) = (exact[key].as_f64().unwrap(), loose[key].as_f64().unwrap());
        assert!((l / e - 1.0).abs() <= 1e-4, "{key}: {l} vs {e}");
        let (lo, hi) = (
            loose[format!("{key}_lo")].as_f64().unwrap(),
            loose[format!("{key}_hi")].as_f64().unwrap(),
        );
        assert!(lo <= e && e <= hi, "{key}: {e} ∉ [{lo}, {hi}]");
    }
    for bad in ["0", "1", "-0.001", "nan"] {
        let (code, _, err) = solve(&[scene, "--method", "lagrange", "--cond-tol", bad]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        let (code, _, err) = solve(&[scene, "--method", "lagrange", "--krylov-err", bad]);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(
            err.contains("--krylov-err") && err.contains("(0, 1)"),
            "{err}"
        );
    }
}

/// `solve --vtk DIR` on a scene with `"nodes"` (a chain of 5 springs along x, one DOF per
/// node, line cells, an obstacle under three nodes), read back with vtkio: u per node is
/// the record's u bit for bit, the contact force at a node is −Σ r_c d_c of the record's
/// row forces, the gap is the row's clearance u − û (`lower` rows), the contact flag marks
/// the constrained nodes, and the cells are the scene's lines. A second run into the same
/// file, `--vtk` on a scene without nodes and bad cells are refused with one line.
#[test]
fn vtk_output_of_a_scene_with_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = |nodes: &str| {
        format!(
            r#"{{"name": "chain", "stiffness": {{"dense": [[2,-1,0,0,0],[-1,2,-1,0,0],[0,-1,2,-1,0],[0,0,-1,2,-1],[0,0,0,-1,2]]}},
  "load": [-1, -1, -1, -1, -1],
  "constraints": [{{"dof": 1, "kind": "lower", "limit": -2}}, {{"dof": 2, "kind": "lower", "limit": -2.5}}, {{"dof": 3, "kind": "lower", "limit": -2}}]{nodes}}}"#
        )
    };
    let nodes = r#", "nodes": {"coordinates": [[0,0],[1,0],[2,0],[3,0],[4,0]], "dofs_per_node": 1, "cells": [[0,1],[1,2],[2,3],[3,4]]}"#;
    let path = dir.path().join("chain.scene.json");
    std::fs::write(&path, scene(nodes)).unwrap();
    let vtk = dir.path().join("vtk");
    let (p, v) = (path.to_str().unwrap(), vtk.to_str().unwrap());
    let (code, out, err) = solve(&[p, "--method", "lagrange", "--json", "--vtk", v]);
    assert_eq!(code, 0, "{err}");
    let rec: serde_json::Value = serde_json::from_str(&out).unwrap();
    let floats = |k: &str| -> Vec<f64> {
        rec[k]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (u, r) = (floats("u"), floats("forces"));
    let (points, arrays) = crate::common::read_vtu(&vtk.join("chain_lagrange.vtu"));
    assert_eq!(points.len(), 5);
    let (du, f, gap, flag) = (
        &arrays["u"],
        &arrays["contact_force"],
        &arrays["gap"],
        &arrays["contact_node"],
    );
    let limits = [f64::NAN, -2.0, -2.5, -2.0, f64::NAN];
    for i in 0..5 {
        assert_eq!(points[i], [i as f64, 0.0, 0.0]);
        assert_eq!(du[3 * i], u[i]);
        assert_eq!((du[3 * i + 1], du[3 * i + 2]), (0.0, 0.0));
        let row = (1..=3).contains(&i).then(|| i - 1);
        assert_eq!(f[3 * i], row.map_or(0.0, |c| -r[c]), "node {i}");
        assert_eq!(flag[i], if row.is_some() { 1.0 } else { 0.0 });
        match row {
            Some(_) => assert_eq!(gap[i], u[i] - limits[i]),
            None => assert!(gap[i].is_nan()),
        }
    }
    // Node 2 is pressed onto its obstacle (the load pushes the chain down): a positive
    // contact force on it, zero clearance.
    assert!(f[6] > 0.0 && gap[2].abs() <= 1e-12);
    for (args, needle) in [
        (vec![p, "--method", "lagrange", "--vtk", v], "exists"),
        (vec![SCENE, "--method", "lagrange", "--vtk", v], "--vtk"),
    ] {
        let (code, _, err) = solve(&args);
        assert_eq!(code, 2, "{args:?}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{err}");
    }
    for bad in [
        r#", "nodes": {"coordinates": [[0,0],[1,0],[2,0],[3,0],[4,0]], "dofs_per_node": 1, "cells": [[0,7]]}"#,
        r#", "nodes": {"coordinates": [[0,0],[1,0],[2,0],[3,0]], "dofs_per_node": 1}"#,
        r#", "nodes": {"coordinates": [[0,0],[1,0],[2,0],[3,0],[4]], "dofs_per_node": 1}"#,
    ] {
        std::fs::write(&path, scene(bad)).unwrap();
        let (code, _, err) = solve(&[p, "--method", "lagrange"]);
        assert_eq!(code, 2, "{bad}");
        assert!(err.contains("nodes"), "{err}");
    }
}
