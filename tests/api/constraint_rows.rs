//! Constraint rows: `{"terms": [[d, a], ...]}` beside `{"dof": d}` in scene
//! files, their checks and messages, the bit-for-bit round trip, and a row's algebra
//! (`d_cᵀu`, `x += v d_c`, `d_cᵀKd_c/‖d_c‖⁴`, `e d_c d_cᵀ`) on a hand-computed example.

use crate::common;
use crate::scene_support::{assert_has, scene, scene_err, K3};
use penalty_lab::scene::{parse_scene_str, read_scene, write_scene};
use penalty_lab::strategy::{self, Method};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use std::path::Path;

fn k3() -> Stiffness {
    Stiffness::from_rows(&[
        vec![2.0, -1.0, 0.0],
        vec![-1.0, 2.0, -1.0],
        vec![0.0, -1.0, 2.0],
    ])
    .unwrap()
}

#[test]
fn terms_read_as_rows_and_one_unit_term_is_the_dof_form() {
    let s = parse_scene_str(
        &scene(
            K3,
            "[0, 1, 0]",
            r#"[{"terms": [[0, 0.6], [2, -0.8]], "limit": 0.1, "kind": "upper"},
                {"terms": [[1, 1]], "limit": 0.5, "kind": "lower"}]"#,
        ),
        Path::new("."),
        "t",
    )
    .unwrap();
    let c = &s.problem.constraints;
    assert_eq!(c[0].terms, vec![(0, 0.6), (2, -0.8)]);
    assert_eq!(c[0].single_dof(), None);
    assert_eq!(c[1], Constraint::on_dof(1, 0.5, ConstraintKind::Lower));
}

#[test]
fn bad_rows_are_one_line_errors_naming_the_constraint() {
    let cases: [(&str, &[&str]); 7] = [
        (
            r#"[{"dof": 0, "terms": [[1, 1]], "limit": 0, "kind": "upper"}]"#,
            &["constraints[0]", "both \"dof\" and \"terms\""],
        ),
        (
            r#"[{"limit": 0, "kind": "upper"}]"#,
            &["constraints[0]", "neither \"dof\" nor \"terms\""],
        ),
        (
            r#"[{"terms": [], "limit": 0, "kind": "upper"}]"#,
            &["constraint 0", "no terms"],
        ),
        (
            r#"[{"terms": [[0, 1], [0, 2]], "limit": 0, "kind": "upper"}]"#,
            &["constraint 0", "DOF 0 appears twice"],
        ),
        (
            r#"[{"terms": [[0, 0], [1, 0.0]], "limit": 0, "kind": "upper"}]"#,
            &["constraint 0", "every coefficient is zero"],
        ),
        (
            r#"[{"terms": [[0, 1], [3, 1]], "limit": 0, "kind": "upper"}]"#,
            &["constraint 0", "DOF 3 is out of range"],
        ),
        (
            r#"[{"terms": [[0, 1, 2]], "limit": 0, "kind": "upper"}]"#,
            &[
                "constraints[0].terms[0]",
                "pair [dof, coefficient]",
                "more than two",
            ],
        ),
    ];
    for (cons, words) in cases {
        let e = scene_err(&scene(K3, "[0, 0, 0]", cons));
        assert_has(&e, words);
        assert!(!e.contains('\n'), "one line: {e}");
    }
    let e = scene_err(&scene(
        K3,
        "[0, 0, 0]",
        r#"[{"terms": [[0, 1e999]], "limit": 0, "kind": "upper"}]"#,
    ));
    assert_has(&e, &["line 1", "1e999 is not finite"]);
}

#[test]
fn rows_round_trip_bit_for_bit() {
    let dir = common::tmp_dir("constraint-rows");
    let cons = vec![
        Constraint::row(
            vec![(0, 0.1 + 0.2), (2, -1.0 / 3.0)],
            -0.0,
            ConstraintKind::Upper,
        ),
        Constraint::on_dof(1, 0.3, ConstraintKind::Bilateral),
        Constraint::row(vec![(2, 2.5)], 1e-300, ConstraintKind::Lower),
    ];
    let p = Problem::new(k3(), vec![0.0, 1.0, -2.0], cons.clone()).unwrap();
    let path = dir.path().join("rows.scene.json");
    write_scene(&path, "rows", &p, None, 100).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("\"terms\"") && text.contains("\"dof\": 1"),
        "{text}"
    );
    let back = read_scene(&path).unwrap().problem.constraints;
    assert_eq!(back.len(), cons.len());
    for (a, b) in back.iter().zip(&cons) {
        assert_eq!(a.kind, b.kind);
        assert_eq!(a.limit.to_bits(), b.limit.to_bits());
        let bits = |c: &Constraint| -> Vec<(usize, u64)> {
            c.terms.iter().map(|&(d, v)| (d, v.to_bits())).collect()
        };
        assert_eq!(bits(a), bits(b));
    }
}

