//! Validation messages of the two readers: one line naming the file and the place, for bad
//! scenes (DOFs, kinds, sizes, malformed or non-finite JSON, missing fields, the stiffness
//! source, a bad Matrix Market reference) and bad Matrix Market text.

use crate::common;
use crate::scene_support::{assert_has, bits, mm_err, scene, scene_err, C1, K3, MM_HDR};
use penalty_lab::scene::{parse_scene_str, read_matrix_market, read_scene, MAX_DIM};
use std::fs;
use std::path::Path;

#[test]
fn scene_errors_name_the_file() {
    let e = read_scene(Path::new("tests/data/scenes/does-not-exist.scene.json"))
        .unwrap_err()
        .to_string();
    assert_has(&e, &["does-not-exist.scene.json", "cannot read scene file"]);

    let dir = common::tmp_dir("scene-io-errs");
    let path = dir.path().join("x.scene.json");
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
    assert_eq!(s.problem.constraints[0].single_dof().unwrap(), 2);
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
        &[
            "t.scene.json",
            "load vector q (K is 3×3) has 2 entries, expected 3",
        ],
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
    // An object is the Matrix Market form of D (`{"matrix_market": ..., "limits": ...}`).
    let e = scene_err(&scene(K3, "[0, 0, 0]", "{}"));
    assert_has(
        &e,
        &["constraints", "missing required field \"matrix_market\""],
    );
    let e = scene_err(&scene(K3, "[0, 0, 0]", "\"none\""));
    assert_has(&e, &["constraints", "expected an array of constraints"]);
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
    let dir = common::tmp_dir("scene-io-mmref");
    fs::write(
        dir.path().join("K.mtx"),
        format!("{MM_HDR}3 3 2\n1 1 1\n7 2\n"),
    )
    .unwrap();
    let e = parse_scene_str(
        &scene(r#"{"matrix_market": "K.mtx"}"#, "[0, 0, 0]", "[]"),
        dir.path(),
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
    fs::write(dir.path().join("K.mtx"), format!("{MM_HDR}2 2 1\n1 1 1\n")).unwrap();
    let e = parse_scene_str(
        &scene(r#"{"matrix_market": "K.mtx"}"#, "[0, 0, 0]", "[]"),
        dir.path(),
        "s.scene.json",
    )
    .unwrap_err()
    .to_string();
    assert_has(
        &e,
        &[
            "s.scene.json",
            "load vector q (K is 2×2) has 3 entries, expected 2",
        ],
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
