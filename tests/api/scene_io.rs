//! Scene files and Matrix Market I/O: round trips (bit-identical), symmetric expansion,
//! validation messages, atomic writes, and no-panic fuzzing of both readers.

use penalty_lab::scene::{
    parse_matrix_market_str, parse_scene_str, read_matrix_market, read_scene, write_matrix_market,
    write_scene, MAX_DIM,
};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use proptest::prelude::*;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

// ----------------------------------------------------------------------------------------
// Helpers
// ----------------------------------------------------------------------------------------

/// A fresh directory under the system temp dir, removed on drop.
struct TmpDir(PathBuf);

impl TmpDir {
    fn new(tag: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let d = std::env::temp_dir().join(format!(
            "penalty-lab-scene-io-{}-{tag}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        TmpDir(d)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    fn listing(&self) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(&self.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }
}

impl Drop for TmpDir {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes")
}

/// Stored entries as (row, col, bits), in storage order.
fn entries(k: &Stiffness) -> Vec<(usize, usize, u64)> {
    let mut v = Vec::new();
    k.for_each_entry(|i, j, x| v.push((i, j, x.to_bits())));
    v
}

/// All N² values as bits (0.0 where not stored).
fn all_bits(k: &Stiffness) -> Vec<u64> {
    let n = k.n();
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .map(|(i, j)| k.get(i, j).to_bits())
        .collect()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn constraint_bits(p: &Problem) -> Vec<(usize, u64, ConstraintKind)> {
    p.constraints
        .iter()
        .map(|c| (c.dof, c.limit.to_bits(), c.kind))
        .collect()
}

fn scene_err(json: &str) -> String {
    match parse_scene_str(json, &fixtures(), "t.scene.json") {
        Ok(_) => panic!("expected an error for scene:\n{json}"),
        Err(e) => e.to_string(),
    }
}

fn mm_err(text: &str) -> String {
    match parse_matrix_market_str(text, "K.mtx") {
        Ok(_) => panic!("expected an error for Matrix Market text:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[track_caller]
fn assert_has(msg: &str, words: &[&str]) {
    for w in words {
        assert!(
            msg.contains(w),
            "message {msg:?} should contain {w:?} (all of {words:?})"
        );
    }
    assert!(!msg.contains('\n'), "message should be one line: {msg:?}");
}

/// A minimal valid scene with the given pieces (3×3 identity-ish K by default).
fn scene(stiffness: &str, load: &str, constraints: &str) -> String {
    format!(
        r#"{{"name": "t", "stiffness": {stiffness}, "load": {load}, "constraints": {constraints}}}"#
    )
}

const K3: &str = r#"{"dense": [[2, -1, 0], [-1, 2, -1], [0, -1, 2]]}"#;
const C1: &str = r#"[{"dof": 1, "limit": 0.5, "kind": "upper"}]"#;

const MM_HDR: &str = "%%MatrixMarket matrix coordinate real general\n";

/// Awkward finite values: shortest forms of 17 digits, subnormals, extremes, −0.
const AWKWARD: [f64; 10] = [
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

fn awkward_problem(n: usize) -> (Vec<Vec<f64>>, Vec<f64>, Vec<Constraint>) {
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
        Constraint {
            dof: n - 1,
            limit: 0.1 + 0.2,
            kind: ConstraintKind::Bilateral,
        },
        Constraint {
            dof: 0,
            limit: -0.0,
            kind: ConstraintKind::Upper,
        },
        Constraint {
            dof: 1,
            limit: -1e-300,
            kind: ConstraintKind::Lower,
        },
    ];
    (rows, q, cons)
}

// ----------------------------------------------------------------------------------------
// Fixtures and reading
// ----------------------------------------------------------------------------------------

#[test]
fn reads_fixture_scene_with_optional_fields() {
    let s = read_scene(&fixtures().join("small.scene.json")).unwrap();
    assert_eq!(s.name, "small");
    assert_eq!(
        s.description.as_deref(),
        Some("3-DOF symmetric fixture for tests/api/scene_io.rs")
    );
    let p = &s.problem;
    assert_eq!(p.n(), 3);
    assert!(!p.k.is_sparse());
    assert_eq!(p.k.get(1, 2), -1.5);
    assert_eq!(p.k.get(2, 2), 2.25);
    assert_eq!(bits(&p.q), bits(&[0.0, -50.0, 0.1]));
    assert_eq!(
        p.constraints,
        vec![
            Constraint {
                dof: 1,
                limit: -3.0,
                kind: ConstraintKind::Lower
            },
            Constraint {
                dof: 2,
                limit: 0.5,
                kind: ConstraintKind::Bilateral
            },
        ]
    );
    let meta = s.meta.unwrap();
    assert_eq!(meta["generator"], "hand-written");
    assert_eq!(meta["seed"].as_u64(), Some(7));
    assert_eq!(meta["weights"][1].as_f64(), Some(2.5));
}

#[test]
fn matrix_market_scene_resolves_relative_to_scene_dir_and_stays_sparse() {
    // The test's working directory is the crate root, not the fixture directory.
    let mm = read_scene(&fixtures().join("small_mm.scene.json")).unwrap();
    let dense = read_scene(&fixtures().join("small.scene.json")).unwrap();
    assert!(
        mm.problem.k.is_sparse(),
        "a Matrix Market K must not be densified"
    );
    assert_eq!(all_bits(&mm.problem.k), all_bits(&dense.problem.k));
    assert_eq!(bits(&mm.problem.q), bits(&dense.problem.q));
    assert_eq!(mm.description, None);
    assert!(mm.meta.is_none());
}

#[test]
fn symmetric_matrix_market_is_expanded() {
    let sym = read_matrix_market(&fixtures().join("small_sym.mtx")).unwrap();
    let gen = read_matrix_market(&fixtures().join("small_gen.mtx")).unwrap();
    assert!(sym.is_sparse() && gen.is_sparse());
    assert_eq!(sym.n(), 3);
    // 5 stored in the file, 7 after expansion; identical structure and values.
    assert_eq!(sym.nnz(), 7);
    assert_eq!(entries(&sym), entries(&gen));
    assert_eq!(sym.get(0, 1), -1.0);
    assert_eq!(sym.get(1, 0), -1.0);
    assert_eq!(sym.get(1, 2), -1.5);
    assert_eq!(sym.get(2, 1), -1.5);
    assert_eq!(sym.get(0, 2), 0.0);
    assert!(sym.is_symmetric());
}

/// Cross-check against nalgebra-sparse's reader on valid input.
#[test]
fn agrees_with_nalgebra_sparse_on_valid_files() {
    for name in ["small_sym.mtx", "small_gen.mtx"] {
        let text = fs::read_to_string(fixtures().join(name)).unwrap();
        let ours = parse_matrix_market_str(&text, name).unwrap();
        let coo = nalgebra_sparse::io::load_coo_from_matrix_market_str::<f64>(&text).unwrap();
        assert_eq!((coo.nrows(), coo.ncols()), (ours.n(), ours.n()));
        let mut dense = vec![0.0; ours.n() * ours.n()];
        for (i, j, v) in coo.triplet_iter() {
            dense[i * ours.n() + j] += *v;
        }
        assert_eq!(all_bits(&ours), bits(&dense), "{name}");
    }
}

#[test]
fn matrix_market_variants() {
    // integer field, comments and blank lines, duplicates summed.
    let k = parse_matrix_market_str(
        "%%MatrixMarket matrix coordinate integer general\n% c\n\n2 2 4\n1 1 3\n2 2 5\n% late comment\n1 1 4\n2 1 -2\n",
        "i.mtx",
    )
    .unwrap();
    assert_eq!(all_bits(&k), bits(&[7.0, 0.0, -2.0, 5.0]));
    // Upper-triangle-only symmetric file, Fortran exponent, CRLF, case-insensitive header.
    let k = parse_matrix_market_str(
        "%%matrixmarket MATRIX Coordinate Real Symmetric\r\n2 2 2\r\n1 2 1.5D+00\r\n2 2 4\r\n",
        "u.mtx",
    )
    .unwrap();
    assert_eq!(all_bits(&k), bits(&[0.0, 1.5, 1.5, 4.0]));
    // array real general: column-major; +0.0 not stored.
    let k = parse_matrix_market_str(
        "%%MatrixMarket matrix array real general\n2 2\n1\n3\n0\n4\n",
        "a.mtx",
    )
    .unwrap();
    assert!(k.is_sparse());
    assert_eq!(k.nnz(), 3);
    assert_eq!(all_bits(&k), bits(&[1.0, 0.0, 3.0, 4.0]));
    // array symmetric: lower triangle column by column.
    let k = parse_matrix_market_str(
        "%%MatrixMarket matrix array real symmetric\n3 3\n1 2 3\n4 5\n6\n",
        "s.mtx",
    )
    .unwrap();
    assert_eq!(
        all_bits(&k),
        bits(&[1.0, 2.0, 3.0, 2.0, 4.0, 5.0, 3.0, 5.0, 6.0])
    );
    // Explicit zero entries in coordinate files are kept (structure preserved).
    let k = parse_matrix_market_str(&format!("{MM_HDR}2 2 2\n1 1 0\n2 2 1\n"), "z.mtx").unwrap();
    assert_eq!(k.nnz(), 2);
}

// ----------------------------------------------------------------------------------------
// Round trips
// ----------------------------------------------------------------------------------------

#[test]
fn round_trip_dense_inline_is_bit_identical() {
    let dir = TmpDir::new("dense");
    let (rows, q, cons) = awkward_problem(6);
    let p = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let meta = serde_json::json!({"generator": "test", "seed": 42, "x": [0.1, -3]});
    let path = dir.path("beam.scene.json");
    write_scene(&path, "beam \"quoted\" ✓", &p, Some(&meta), 100).unwrap();
    assert_eq!(
        dir.listing(),
        vec!["beam.scene.json"],
        "no .mtx, no temp files"
    );
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"dense\""), "{text}");

    let s = read_scene(&path).unwrap();
    assert_eq!(s.name, "beam \"quoted\" ✓");
    assert_eq!(s.meta.as_ref(), Some(&meta));
    assert!(!s.problem.k.is_sparse());
    assert_eq!(entries(&s.problem.k), entries(&p.k));
    assert_eq!(bits(&s.problem.q), bits(&p.q));
    assert_eq!(constraint_bits(&s.problem), constraint_bits(&p));
}

#[test]
fn round_trip_dense_above_threshold_goes_to_mtx() {
    let dir = TmpDir::new("dense-mtx");
    let (rows, q, cons) = awkward_problem(5);
    let p = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let path = dir.path("big.scene.json");
    write_scene(&path, "big", &p, None, 4).unwrap();
    assert_eq!(dir.listing(), vec!["big.mtx", "big.scene.json"]);
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.contains(r#""matrix_market": "big.mtx""#), "{text}");
    assert!(!text.contains("meta"));

    let s = read_scene(&path).unwrap();
    assert!(s.problem.k.is_sparse());
    assert_eq!(all_bits(&s.problem.k), all_bits(&p.k));
    // -0.0 entries survive; +0.0 entries are simply not stored.
    let stored_zero = entries(&s.problem.k).iter().filter(|e| e.2 == 0).count();
    assert_eq!(stored_zero, 0);
    assert_eq!(bits(&s.problem.q), bits(&p.q));
    assert_eq!(constraint_bits(&s.problem), constraint_bits(&p));
}

#[test]
fn round_trip_sparse_general_and_symmetric() {
    let dir = TmpDir::new("sparse");
    // Non-symmetric, with an explicit stored zero and a -0.0.
    let t = vec![
        (0, 0, 4.0),
        (1, 0, 0.1 + 0.2),
        (0, 1, -1.0),
        (1, 1, 5e-324),
        (2, 2, 0.0),
        (3, 3, -0.0),
        (3, 1, 1e300),
    ];
    let k = Stiffness::from_triplets(4, &t).unwrap();
    let p = Problem::new(k, vec![1.0, -0.0, 0.5, 1e-7], vec![]).unwrap();
    let path = dir.path("g.scene.json");
    write_scene(&path, "g", &p, None, usize::MAX).unwrap();
    let mtx = fs::read_to_string(dir.path("g.mtx")).unwrap();
    assert!(mtx.starts_with("%%MatrixMarket matrix coordinate real general\n"));
    let s = read_scene(&path).unwrap();
    assert!(s.problem.k.is_sparse());
    assert_eq!(entries(&s.problem.k), entries(&p.k));
    assert_eq!(bits(&s.problem.q), bits(&p.q));
    assert!(s.problem.constraints.is_empty());

    // Bitwise symmetric → symmetric file with the lower triangle only.
    let t = vec![
        (0, 0, 2.0),
        (1, 0, 0.1 + 0.2),
        (0, 1, 0.1 + 0.2),
        (1, 1, 3.0),
        (2, 1, -1e-9),
        (1, 2, -1e-9),
        (2, 2, 1.0),
    ];
    let k = Stiffness::from_triplets(3, &t).unwrap();
    let p = Problem::new(k, vec![0.0; 3], vec![]).unwrap();
    let path = dir.path("s.scene.json");
    write_scene(&path, "s", &p, None, usize::MAX).unwrap();
    let mtx = fs::read_to_string(dir.path("s.mtx")).unwrap();
    assert!(mtx.starts_with("%%MatrixMarket matrix coordinate real symmetric\n"));
    assert!(mtx.contains("\n3 3 5\n"), "{mtx}");
    let s = read_scene(&path).unwrap();
    assert_eq!(entries(&s.problem.k), entries(&p.k));

    // Symmetric within tolerance but not bitwise → general, still exact (and not symmetric:
    // the certified routes need every mirror pair equal bit for bit).
    let t = vec![(0, 0, 1.0), (1, 0, 0.3), (0, 1, 0.1 + 0.2), (1, 1, 1.0)];
    let k = Stiffness::from_triplets(2, &t).unwrap();
    assert!(!k.is_symmetric());
    assert!(matches!(
        k.symmetry(),
        penalty_lab::system::Symmetry::Near(_)
    ));
    let path = dir.path("k.mtx");
    write_matrix_market(&path, &k).unwrap();
    assert!(fs::read_to_string(&path).unwrap().contains("general"));
    assert_eq!(entries(&read_matrix_market(&path).unwrap()), entries(&k));
    assert_eq!(
        dir.listing(),
        vec!["g.mtx", "g.scene.json", "k.mtx", "s.mtx", "s.scene.json"]
    );
}

fn finite_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<u64>()
            .prop_map(f64::from_bits)
            .prop_filter("finite", |x| x.is_finite()),
        -1e3..1e3f64,
        (-50i32..50).prop_map(f64::from),
        Just(0.0),
        Just(-0.0),
        Just(0.1 + 0.2),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// write_scene → read_scene reproduces K (values and, for sparse K, structure), q and
    /// the constraints bit for bit, inline or via Matrix Market, symmetric or not.
    #[test]
    fn round_trip_is_bit_identical(
        (n, vals, mask, q, codes, limits, sparse, sym, threshold) in (1usize..7).prop_flat_map(|n| (
            Just(n),
            prop::collection::vec(finite_f64(), n * n),
            prop::collection::vec(any::<bool>(), n * n),
            prop::collection::vec(finite_f64(), n),
            prop::collection::vec(0u8..4, n),
            prop::collection::vec(finite_f64(), n),
            any::<bool>(),
            any::<bool>(),
            prop_oneof![Just(0usize), Just(3), Just(100)],
        ))
    ) {
        let at = |i: usize, j: usize| if sym && i < j { vals[j * n + i] } else { vals[i * n + j] };
        let keep = |i: usize, j: usize| if sym && i < j { mask[j * n + i] } else { mask[i * n + j] };
        let k = if sparse {
            let t: Vec<_> = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .filter(|&(i, j)| keep(i, j))
                .map(|(i, j)| (i, j, at(i, j)))
                .collect();
            Stiffness::from_triplets(n, &t).unwrap()
        } else {
            let rows: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| at(i, j)).collect()).collect();
            Stiffness::from_rows(&rows).unwrap()
        };
        let cons: Vec<Constraint> = codes
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .map(|(d, &c)| Constraint {
                dof: d,
                limit: limits[d],
                kind: [ConstraintKind::Bilateral, ConstraintKind::Upper, ConstraintKind::Lower]
                    [usize::from(c - 1)],
            })
            .collect();
        let p = Problem::new(k, q, cons).unwrap();
        let dir = TmpDir::new("prop");
        let path = dir.path("p.scene.json");
        write_scene(&path, "p", &p, None, threshold).unwrap();
        let s = read_scene(&path).unwrap();
        let via_mtx = sparse || n > threshold;
        prop_assert_eq!(s.problem.k.is_sparse(), via_mtx);
        if sparse || !via_mtx {
            prop_assert_eq!(entries(&s.problem.k), entries(&p.k));
        } else {
            prop_assert_eq!(all_bits(&s.problem.k), all_bits(&p.k));
        }
        prop_assert_eq!(bits(&s.problem.q), bits(&p.q));
        prop_assert_eq!(constraint_bits(&s.problem), constraint_bits(&p));
    }
}

// ----------------------------------------------------------------------------------------
// Atomic writes
// ----------------------------------------------------------------------------------------

#[test]
fn failed_write_leaves_nothing_behind() {
    let dir = TmpDir::new("atomic");
    let (rows, q, cons) = awkward_problem(3);
    let good = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let path = dir.path("a.scene.json");
    write_scene(&path, "a", &good, None, 100).unwrap();
    let before = fs::read(&path).unwrap();

    // A problem made invalid after construction cannot be written; the old file survives.
    let mut bad = good.clone();
    bad.q[1] = f64::NAN;
    let e = write_scene(&path, "a", &bad, None, 0)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["a.scene.json", "load entry 1 is not finite"]);
    assert_eq!(fs::read(&path).unwrap(), before);
    assert_eq!(dir.listing(), vec!["a.scene.json"]);

    // Missing directory: error naming the file, nothing created anywhere.
    let nowhere = dir.path("no/such/dir/x.scene.json");
    let e = write_scene(&nowhere, "x", &good, None, 0)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["x.mtx", "cannot create temporary file"]);
    assert_eq!(dir.listing(), vec!["a.scene.json"]);

    // Overwriting replaces the file completely.
    write_scene(&path, "renamed", &good, None, 100).unwrap();
    assert_eq!(read_scene(&path).unwrap().name, "renamed");
    assert_eq!(dir.listing(), vec!["a.scene.json"]);
}

// ----------------------------------------------------------------------------------------
// Validation messages: scenes
// ----------------------------------------------------------------------------------------

#[test]
fn scene_errors_name_the_file() {
    let e = read_scene(Path::new("tests/data/scenes/does-not-exist.scene.json"))
        .unwrap_err()
        .to_string();
    assert_has(&e, &["does-not-exist.scene.json", "cannot read scene file"]);

    let dir = TmpDir::new("errs");
    let path = dir.path("x.scene.json");
    fs::write(
        &path,
        scene(
            K3,
            "[0, 0, 0]",
            r#"[{"dof": 12, "limit": 1, "kind": "upper"}]"#,
        ),
    )
    .unwrap();
    let e = read_scene(&path).unwrap_err().to_string();
    assert_has(
        &e,
        &["x.scene.json: constraint 0: DOF 12 is out of range (N = 3, DOFs are 0-based)"],
    );

    fs::write(&path, b"{\"name\": \"\xff\"}").unwrap();
    let e = read_scene(&path).unwrap_err().to_string();
    assert_has(&e, &["x.scene.json", "UTF-8"]);
}

#[test]
fn dof_out_of_range() {
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"dof": 0, "limit": 0, "kind": "upper"}, {"dof": 3, "limit": 1, "kind": "lower"}]"#,
    ));
    assert_has(
        &e,
        &[
            "t.scene.json",
            "constraint 1",
            "DOF 3 is out of range",
            "N = 3",
        ],
    );
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"dof": -1, "limit": 0, "kind": "upper"}]"#,
    ));
    assert_has(&e, &["constraints[0].dof", "non-negative integer", "-1"]);
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"dof": 1.5, "limit": 0, "kind": "upper"}]"#,
    ));
    assert_has(&e, &["constraints[0].dof", "1.5"]);
    // 2.0 is an integer, accepted.
    let s = parse_scene_str(
        &scene(
            K3,
            "[0, 0, 0]",
            r#"[{"dof": 2.0, "limit": 0, "kind": "upper"}]"#,
        ),
        Path::new("."),
        "t",
    )
    .unwrap();
    assert_eq!(s.problem.constraints[0].dof, 2);
}

