//! Reading scene files and Matrix Market: the fixtures with their optional fields, a Matrix
//! Market K resolved next to its scene and kept sparse, symmetric expansion, the format's
//! variants, and agreement with nalgebra-sparse's reader.

use crate::scene_support::{all_bits, bits, entries, fixtures, MM_HDR};
use penalty_lab::scene::{parse_matrix_market_str, read_matrix_market, read_scene};
use penalty_lab::system::{Constraint, ConstraintKind};
use std::fs;

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
            Constraint::on_dof(1, -3.0, ConstraintKind::Lower),
            Constraint::on_dof(2, 0.5, ConstraintKind::Bilateral),
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
