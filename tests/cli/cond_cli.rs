//! The `cond` binary: cond₂ of a bare Matrix Market matrix against analytic values (SPD,
//! unsymmetric), what it says of a singular matrix, and exit status 2 with one line on bad
//! input.

use std::path::Path;
use std::process::Command;

fn cond(args: &[&str]) -> (i32, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_cond"))
        .args(args)
        .output()
        .expect("run cond");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

fn json(path: &Path) -> serde_json::Value {
    let (code, out, err) = cond(&[path.to_str().unwrap(), "--json"]);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

/// The contract's relative tolerance at `c`: max(1e-12, 4·ε_mach·c).
fn contract(c: f64) -> f64 {
    (4.0 * f64::EPSILON * c).max(1e-12)
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// tridiag(−1, 2, −1) of size n, lower triangle in symmetric storage: λ_k = 4 sin²(kπ/(2(n+1))),
/// so cond₂ = sin²(nπ/(2(n+1))) / sin²(π/(2(n+1))) = cot²(π/(2(n+1))).
#[test]
fn laplacian_matches_its_analytic_cond_with_a_proven_bracket() {
    let dir = tempfile::tempdir().unwrap();
    let n = 300;
    let mut text = format!(
        "%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n",
        2 * n - 1
    );
    for i in 1..=n {
        text += &format!("{i} {i} 2\n");
        if i < n {
            text += &format!("{} {i} -1\n", i + 1);
        }
    }
    let v = json(&write(dir.path(), "L.mtx", &text));
    let x = std::f64::consts::PI / (2.0 * (n as f64 + 1.0));
    let exact = (x.cos() / x.sin()).powi(2);
    let c = v["cond2"].as_f64().unwrap();
    let (lo, hi) = (
        v["cond2_lo"].as_f64().unwrap(),
        v["cond2_hi"].as_f64().unwrap(),
    );
    // The analytic value in double carries a few ulps of cot²: well inside the contract.
    assert!(
        (c - exact).abs() <= contract(exact) * exact,
        "{c} vs {exact}"
    );
    assert!(lo <= exact * (1.0 + 8.0 * f64::EPSILON) && exact <= hi * (1.0 + 8.0 * f64::EPSILON));
    assert_eq!(v["cond2_bounds_proven"], true);
    assert_eq!(v["cond2_within_contract"], true);
    assert_eq!(v["n"], n);
    assert_eq!(v["nnz"], 3 * n - 2);
    assert_eq!(v["symmetry"], "exact");
    assert!(v["cond_route"].is_string());
    assert_eq!(v["warnings"].as_array().unwrap().len(), 0, "{v}");
}

/// [[1, 2], [0, 1]]: σ² = 3 ± 2√2, so cond₂ = (1 + √2)² = 3 + 2√2.
#[test]
fn unsymmetric_matrix_gets_its_singular_value_ratio() {
    let dir = tempfile::tempdir().unwrap();
    let text = "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1\n1 2 2\n2 2 1\n";
    let v = json(&write(dir.path(), "A.mtx", text));
    let exact = 3.0 + 2.0 * 2f64.sqrt();
    let c = v["cond2"].as_f64().unwrap();
    assert!(
        (c - exact).abs() <= contract(exact) * exact,
        "{c} vs {exact}"
    );
    assert_eq!(v["symmetry"], "unsymmetric");
    let (lo, hi) = (
        v["cond2_lo"].as_f64().unwrap(),
        v["cond2_hi"].as_f64().unwrap(),
    );
    assert!(lo <= exact * (1.0 + 4.0 * f64::EPSILON) && exact <= hi * (1.0 + 4.0 * f64::EPSILON));
}

#[test]
fn singular_matrix_is_said_to_be_singular() {
    let dir = tempfile::tempdir().unwrap();
    let text = "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 1\n2 1 1\n2 2 1\n";
    let v = json(&write(dir.path(), "S.mtx", text));
    let w = v["warnings"].as_array().unwrap();
    assert!(
        w.iter().any(|x| x.as_str().unwrap().contains("singular")),
        "{v}"
    );
    assert_eq!(v["cond2_within_contract"], false);
    assert!(v["cond2_hi"].is_null(), "{v}");
    // The table says it too.
    let (code, out, _) = cond(&[dir.path().join("S.mtx").to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        out.contains("warning:") && out.contains("singular"),
        "{out}"
    );
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let ok = write(
        dir.path(),
        "ok.mtx",
        "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 2\n",
    );
    let rect = write(
        dir.path(),
        "rect.mtx",
        "%%MatrixMarket matrix coordinate real general\n2 3 1\n1 1 2\n",
    );
    let nan = write(
        dir.path(),
        "nan.mtx",
        "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 nan\n",
    );
    let missing = dir.path().join("missing.mtx");
    let cases: [(Vec<&str>, &str); 5] = [
        (vec![missing.to_str().unwrap()], "missing.mtx"),
        (vec![rect.to_str().unwrap()], "rect.mtx"),
        (vec![nan.to_str().unwrap()], "nan.mtx"),
        (vec![ok.to_str().unwrap(), "--cond-tol", "0"], "--cond-tol"),
        (vec![ok.to_str().unwrap(), "--out", "x"], "--out"),
    ];
    for (args, names) in cases {
        let (code, out, err) = cond(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "{args:?}: {out}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: {err}");
    }
}