#[test]
fn a_rows_algebra_by_hand() {
    // d = (0.6, 0, −0.8): ‖d‖ = 1; dᵀKd = 0.36·2 + 0.64·2 − 2·0.6·0.8·K_02 (= 0) = 2.
    let c = Constraint::row(vec![(0, 0.6), (2, -0.8)], 0.1, ConstraintKind::Upper);
    let k = k3();
    let u = [1.0, 5.0, 2.0];
    assert!((c.value(&u) - (0.6 - 1.6)).abs() <= 4.0 * f64::EPSILON);
    assert!((c.gap(&u) - (0.6 - 1.6 - 0.1)).abs() <= 4.0 * f64::EPSILON);
    assert!((c.stiffness(&k) - 2.0).abs() <= 8.0 * f64::EPSILON);
    let mut x = [0.0; 3];
    c.scatter(&mut x, 2.0);
    assert_eq!(x, [1.2, 0.0, -1.6]);
    // Scaling the row by 2 scales its stiffness by 2²/2⁴: the penalty's units follow the row.
    let c2 = Constraint::row(vec![(0, 1.2), (2, -1.6)], 0.2, ConstraintKind::Upper);
    assert!((c2.stiffness(&k) - 0.5).abs() <= 8.0 * f64::EPSILON);
    let outer: Vec<(usize, usize, f64)> = c.outer(10.0).collect();
    assert_eq!(outer.len(), 4);
    for &(i, j, v) in &outer {
        let (a, b) = (
            if i == 0 { 0.6 } else { -0.8 },
            if j == 0 { 0.6 } else { -0.8 },
        );
        assert_eq!(v, 10.0 * (a * b), "({i}, {j})");
    }
    // The penalized matrix gains the coupled entry K_02 += ε·0.6·(−0.8), symmetric bit for bit.
    let p = Problem::new(k, vec![0.0, 0.0, 1.0], vec![c]).unwrap();
    let a = p.penalized_k(&[10.0]);
    assert_eq!(a.get(0, 2), 10.0 * (0.6 * -0.8));
    assert_eq!(a.get(0, 2).to_bits(), a.get(2, 0).to_bits());
    assert!(a.is_symmetric());
}

/// The cond₂ floor over all E for a coupled row is `λ_max(K)/λ_min(ZᵀKZ)` (Z an orthonormal
/// basis of the null space of Dᵀ, here by hand: e₂ and (0.8, 0, 0.6)); every rule solves a
/// coupled row, `optimal` too, its report carrying that floor below its cond₂.
#[test]
fn coupled_rows_get_every_rule_and_the_floor() {
    use nalgebra::{DMatrix, SymmetricEigen};
    let c = Constraint::row(vec![(0, 0.6), (2, -0.8)], 0.1, ConstraintKind::Upper);
    let p = Problem::new(k3(), vec![0.0, 0.0, 1.0], vec![c]).unwrap();
    let kd = p.k.to_dense();
    let k = DMatrix::from_fn(3, 3, |i, j| kd[(i, j)]);
    let z = DMatrix::from_row_slice(3, 2, &[0.0, 0.8, 1.0, 0.0, 0.0, 0.6]);
    let kz = z.transpose() * &k * &z;
    let lmin = SymmetricEigen::new(kz).eigenvalues.min();
    let lmax = SymmetricEigen::new(k).eigenvalues.max();
    let floor = strategy::optimal::cond2_lower_bound(&p).unwrap();
    assert!(
        floor <= lmax / lmin && floor >= lmax / lmin * (1.0 - 1e-12),
        "floor {floor:e} vs λ_max(K)/λ_min(K_Z) {:e}",
        lmax / lmin
    );
    let opt = strategy::solve(&p, Method::optimal(0.01)).unwrap();
    assert!(opt.max_penetration <= 0.01);
    let report = opt.stats.optimal.unwrap();
    assert_eq!(report.cond2_lower_bound, floor);
    for m in [
        Method::constant(10.0),
        Method::scaled(1.0),
        Method::spring(0.01),
        Method::paper(0.01),
        Method::condensed(0.01),
        Method::lagrange(),
    ] {
        let sol = strategy::solve(&p, m).unwrap();
        assert!(sol.u.iter().all(|v| v.is_finite()));
    }
}