#[test]
fn duplicate_dof() {
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"dof": 1, "limit": 0, "kind": "upper"}, {"dof": 1, "limit": 1, "kind": "lower"}]"#,
    ));
    assert_has(
        &e,
        &["t.scene.json", "constraint 1", "DOF 1 is constrained twice"],
    );
}

#[test]
fn unknown_kind_lists_valid_kinds() {
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"dof": 1, "limit": 0, "kind": "Upper"}]"#,
    ));
    assert_has(
        &e,
        &[
            "constraints[0].kind",
            "unknown kind \"Upper\"",
            "bilateral",
            "upper",
            "lower",
        ],
    );
    let e = scene_err(&scene(K3, "[0, 0, 0]", r#"[{"dof": 1, "limit": 0}]"#));
    assert_has(&e, &["constraints[0]", "missing required field \"kind\""]);
}

#[test]
fn wrong_load_length() {
    let e = scene_err(&scene(K3, "[0, 0]", C1));
    assert_has(
        &e,
        &["t.scene.json", "load vector has 2 entries but K is 3×3"],
    );
}

#[test]
fn malformed_json_reports_line_and_column() {
    let json = "{\n  \"name\": \"t\",\n  \"load\": [1, 2,, 3]\n}";
    let e = scene_err(json);
    assert_has(&e, &["t.scene.json", "line 3, column 17", "malformed JSON"]);
    let e = scene_err("{\"name\": \"t\",\n\"x\": [1, 2}\n");
    assert_has(&e, &["line 2, column 11", "expected ',' or ']'"]);
    assert_has(&scene_err(""), &["empty"]);
    let valid = scene(K3, "[0, 0, 0]", "[]");
    assert_has(
        &scene_err(&format!("{valid} x")),
        &["line 1", "unexpected 'x' after the end"],
    );
    assert_has(
        &scene_err(r#"{"name": "a", "name": "b"}"#),
        &["line 1, column 20", "duplicate key \"name\""],
    );
    assert_has(&scene_err("{\"a\": \"x\ny\"}"), &["control character"]);
    assert_has(
        &scene_err(r#"{"name": "t", "meta": {"seed": 1, "run": {"a": 1, "a": 2}}}"#),
        &["line 1", "meta.run", "duplicate key \"a\""],
    );
    assert_has(
        &scene_err("[1, 2]"),
        &[
            "line 1, column 1",
            "expected a JSON object",
            "found an array",
        ],
    );
    // 10 000 nested arrays: an error, not a stack overflow, at the top level (not an
    // object), in an ignored key (skipped without recursion) and in `meta` (kept: limited).
    let deep = format!("{}{}", "[".repeat(10_000), "]".repeat(10_000));
    assert_has(&scene_err(&deep), &["expected a JSON object"]);
    let ignored = format!(r#"{{"x": {deep}}}"#);
    assert_has(&scene_err(&ignored), &["missing required field \"name\""]);
    let in_meta = format!(r#"{{"name": "t", "meta": {deep}}}"#);
    assert_has(&scene_err(&in_meta), &["line 1", "nesting deeper than 128"]);
}

#[test]
fn non_finite_numbers_are_rejected() {
    let e = scene_err(&scene(r#"{"dense": [[1, 0], [0, 1e999]]}"#, "[0, 0]", "[]"));
    assert_has(&e, &["line 1", "number 1e999 is not finite"]);
    let e = scene_err(&scene(K3, "[0, -1e400, 0]", "[]"));
    assert_has(&e, &["not finite"]);
    let e = scene_err(&scene(K3, "[0, NaN, 0]", "[]"));
    assert_has(&e, &["NaN and Infinity are not valid JSON numbers"]);
    let e = scene_err(&scene(K3, "[0, -Infinity, 0]", "[]"));
    assert_has(&e, &["NaN and Infinity"]);
    // Tiny numbers underflow to 0 (or a subnormal), which is finite and fine.
    let s = parse_scene_str(&scene(K3, "[1e-400, 5e-324, 0]", "[]"), Path::new("."), "t").unwrap();
    assert_eq!(bits(&s.problem.q), bits(&[0.0, 5e-324, 0.0]));
}

#[test]
fn null_and_non_numeric_matrix_entries() {
    let e = scene_err(&scene(r#"{"dense": [[1, null], [0, 1]]}"#, "[0, 0]", "[]"));
    assert_has(
        &e,
        &["stiffness.dense[0][1]", "expected a number, found null"],
    );
    let e = scene_err(&scene(r#"{"dense": [[1, 0], [0, "2"]]}"#, "[0, 0]", "[]"));
    assert_has(&e, &["stiffness.dense[1][1]", "found the string \"2\""]);
    let e = scene_err(&scene(r#"{"dense": [[1, 0], [0, true]]}"#, "[0, 0]", "[]"));
    assert_has(&e, &["found a boolean"]);
    let e = scene_err(&scene(K3, "[0, {}, 0]", "[]"));
    assert_has(&e, &["load[1]", "found an object"]);
    let e = scene_err(&scene(r#"{"dense": [[1, 0], [0]]}"#, "[0, 0]", "[]"));
    assert_has(&e, &["not square", "row 1 has 1 entries, expected 2"]);
    let e = scene_err(&scene(r#"{"dense": []}"#, "[]", "[]"));
    assert_has(&e, &["empty"]);
}

#[test]
fn stiffness_needs_exactly_one_source() {
    let e = scene_err(&scene(
        r#"{"dense": [[1]], "matrix_market": "small_sym.mtx"}"#,
        "[0]",
        "[]",
    ));
    assert_has(
        &e,
        &[
            "stiffness",
            "both \"dense\" and \"matrix_market\"",
            "exactly one",
        ],
    );
    let e = scene_err(&scene("{}", "[0]", "[]"));
    assert_has(&e, &["stiffness", "exactly one"]);
    let e = scene_err(&scene(r#"{"sparse": [[1]]}"#, "[0]", "[]"));
    assert_has(&e, &["unknown key \"sparse\"", "exactly one"]);
    let e = scene_err(&scene(r#"{"dense": [[1]], "units": "N/m"}"#, "[0]", "[]"));
    assert_has(&e, &["unknown key \"units\""]);
    let e = scene_err(&scene("[[1]]", "[0]", "[]"));
    assert_has(&e, &["stiffness", "expected an object"]);
}

#[test]
fn missing_fields_and_wrong_types() {
    let e = scene_err(r#"{"stiffness": {"dense": [[1]]}, "load": [0], "constraints": []}"#);
    assert_has(&e, &["missing required field \"name\""]);
    let e = scene_err(r#"{"name": "t", "stiffness": {"dense": [[1]]}, "load": [0]}"#);
    assert_has(
        &e,
        &["missing required field \"constraints\"", "[] for none"],
    );
    let e = scene_err(r#"{"name": "t", "stiffness": {"dense": [[1]]}, "constraints": []}"#);
    assert_has(&e, &["missing required field \"load\""]);
    let e = scene_err(r#"{"name": "t", "load": [0], "constraints": []}"#);
    assert_has(&e, &["missing required field \"stiffness\""]);
    let e =
        scene_err(r#"{"name": 5, "stiffness": {"dense": [[1]]}, "load": [0], "constraints": []}"#);
    assert_has(&e, &["name", "expected a string, found a number"]);
    let e = scene_err(
        r#"{"name": "t", "description": [], "stiffness": {"dense": [[1]]}, "load": [0], "constraints": []}"#,
    );
    assert_has(&e, &["description", "expected a string"]);
    let e = scene_err(&scene(K3, "[0, 0, 0]", "{}"));
    assert_has(&e, &["constraints", "expected an array"]);
}

#[test]
fn matrix_market_reference_errors() {
    let e = scene_err(&scene(r#"{"matrix_market": "missing.mtx"}"#, "[0]", "[]"));
    assert_has(
        &e,
        &[
            "t.scene.json",
            "stiffness.matrix_market",
            "missing.mtx",
            "cannot read file",
        ],
    );
    let dir = TmpDir::new("mmref");
    fs::write(dir.path("K.mtx"), format!("{MM_HDR}3 3 2\n1 1 1\n7 2\n")).unwrap();
    let e = parse_scene_str(
        &scene(r#"{"matrix_market": "K.mtx"}"#, "[0, 0, 0]", "[]"),
        &dir.0,
        "s.scene.json",
    )
    .unwrap_err()
    .to_string();
    assert_has(
        &e,
        &[
            "s.scene.json",
            "K.mtx: line 4: expected 3 fields \"row col value\", found 2",
        ],
    );
    // Sizes are checked against the Matrix Market K too.
    fs::write(dir.path("K.mtx"), format!("{MM_HDR}2 2 1\n1 1 1\n")).unwrap();
    let e = parse_scene_str(
        &scene(r#"{"matrix_market": "K.mtx"}"#, "[0, 0, 0]", "[]"),
        &dir.0,
        "s.scene.json",
    )
    .unwrap_err()
    .to_string();
    assert_has(
        &e,
        &["s.scene.json", "load vector has 3 entries but K is 2×2"],
    );
}

// ----------------------------------------------------------------------------------------
// Validation messages: Matrix Market
// ----------------------------------------------------------------------------------------

#[test]
fn matrix_market_errors() {
    assert_has(&mm_err(""), &["K.mtx", "empty"]);
    assert_has(
        &mm_err("1 1 1\n1 1 1\n"),
        &["line 1", "not a Matrix Market file"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate real\n1 1 0\n"),
        &["header must have 5 fields"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 4 0\n")),
        &["line 2", "not square", "3 rows × 4 columns"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate real symmetric\n2 3 0\n"),
        &["not square"],
    );
    assert_has(&mm_err(&format!("{MM_HDR}0 0 0\n")), &["empty (0×0)"]);
    assert_has(
        &mm_err(&format!("{MM_HDR}% only comments\n")),
        &["size line"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3\n")),
        &["size line", "expected 3 integers"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 x 1\n")),
        &["\"x\" is not a non-negative integer"],
    );
    assert_has(&mm_err(&format!("{MM_HDR}2 2 5\n")), &["at most 4"]);
    let big = MAX_DIM + 1;
    assert_has(
        &mm_err(&format!("{MM_HDR}{big} {big} 0\n")),
        &["exceeds the supported maximum"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 2\n1 1 1.0\n1 2\n")),
        &["line 4", "expected 3 fields \"row col value\", found 2"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n1 1 1 9\n")),
        &["expected 3 fields", "found 4 or more"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n4 1 1.0\n")),
        &["line 3", "row index 4 is out of range (1..=3", "1-based"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n1 0 1.0\n")),
        &["column index 0 is out of range"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n99999999999999999999999 1 1.0\n")),
        &["row index 99999999999999999999999 is out of range"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n-1 1 1.0\n")),
        &["out of range"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n1.5 1 1.0\n")),
        &["\"1.5\" is not an integer"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 3\n1 1 1\n2 2 2\n")),
        &["truncated", "declares 3 entries", "after 2"],
    );
    assert_has(
        &mm_err(&format!("{MM_HDR}3 3 1\n1 1 1\n2 2 2\n")),
        &["line 4", "more entries than the 1 declared"],
    );
    for bad in ["nan", "NaN", "inf", "-Infinity", "1e400"] {
        assert_has(
            &mm_err(&format!("{MM_HDR}1 1 1\n1 1 {bad}\n")),
            &["line 3", "not finite"],
        );
    }
    assert_has(
        &mm_err(&format!("{MM_HDR}1 1 1\n1 1 abc\n")),
        &["\"abc\" is not a number"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate integer general\n1 1 1\n1 1 1.5\n"),
        &["\"1.5\" is not an integer"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate complex general\n1 1 1\n1 1 1 0\n"),
        &["complex matrices are not supported"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate pattern general\n1 1 1\n1 1\n"),
        &["pattern matrices are not supported"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate real skew-symmetric\n2 2 1\n2 1 1\n"),
        &["skew-symmetric matrices are not supported"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate real hermitian\n2 2 1\n2 1 1\n"),
        &["hermitian"],
    );
    assert_has(
        &mm_err("%%MatrixMarket vector coordinate real general\n2 2 1\n2 1 1\n"),
        &["unsupported object \"vector\""],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n2 1 1\n1 3 1\n"),
        &["line 4", "both sides of the diagonal", "lower triangle"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix array real general\n2 2\n1 2 3\n"),
        &["truncated"],
    );
    assert_has(
        &mm_err("%%MatrixMarket matrix array real general\n1 1\n1 2\n"),
        &["more values than the 1 expected"],
    );
    // The file name appears for file-based reads.
    let e = read_matrix_market(Path::new("tests/data/scenes/nope.mtx"))
        .unwrap_err()
        .to_string();
    assert_has(&e, &["nope.mtx", "cannot read file"]);
}

// ----------------------------------------------------------------------------------------
// No panics on arbitrary input
// ----------------------------------------------------------------------------------------

fn mm_line() -> impl Strategy<Value = String> {
    prop_oneof![
        "[0-9]{1,2} [0-9]{1,2} [-+.eEinfaD0-9]{1,8}",
        "[0-9]{1,25} [0-9]{1,25} [-0-9.e]{1,25}",
        "[0-9 ]{0,12}",
        "%[ -~]{0,10}",
        "[ -~]{0,20}",
    ]
}

fn mm_text() -> impl Strategy<Value = String> {
    (
        "%%MatrixMarket matrix (coordinate|array|vector) (real|integer|double|pattern|complex|x) (general|symmetric|skew-symmetric|hermitian)",
        prop_oneof!["[0-9]{1,2} [0-9]{1,2}( [0-9]{1,2})?", "[0-9]{1,25} [0-9]{1,25} [0-9]{1,25}", "[ -~]{0,12}"],
        prop::collection::vec(mm_line(), 0..10),
        prop_oneof![Just("\n"), Just("\r\n")],
    )
        .prop_map(|(h, s, lines, nl)| {
            let mut t = format!("{h}{nl}{s}{nl}");
            for l in lines {
                t.push_str(&l);
                t.push_str(nl);
            }
            t
        })
}

/// A valid scene text with a few random edits at random char boundaries.
fn mutated_scene() -> impl Strategy<Value = String> {
    let base = fs::read_to_string(fixtures().join("small.scene.json")).unwrap();
    prop::collection::vec(
        (
            any::<prop::sample::Index>(),
            0usize..4,
            "[\\[\\]{}\":,0-9a-zA-Z .eE+\\\\-]{0,3}",
        ),
        1..5,
    )
    .prop_map(move |edits| {
        let mut chars: Vec<char> = base.chars().collect();
        for (idx, del, ins) in edits {
            let at = idx.index(chars.len() + 1);
            let end = (at + del).min(chars.len());
            chars.splice(at..end, ins.chars());
        }
        chars.into_iter().collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_scene_str(&text, Path::new("."), "fuzz.scene.json");
        let _ = parse_matrix_market_str(&text, "fuzz.mtx");
        let with_header = format!("{MM_HDR}{text}");
        let _ = parse_matrix_market_str(&with_header, "fuzz.mtx");
    }

    #[test]
    fn arbitrary_strings_never_panic(s in "\\PC{0,300}") {
        let _ = parse_scene_str(&s, Path::new("."), "fuzz.scene.json");
        let _ = parse_matrix_market_str(&s, "fuzz.mtx");
    }

    #[test]
    fn matrix_market_like_text_never_panics(text in mm_text()) {
        if let Ok(k) = parse_matrix_market_str(&text, "fuzz.mtx") {
            prop_assert!(k.is_sparse());
            prop_assert!(k.all_finite());
        }
    }

    #[test]
    fn json_like_text_never_panics(s in "[\\[\\]{}\":,0-9a-z .eE+\\\\-]{0,200}") {
        let _ = parse_scene_str(&s, Path::new("."), "fuzz.scene.json");
    }

    #[test]
    fn mutated_scenes_never_panic(text in mutated_scene()) {
        match parse_scene_str(&text, &fixtures(), "fuzz.scene.json") {
            Ok(s) => prop_assert_eq!(s.problem.q.len(), s.problem.n()),
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.starts_with("fuzz.scene.json: "), "{}", msg);
                prop_assert!(!msg.contains('\n'), "{}", msg);
            }
        }
    }
}
