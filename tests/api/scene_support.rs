//! Helpers of the scene-file and Matrix Market tests (`scene_reading`, `scene_round_trips`,
//! `scene_validation`, `scene_fuzz`): fixtures, bit-level views of K and q, error-message
//! checks, and small scenes.

pub(crate) use crate::common::matrices::constraint_bits;
use penalty_lab::scene::{parse_matrix_market_str, parse_scene_str};
use penalty_lab::system::{Constraint, ConstraintKind, Stiffness};
use std::fs;
use std::path::{Path, PathBuf};

/// The names in `dir`, sorted.
pub(crate) fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

pub(crate) fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

/// Stored entries as (row, col, bits), in storage order.
pub(crate) fn entries(k: &Stiffness) -> Vec<(usize, usize, u64)> {
    let mut v = Vec::new();
    k.for_each_entry(|i, j, x| v.push((i, j, x.to_bits())));
    v
}

/// All N² values as bits (0.0 where not stored).
pub(crate) fn all_bits(k: &Stiffness) -> Vec<u64> {
    let n = k.n();
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .map(|(i, j)| k.get(i, j).to_bits())
        .collect()
}

pub(crate) fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

pub(crate) fn scene_err(json: &str) -> String {
    match parse_scene_str(json, &fixtures(), "t.scene.json") {
        Ok(_) => panic!("expected an error for scene:\n{json}"),
        Err(e) => e.to_string(),
    }
}

pub(crate) fn mm_err(text: &str) -> String {
    match parse_matrix_market_str(text, "K.mtx") {
        Ok(_) => panic!("expected an error for Matrix Market text:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[track_caller]
pub(crate) fn assert_has(msg: &str, words: &[&str]) {
    for w in words {
        assert!(
            msg.contains(w),
            "message {msg:?} should contain {w:?} (all of {words:?})"
        );
    }
    assert!(!msg.contains('\n'), "message should be one line: {msg:?}");
}

/// A minimal valid scene with the given pieces (3×3 identity-ish K by default).
pub(crate) fn scene(stiffness: &str, load: &str, constraints: &str) -> String {
    format!(
        r#"{{"name": "t", "stiffness": {stiffness}, "load": {load}, "constraints": {constraints}}}"#
    )
}

pub(crate) const K3: &str = r#"{"dense": [[2, -1, 0], [-1, 2, -1], [0, -1, 2]]}"#;
pub(crate) const C1: &str = r#"[{"dof": 1, "limit": 0.5, "kind": "upper"}]"#;

pub(crate) const MM_HDR: &str = "%%MatrixMarket matrix coordinate real general\n";

/// Awkward finite values: shortest forms of 17 digits, subnormals, extremes, −0.
pub(crate) const AWKWARD: [f64; 10] = [
    0.1 + 0.2,
    -0.0,
    5e-324,
    1.797_693_134_862_315_7e308,
    -2.225_073_858_507_201e-308,
    std::f64::consts::PI,
    1e15,
    123_456_789.012_345_68,
    -7.0,
    1.0 / 3.0,
];

pub(crate) fn awkward_problem(n: usize) -> (Vec<Vec<f64>>, Vec<f64>, Vec<Constraint>) {
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    if i == j {
                        10.0 + AWKWARD[(i + j) % AWKWARD.len()].abs().min(1e3)
                    } else if (i + 2 * j) % 3 == 0 {
                        0.0
                    } else {
                        AWKWARD[(3 * i + j) % AWKWARD.len()]
                    }
                })
                .collect()
        })
        .collect();
    let q: Vec<f64> = (0..n).map(|i| AWKWARD[(i * 7) % AWKWARD.len()]).collect();
    let cons = vec![
        Constraint::on_dof(n - 1, 0.1 + 0.2, ConstraintKind::Bilateral),
        Constraint::on_dof(0, -0.0, ConstraintKind::Upper),
        Constraint::on_dof(1, -1e-300, ConstraintKind::Lower),
    ];
    (rows, q, cons)
}