/// D as a Matrix Market file (row c = constraint c) reads as the same rows as `terms`, and its
/// mistakes are one-line errors naming the place.
#[test]
fn rows_from_a_matrix_market_d() {
    let dir = common::tmp_dir("constraint-rows-mtx");
    let d = "%%MatrixMarket matrix coordinate real general\n% two rows\n2 3 3\n1 1 0.6\n1 3 -0.8\n2 2 1\n";
    std::fs::write(dir.path().join("D.mtx"), d).unwrap();
    let write = |cons: &str| {
        let path = dir.path().join("t.scene.json");
        std::fs::write(&path, scene(K3, "[0, 1, 0]", cons)).unwrap();
        read_scene(&path)
    };
    let s =
        write(r#"{"matrix_market": "D.mtx", "limits": [0.1, 0.5], "kinds": ["upper", "lower"]}"#)
            .unwrap();
    let c = &s.problem.constraints;
    assert_eq!(
        c[0],
        Constraint::row(vec![(0, 0.6), (2, -0.8)], 0.1, ConstraintKind::Upper)
    );
    assert_eq!(c[1], Constraint::on_dof(1, 0.5, ConstraintKind::Lower));
    let s = write(r#"{"matrix_market": "D.mtx", "limits": [0.1, 0.5], "kind": "upper"}"#).unwrap();
    assert!(s
        .problem
        .constraints
        .iter()
        .all(|c| c.kind == ConstraintKind::Upper));
    for (cons, words) in [
        (
            r#"{"matrix_market": "D.mtx", "limits": [0.1], "kind": "upper"}"#,
            &["constraints.limits", "1 limits for the 2 rows"][..],
        ),
        (
            r#"{"matrix_market": "D.mtx", "limits": [0.1, 0.5]}"#,
            &["exactly one of \"kind\"", "\"kinds\""][..],
        ),
        (
            r#"{"matrix_market": "D.mtx", "limits": [0.1, 0.5], "kinds": ["upper"]}"#,
            &["constraints.kinds", "1 kinds for the 2 rows"][..],
        ),
        (
            r#"{"matrix_market": "missing.mtx", "limits": [0.1, 0.5], "kind": "upper"}"#,
            &["constraints.matrix_market", "missing.mtx"][..],
        ),
        (
            r#"{"matrix_market": "D.mtx", "limits": [0.1, 0.5], "kind": "upper", "x": 1}"#,
            &["constraints: unknown key \"x\"", "the rows of D"][..],
        ),
    ] {
        let e = write(cons).unwrap_err().to_string();
        assert_has(&e, words);
        assert!(!e.contains('\n'), "one line: {e}");
    }
    // A D whose width is not N, and a row given one DOF twice.
    std::fs::write(
        dir.path().join("D.mtx"),
        "%%MatrixMarket matrix coordinate real general\n1 4 1\n1 4 1\n",
    )
    .unwrap();
    let e = write(r#"{"matrix_market": "D.mtx", "limits": [0], "kind": "upper"}"#)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["D has 4 columns but K is 3×3"]);
    std::fs::write(
        dir.path().join("D.mtx"),
        "%%MatrixMarket matrix coordinate real general\n1 3 2\n1 2 1\n1 2 1\n",
    )
    .unwrap();
    let e = write(r#"{"matrix_market": "D.mtx", "limits": [0], "kind": "upper"}"#)
        .unwrap_err()
        .to_string();
    assert_has(&e, &["constraint 0", "DOF 1 appears twice"]);
}

/// Edge cases: a zero coefficient is no term (the row keeps its Boolean
/// routes); a `symmetric` D.mtx is refused rather than mirrored; d_cᵀKd_c/‖d_c‖⁴ does not
/// overflow for a row scaled by 1e90 (it scales by 1e-180, exactly as the formula says).
#[test]
fn zeros_symmetric_d_and_huge_rows() {
    let row = Constraint::row(
        vec![(1, 1.0), (2, -0.0), (0, 0.0)],
        0.5,
        ConstraintKind::Upper,
    );
    assert_eq!(row, Constraint::on_dof(1, 0.5, ConstraintKind::Upper));
    let dir = common::tmp_dir("constraint-rows-sym");
    std::fs::write(
        dir.path().join("D.mtx"),
        "%%MatrixMarket matrix coordinate real symmetric\n3 3 2\n1 1 1\n3 1 -1\n",
    )
    .unwrap();
    let path = dir.path().join("t.scene.json");
    std::fs::write(
        &path,
        scene(
            K3,
            "[0, 1, 0]",
            r#"{"matrix_market": "D.mtx", "limits": [0, 0, 0], "kind": "upper"}"#,
        ),
    )
    .unwrap();
    let e = read_scene(&path).unwrap_err().to_string();
    assert_has(&e, &["D.mtx", "line 1", "general", "symmetric"]);
    let k = k3();
    let unit = Constraint::row(vec![(0, 1.0), (2, -1.0)], 0.0, ConstraintKind::Upper);
    let huge = Constraint::row(vec![(0, 1e90), (2, -1e90)], 0.0, ConstraintKind::Upper);
    let (a, b) = (unit.stiffness(&k), huge.stiffness(&k));
    assert!(b > 0.0 && b.is_finite(), "{b:e}");
    assert!((b / (a * 1e-180) - 1.0).abs() <= 1e-14, "{a:e} {b:e}");
}

/// The barrier's start on rows that share a DOF (`u0 + u1 ≥ 1`, `−u1 + u2 ≥ 1`, K = 2I,
/// q = 0): one pass of projections leaves the first row violated; the repeated sweep finds a
/// strictly feasible start, and the barrier's solution keeps both gaps open.
#[test]
fn barrier_starts_feasible_on_rows_that_share_a_dof() {
    let k = Stiffness::from_rows(&[
        vec![2.0, 0.0, 0.0],
        vec![0.0, 2.0, 0.0],
        vec![0.0, 0.0, 2.0],
    ])
    .unwrap();
    let rows = vec![
        Constraint::row(vec![(0, 1.0), (1, 1.0)], 1.0, ConstraintKind::Lower),
        Constraint::row(vec![(1, -1.0), (2, 1.0)], 1.0, ConstraintKind::Lower),
    ];
    let p = Problem::new(k, vec![0.0; 3], rows).unwrap();
    let s = strategy::solve(&p, Method::barrier(0.1)).unwrap();
    for c in &p.constraints {
        assert!(c.gap(&s.u) > 0.0, "{:?}: gap {}", c.terms, c.gap(&s.u));
    }
    let l = strategy::solve(&p, Method::lagrange()).unwrap();
    // Lagrange's KKT point is u = (1, 0, 1) (hand-solved); the barrier lies within d̂ of it.
    for (a, b) in l.u.iter().zip([1.0, 0.0, 1.0]) {
        assert!((a - b).abs() <= 1e-12, "{:?}", l.u);
    }
    for (a, b) in s.u.iter().zip(&l.u) {
        assert!((a - b).abs() <= 0.1, "{:?} vs {:?}", s.u, l.u);
    }
}

/// A band narrower than d̂ (a reviewer's scene): `u0 − u1 ≤ 1` and `u0 − u1 ≥ 0.9` with d̂ = 0.5,
/// so no point is d̂/4 from both rows; the start's margin halves until one lies strictly
/// inside, and the barrier's solution keeps both gaps open. The load pulls u0 − u1 towards
/// 10, so Lagrange sits on the upper row.
#[test]
fn barrier_starts_inside_a_band_narrower_than_dhat() {
    let k = Stiffness::from_rows(&[vec![2.0, -1.0], vec![-1.0, 2.0]]).unwrap();
    let rows = vec![
        Constraint::row(vec![(0, 1.0), (1, -1.0)], 1.0, ConstraintKind::Upper),
        Constraint::row(vec![(0, 1.0), (1, -1.0)], 0.9, ConstraintKind::Lower),
    ];
    let p = Problem::new(k, vec![30.0, -30.0], rows).unwrap();
    let s = strategy::solve(&p, Method::barrier(0.5)).unwrap();
    let slack = s.u[0] - s.u[1];
    assert!(slack > 0.9 && slack < 1.0, "u0 − u1 = {slack}");
    let l = strategy::solve(&p, Method::lagrange()).unwrap();
    assert!((l.u[0] - l.u[1] - 1.0).abs() <= 1e-12, "{:?}", l.u);
    assert!(
        1.0 - slack <= 0.5,
        "the barrier lies within d̂ of the upper row: {slack}"
    );
}

/// Three bilateral rows of which the third is 0.1·(first) + ⅔·(second) to rounding (a
/// reviewer's scene): `S = DᵀK⁻¹D` is singular, Lagrange refuses the saddle point, and
/// `condensed` errors naming dependent rows (not only that its active set did not converge).
#[test]
fn dependent_rows_are_named_by_condensed() {
    let k = Stiffness::from_rows(&[
        vec![4.0, -1.0, 0.0, 0.0],
        vec![-1.0, 4.0, -1.0, 0.0],
        vec![0.0, -1.0, 4.0, -1.0],
        vec![0.0, 0.0, -1.0, 4.0],
    ])
    .unwrap();
    let b = ConstraintKind::Bilateral;
    let rows = vec![
        Constraint::row(vec![(0, 1.0), (1, 1.0 / 3.0)], 0.2, b),
        Constraint::row(vec![(1, 1.0), (2, 0.3)], 0.3, b),
        Constraint::row(
            vec![(0, 0.1), (1, 0.7), (2, 0.19999999999999998)],
            0.21999999999999997,
            b,
        ),
    ];
    let p = Problem::new(k, vec![1.0; 4], rows).unwrap();
    assert!(strategy::solve(&p, Method::lagrange()).is_err());
    let e = strategy::solve(&p, Method::condensed(1e-3))
        .unwrap_err()
        .to_string();
    assert!(e.contains("dependent"), "{e}");
}
