//! The near-null space of a scene (`near_null_space` + `block_size`, or `nodes`): written
//! and read back bit for bit, built from node coordinates, and refused with a message naming
//! the field when it does not fit K.

use crate::common;
use penalty_lab::model::incline_block;
use penalty_lab::scene::{parse_scene_str, read_scene, write_scene};
use penalty_lab::system::NearNull;
use std::fs;
use std::path::Path;

#[test]
fn a_models_rigid_body_modes_round_trip_through_a_scene() {
    let dir = common::tmp_dir("near-null-round-trip");
    let p = incline_block::problem(30.0, 6, 3).unwrap();
    let path = dir.path().join("incline.scene.json");
    write_scene(&path, "incline", &p, None, 0).unwrap();
    assert!(dir.path().join("incline.B.mtx").exists());
    let s = read_scene(&path).unwrap();
    let (a, b) = (p.near_null.unwrap(), s.problem.near_null.unwrap());
    assert_eq!((b.block_size, b.k), (2, 3));
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.b), bits(&b.b));
}

/// A 2-DOF spring scene (N = 4: two nodes of 2 DOFs) with `extra` spliced in.
fn scene(extra: &str) -> String {
    format!(
        r#"{{"name": "s", "stiffness": {{"dense": [[2,-1,0,0],[-1,2,0,0],[0,0,2,-1],[0,0,-1,2]]}},
            "load": [0, 0, 0, 1], "constraints": [{{"dof": 0, "limit": 0, "kind": "lower"}}]{extra}}}"#
    )
}

#[test]
fn nodes_give_rigid_body_modes_and_b_files_are_read() {
    let s = parse_scene_str(
        &scene(r#", "nodes": {"coordinates": [[0, 0], [1, 2]], "dofs_per_node": 2}"#),
        Path::new("."),
        "t",
    )
    .unwrap();
    let nn = s.problem.near_null.unwrap();
    let want = NearNull::rigid_body_modes(&[vec![0.0, 0.0], vec![1.0, 2.0]], 2).unwrap();
    assert_eq!(nn, want);

    let dir = common::tmp_dir("near-null-file");
    fs::write(
        dir.path().join("B.mtx"),
        "%%MatrixMarket matrix array real general\n4 1\n1\n1\n1\n1\n",
    )
    .unwrap();
    let s = parse_scene_str(
        &scene(r#", "near_null_space": {"matrix_market": "B.mtx"}, "block_size": 2"#),
        dir.path(),
        "t",
    )
    .unwrap();
    let nn = s.problem.near_null.unwrap();
    assert_eq!((nn.block_size, nn.k, nn.b.clone()), (2, 1, vec![1.0; 4]));
}

#[test]
fn near_null_spaces_that_do_not_fit_are_refused_with_the_field_named() {
    let dir = common::tmp_dir("near-null-bad");
    fs::write(
        dir.path().join("B3.mtx"),
        "%%MatrixMarket matrix array real general\n3 1\n1\n1\n1\n",
    )
    .unwrap();
    let cases = [
        (
            r#", "near_null_space": {"matrix_market": "B3.mtx"}"#,
            "B has 3 rows",
        ),
        (
            r#", "near_null_space": {"matrix_market": "missing.mtx"}"#,
            "near_null_space.matrix_market",
        ),
        (r#", "block_size": 2"#, "block_size"),
        (
            r#", "nodes": {"coordinates": [[0, 0]], "dofs_per_node": 2}"#,
            "1 nodes × 2 DOFs per node = 2",
        ),
        (
            r#", "nodes": {"coordinates": [[0, 0], [1]], "dofs_per_node": 2}"#,
            "coordinates of node 1",
        ),
        (
            r#", "nodes": {"coordinates": [[0, 0], [1, 1]], "dofs_per_node": 2}, "block_size": 1"#,
            "differs from nodes.dofs_per_node",
        ),
        (
            r#", "near_null_space": {"matrix_market": "B3.mtx", "extra": 1}"#,
            "extra",
        ),
    ];
    for (extra, needle) in cases {
        let e = parse_scene_str(&scene(extra), dir.path(), "t")
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{extra}: {e}");
    }
}
