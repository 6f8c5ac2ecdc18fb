//! Scene files written and read back: bit-identical round trips (inline, through Matrix
//! Market above the size threshold, sparse general and symmetric, and under proptest), and
//! atomic writes that leave nothing behind when they fail.

use crate::common;
use crate::scene_support::{
    all_bits, assert_has, awkward_problem, bits, constraint_bits, entries, listing,
};
use penalty_lab::scene::{read_matrix_market, read_scene, write_matrix_market, write_scene};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use proptest::prelude::*;
use std::fs;

#[test]
fn round_trip_dense_inline_is_bit_identical() {
    let dir = common::tmp_dir("scene-io-dense");
    let (rows, q, cons) = awkward_problem(6);
    let p = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let meta = serde_json::json!({"generator": "test", "seed": 42, "x": [0.1, -3]});
    let path = dir.path().join("beam.scene.json");
    write_scene(&path, "beam \"quoted\" ✓", &p, Some(&meta), 100).unwrap();
    assert_eq!(
        listing(dir.path()),
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
    let dir = common::tmp_dir("scene-io-dense-mtx");
    let (rows, q, cons) = awkward_problem(5);
    let p = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let path = dir.path().join("big.scene.json");
    write_scene(&path, "big", &p, None, 4).unwrap();
    assert_eq!(listing(dir.path()), vec!["big.mtx", "big.scene.json"]);
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
    let dir = common::tmp_dir("scene-io-sparse");
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
    let path = dir.path().join("g.scene.json");
    write_scene(&path, "g", &p, None, usize::MAX).unwrap();
    let mtx = fs::read_to_string(dir.path().join("g.mtx")).unwrap();
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
    let path = dir.path().join("s.scene.json");
    write_scene(&path, "s", &p, None, usize::MAX).unwrap();
    let mtx = fs::read_to_string(dir.path().join("s.mtx")).unwrap();
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
    let path = dir.path().join("k.mtx");
    write_matrix_market(&path, &k).unwrap();
    assert!(fs::read_to_string(&path).unwrap().contains("general"));
    assert_eq!(entries(&read_matrix_market(&path).unwrap()), entries(&k));
    assert_eq!(
        listing(dir.path()),
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
            .map(|(d, &c)| {
                Constraint::on_dof(
                    d,
                    limits[d],
                    [ConstraintKind::Bilateral, ConstraintKind::Upper, ConstraintKind::Lower]
                        [usize::from(c - 1)],
                )
            })
            .collect();
        let p = Problem::new(k, q, cons).unwrap();
        let dir = common::tmp_dir("scene-io-prop");
        let path = dir.path().join("p.scene.json");
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
    let dir = common::tmp_dir("scene-io-atomic");
    let (rows, q, cons) = awkward_problem(3);
    let good = Problem::new(Stiffness::from_rows(&rows).unwrap(), q, cons).unwrap();
    let path = dir.path().join("a.scene.json");
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
    assert_eq!(listing(dir.path()), vec!["a.scene.json"]);

    // Missing directory: error naming the file, nothing created anywhere.
    let nowhere = dir.path().join("no/such/dir/x.scene.json");
    let e = write_scene(&nowhere, "x", &good, None, 0)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["x.mtx", "cannot create temporary file"]);
    assert_eq!(listing(dir.path()), vec!["a.scene.json"]);

    // Overwriting replaces the file completely.
    write_scene(&path, "renamed", &good, None, 100).unwrap();
    assert_eq!(read_scene(&path).unwrap().name, "renamed");
    assert_eq!(listing(dir.path()), vec!["a.scene.json"]);
}
