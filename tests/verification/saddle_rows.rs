//! The sparse saddle-point cond₂ route for constraint rows that couple DOFs
//! (`conditioning::saddle::cond2_saddle_rows`) against dense symmetric eigenvalues
//! of the assembled `[K D; Dᵀ 0]` (this code's dense route, and NumPy's SVD where
//! `tests/data/coupled/reference.json` has it): the dense value lies in the certified
//! bracket, widened by the dense solver's own rounding (64·n·ε_mach·cond₂ relative, as in
//! `saddle_cond.rs`), on the inclined plane (two-term rows), the two-body patch test with
//! mortar and one-pass node-to-segment rows, Hertz between two elastic bodies (mortar), the
//! outside references' truss scenes, and single-DOF rows written as rows.

use penalty_lab::conditioning::saddle::{cond2_saddle, cond2_saddle_rows, Row, SCHUR_TEST_MAX};
use penalty_lab::conditioning::{cond2_dense, CondReport, CondRoute};
use penalty_lab::error::Error;
use penalty_lab::model::elasticity::{Grid, Material};
use penalty_lab::model::two_body::{patch, Discretization, TwoBlocks};
use penalty_lab::scene::read_scene;
use penalty_lab::strategy::{self, lagrange, Method, SystemKind};
use penalty_lab::study::contact_bench::BenchConfig;
use penalty_lab::study::hertz::Case;
use penalty_lab::system::{sparse_of_dense, Problem, Stiffness};
use std::path::Path;

/// K in compressed columns, whatever its storage.
fn sparse_k(p: &Problem) -> faer::sparse::SparseColMat<usize, f64> {
    match &p.k {
        Stiffness::Sparse(k) => k.clone(),
        Stiffness::Dense(k) => sparse_of_dense(k.as_ref()),
    }
}

/// Lagrange's active set and its rows.
fn active_rows(p: &Problem) -> (Vec<usize>, Vec<Row>) {
    let s = strategy::solve(p, Method::lagrange()).unwrap();
    let SystemKind::SaddlePoint { active } = s.system else {
        panic!("lagrange returns a saddle point")
    };
    let rows = active
        .iter()
        .map(|&c| p.constraints[c].terms.clone())
        .collect();
    (active, rows)
}

/// The rows route on Lagrange's system of `p`, checked against the dense eigenvalues; returns
/// the report and the dense cond₂.
fn check(p: &Problem, label: &str) -> (CondReport, f64) {
    let (act, rows) = active_rows(p);
    let sparse = cond2_saddle_rows(&sparse_k(p), &rows, SCHUR_TEST_MAX, None).unwrap();
    assert_eq!(sparse.route, CondRoute::SparseSaddleInertia, "{label}");
    let dense = crate::saddle_cond::check(p, &act, &sparse, label);
    let kkt = lagrange::saddle_matrix(p, &act).to_dense();
    let slack = 64.0 * kkt.nrows() as f64 * f64::EPSILON * dense.cond2;
    // The value itself as exact as the dense one: within the contract's width.
    let rel = (sparse.cond2 / dense.cond2 - 1.0).abs();
    assert!(
        rel <= 1e-11f64.max(slack),
        "{label}: cond₂ {:e} vs dense {:e}",
        sparse.cond2,
        dense.cond2
    );
    // |det A| from the route's factors against the dense LU's.
    let det = sparse.log10_det.expect("log10|det A|");
    let lu = faer::linalg::solvers::PartialPivLu::new(kkt.as_ref());
    let dense_det: f64 = (0..kkt.nrows()).map(|i| lu.U()[(i, i)].abs().log10()).sum();
    assert!(
        (det - dense_det).abs() <= 1e-9 * dense_det.abs().max(1.0),
        "{label}: log10|det| {det} vs {dense_det}"
    );
    (sparse, dense.cond2)
}

/// `p` with `rows` as bilateral constraints (limit 0).
fn with_rows(p: &Problem, rows: &[Row]) -> Problem {
    let mut q = p.clone();
    q.constraints = rows
        .iter()
        .map(|t| {
            penalty_lab::system::Constraint::row(
                t.clone(),
                0.0,
                penalty_lab::system::ConstraintKind::Bilateral,
            )
        })
        .collect();
    q
}

fn steel() -> Material {
    Material {
        young: 210e3,
        poisson: 0.3,
    }
}

fn blocks(nx_lower: usize, nx_upper: usize) -> TwoBlocks {
    TwoBlocks::steel_under_aluminium(1.0, (0.6, 0.4), (nx_lower, 3), (nx_upper, 2))
}

#[test]
fn inclined_plane_rows_bracket_the_dense_cond2() {
    let grid = Grid::uniform(1.0, 0.5, 7, 5);
    for theta_deg in [15.0f64, 30.0, 45.0] {
        let ind = penalty_lab::model::inclined::inclined_punch(
            &grid,
            &steel(),
            1e-3,
            theta_deg.to_radians(),
        )
        .unwrap();
        let (r, _) = check(&ind.problem, &format!("inclined {theta_deg}°"));
        assert!(r.bounds_proven, "inclined {theta_deg}°: {r:?}");
    }
}

#[test]
fn two_body_rows_bracket_the_dense_cond2() {
    for (disc, lower, upper) in [
        (Discretization::Mortar, 4, 7),
        (Discretization::Mortar, 3, 5),
        (Discretization::Nts1, 4, 7),
    ] {
        let ind = patch(&blocks(lower, upper), 1e-3, disc).unwrap();
        let (r, _) = check(&ind.problem, &format!("{} {lower}:{upper}", disc.name()));
        assert!(r.bounds_proven, "{}: {r:?}", disc.name());
    }
}

/// Hertz between two elastic bodies, mortar rows (contact_bench's `hertz-two-body` on its
/// coarsest mesh): cond₂ ≈ 1e12–1e13, the regime where the dense route's Kahan bounds are
/// wide.
#[test]
fn hertz_two_body_mortar_rows_bracket_the_dense_cond2() {
    let cfg = BenchConfig::default();
    let grid = cfg.grid(Case::HertzTwoBody, 0.2).unwrap();
    let ind = cfg.scene(Case::HertzTwoBody, &grid, 0.05).unwrap();
    let (r, dense) = check(&ind.problem, "hertz-two-body");
    let (lo, hi) = r.certificate.unwrap().cond2_bounds();
    eprintln!(
        "hertz-two-body h = 0.2: N = {}, cond₂ {:e} (dense {dense:e}), proven {}, width {:.1e}",
        ind.problem.n(),
        r.cond2,
        r.bounds_proven,
        hi / lo - 1.0
    );
    // Proven, and narrower than the contract (max(1e-11, 64·ε·cond₂) ≈ 0.08 here) by far.
    assert!(
        r.bounds_proven && hi / lo - 1.0 <= 1e-11,
        "[{lo:e}, {hi:e}]"
    );
}

/// The outside references (NumPy, `scripts/coupled_reference.py`): cond₂ of Lagrange's
/// saddle point by SVD.
#[test]
fn coupled_reference_scenes_agree_with_numpy() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/coupled");
    let reference: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("reference.json")).unwrap())
            .unwrap();
    let mut checked = 0;
    for s in reference["scenes"].as_array().unwrap() {
        let name = s["scene"].as_str().unwrap();
        let scene = read_scene(&dir.join(name)).unwrap();
        let p = &scene.problem;
        let (_, rows) = active_rows(p);
        if rows.len() >= p.n() || rows.iter().all(|r| r.len() == 1) {
            continue;
        }
        let (r, _) = check(p, name);
        let numpy = s["lagrange"]["cond2"].as_f64().unwrap();
        let slack = 64.0 * (p.n() + rows.len()) as f64 * f64::EPSILON * numpy;
        let (lo, hi) = r.certificate.unwrap().cond2_bounds();
        assert!(
            numpy >= lo * (1.0 - slack) && numpy <= hi * (1.0 + slack),
            "{name}: NumPy cond₂ {numpy:e} outside [{lo:e}, {hi:e}]"
        );
        eprintln!(
            "{name}: cond₂ {:e} (NumPy {numpy:e}), proven {}",
            r.cond2, r.bounds_proven
        );
        checked += 1;
    }
    assert!(
        checked >= 2,
        "only {checked} reference scenes have coupled active rows"
    );
}

/// Single-DOF rows with coefficient 1 through the rows route give the Boolean route's cond₂
/// (both within their brackets); a row scaled by 2.5 scales D's column and changes the
/// spectrum, which the rows route follows (checked against the dense eigenvalues).
#[test]
fn single_dof_rows_agree_with_the_boolean_route() {
    let p = &crate::common::matrices::membranes((20, 30), 1, 5)[0];
    let (act, rows) = active_rows(p);
    let dofs: Vec<usize> = act
        .iter()
        .map(|&c| p.constraints[c].single_dof().unwrap())
        .collect();
    let k = sparse_k(p);
    let boolean = cond2_saddle(&k, &dofs).unwrap();
    let as_rows = cond2_saddle_rows(&k, &rows, SCHUR_TEST_MAX, None).unwrap();
    let (lo, hi) = as_rows.certificate.unwrap().cond2_bounds();
    assert!(
        boolean.cond2 >= lo * (1.0 - 1e-12) && boolean.cond2 <= hi * (1.0 + 1e-12),
        "Boolean cond₂ {:e} outside the rows route's [{lo:e}, {hi:e}]",
        boolean.cond2
    );
    assert!((as_rows.cond2 / boolean.cond2 - 1.0).abs() <= 1e-11);
    check(p, "membrane as rows");
    // One row scaled: a different matrix, the same route.
    let mut scaled = p.clone();
    let c0 = act[0];
    let d0 = scaled.constraints[c0].single_dof().unwrap();
    scaled.constraints[c0].terms = vec![(d0, 2.5)];
    check(&scaled, "membrane, one row ×2.5");
}

#[test]
fn bad_rows_are_refused() {
    let p = &crate::common::matrices::membranes((20, 30), 1, 5)[0];
    let k = sparse_k(p);
    let n = p.n();
    let refuse = |rows: &[Row]| cond2_saddle_rows(&k, rows, SCHUR_TEST_MAX, None).unwrap_err();
    assert!(matches!(refuse(&[]), Error::OutOfRange { .. }));
    assert!(matches!(
        refuse(&[vec![(n, 1.0)]]),
        Error::DofOutOfRange { .. }
    ));
    assert!(matches!(
        refuse(&[vec![(0, 1.0), (0, 2.0)]]),
        Error::Duplicate { .. }
    ));
    assert!(matches!(refuse(&[vec![(0, 0.0)]]), Error::NotFinite { .. }));
    assert!(matches!(
        refuse(&[vec![(0, f64::NAN)]]),
        Error::NotFinite { .. }
    ));
    // Dependent rows: A singular.
    assert!(matches!(
        refuse(&[vec![(0, 1.0), (1, 1.0)], vec![(0, 2.0), (1, 2.0)]]),
        Error::Singular(_)
    ));
    // K itself: a NaN entry is named (both coupled routes), a non-square K refused.
    let rows = [vec![(0, 1.0), (1, 0.5)]];
    let mut bad = k.clone();
    let p = bad.symbolic().col_ptr()[3] + 1;
    bad.val_mut()[p] = f64::NAN;
    let (i, j) = (bad.symbolic().row_idx()[p], 3);
    for e in [
        cond2_saddle_rows(&bad, &rows, SCHUR_TEST_MAX, None).unwrap_err(),
        penalty_lab::conditioning::saddle::null_space_lambda_min(&bad, &rows).unwrap_err(),
    ] {
        match e {
            Error::NotFinite { what } => assert_eq!(what, format!("K[{i}, {j}]")),
            e => panic!("{e}"),
        }
    }
    let wide = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(
        2,
        3,
        &[faer::sparse::Triplet::new(0, 0, 1.0)],
    )
    .unwrap();
    assert!(matches!(
        cond2_saddle_rows(&wide, &[vec![(0, 1.0)]], SCHUR_TEST_MAX, None).unwrap_err(),
        Error::Unsupported { .. }
    ));
}

/// λ_min of K on the null space of Dᵀ (the floor of cond₂ over all penalties for coupled rows,
/// `optimal::cond2_lower_bound`) against a dense computation: the (m+1)-th smallest eigenvalue
/// of `PKP`, `P = I − D(DᵀD)⁻¹Dᵀ` (m zeros on range(D), then K_Z's spectrum); the proven
/// upper bound sits above it by at most a few roundings, and the floor lies below the cond₂
/// of `K + DEDᵀ` for penalties spread over eleven decades.
#[test]
fn the_coupled_floor_is_k_on_the_null_space_of_dt() {
    use nalgebra::{DMatrix, SymmetricEigen};
    use penalty_lab::conditioning::saddle::null_space_lambda_min;
    use penalty_lab::strategy::optimal::cond2_lower_bound;
    let grid = Grid::uniform(1.0, 0.5, 5, 3);
    let inclined =
        penalty_lab::model::inclined::inclined_punch(&grid, &steel(), 1e-3, 0.5).unwrap();
    let mortar = patch(&blocks(3, 5), 1e-3, Discretization::Mortar).unwrap();
    for (label, p) in [("inclined", inclined.problem), ("mortar", mortar.problem)] {
        let rows: Vec<Row> = p.constraints.iter().map(|c| c.terms.clone()).collect();
        let got = null_space_lambda_min(&sparse_k(&p), &rows).unwrap();
        let (n, m) = (p.n(), rows.len());
        let kd = p.k.to_dense();
        let k = DMatrix::from_fn(n, n, |i, j| kd[(i, j)]);
        let mut d = DMatrix::<f64>::zeros(n, m);
        for (c, row) in rows.iter().enumerate() {
            for &(i, a) in row {
                d[(i, c)] = a;
            }
        }
        let g = (d.transpose() * &d).cholesky().unwrap();
        let proj = DMatrix::<f64>::identity(n, n) - &d * g.solve(&d.transpose());
        let pkp = &proj * &k * &proj;
        let pkp = (&pkp + pkp.transpose()) * 0.5;
        let mut ev: Vec<f64> = SymmetricEigen::new(pkp)
            .eigenvalues
            .iter()
            .copied()
            .collect();
        ev.sort_by(f64::total_cmp);
        let dense = ev[m];
        let scale = ev[n - 1];
        // The dense value's own rounding: 64·n·ε·λ_max(K).
        let slack = 64.0 * n as f64 * f64::EPSILON * scale;
        assert!(
            got.upper >= dense - slack && got.upper <= dense * (1.0 + 1e-8) + slack,
            "{label}: upper {:e} vs dense λ_min(K_Z) {dense:e} (slack {slack:e})",
            got.upper
        );
        assert!((got.estimate / dense - 1.0).abs() <= 1e-8 + slack / dense);
        // The floor against cond₂(K + DEDᵀ) for penalties over eleven decades.
        let floor = cond2_lower_bound(&p).unwrap();
        for e in [1e-3, 1.0, 1e3, 1e6, 1e8] {
            let eps: Vec<f64> = (0..m)
                .map(|c| e * kd[(c, c)] * (1.0 + c as f64 / 7.0))
                .collect();
            let a = p.penalized_k(&eps).to_dense();
            let cond = cond2_dense(a.as_ref(), true).unwrap().cond2;
            assert!(
                floor <= cond * (1.0 + 64.0 * n as f64 * f64::EPSILON),
                "{label}: floor {floor:e} above cond₂ {cond:e} at ε = {e:e}·k"
            );
        }
        eprintln!(
            "{label}: λ_min(K_Z) {dense:e}, upper {:e}, floor {floor:e}",
            got.upper
        );
    }
}

/// Seeded random rows that overlap (2–4 terms on nearby DOFs, coefficients of either sign over
/// four decades,
/// rows sharing DOFs as mortar rows do) on membranes: the rows route against the dense
/// eigenvalues of the assembled matrix, every bracket holding.
#[test]
fn random_overlapping_rows_bracket_the_dense_cond2() {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    let mut proven = 0;
    let problems = crate::common::matrices::membranes((12, 18), 6, 31);
    for (s, p) in problems.iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + s as u64);
        let n = p.n();
        let m = rng.random_range(3..=n / 8);
        let mut rows: Vec<Row> = Vec::new();
        for _ in 0..m {
            let base = rng.random_range(0..n - 8);
            let terms = rng.random_range(2..=4);
            let mut row: Row = Vec::new();
            while row.len() < terms {
                let d = base + rng.random_range(0..8);
                if row.iter().all(|&(e, _)| e != d) {
                    // Graded: coefficients over four decades (rows of very different scales).
                    let a: f64 = 10f64.powf(rng.random_range(-2.0..2.0));
                    row.push((d, if rng.random_bool(0.3) { -a } else { a }));
                }
            }
            rows.push(row);
        }
        let k = sparse_k(p);
        let label = format!("membrane {s}: N = {n}, m = {m}");
        let r = match cond2_saddle_rows(&k, &rows, SCHUR_TEST_MAX, None) {
            Ok(r) => r,
            // Random rows may be dependent (the same few DOFs): refused, never a wrong number.
            Err(Error::Singular(e)) => {
                eprintln!("{label}: refused ({e})");
                continue;
            }
            Err(e) => panic!("{label}: {e}"),
        };
        let q = with_rows(p, &rows);
        let all: Vec<usize> = (0..m).collect();
        let kkt = lagrange::saddle_matrix(&q, &all).to_dense();
        let dense = cond2_dense(kkt.as_ref(), true).unwrap();
        let slack = 64.0 * (n + m) as f64 * f64::EPSILON * dense.cond2;
        let (lo, hi) = r.certificate.unwrap().cond2_bounds();
        assert!(
            dense.cond2 >= lo * (1.0 - slack) && dense.cond2 <= hi * (1.0 + slack),
            "{label}: dense {:e} outside [{lo:e}, {hi:e}]",
            dense.cond2
        );
        assert!(
            (r.cond2 / dense.cond2 - 1.0).abs() <= 1e-11f64.max(slack),
            "{label}"
        );
        eprintln!(
            "{label}: cond₂ {:e}, proven {}, width {:.1e}",
            r.cond2,
            r.bounds_proven,
            hi / lo - 1.0
        );
        proven += usize::from(r.bounds_proven);
    }
    assert!(proven >= 4, "only {proven} of 6 proven");
}

/// Nearly dependent rows (two rows 1e-6 apart, as two-pass rows are where nodes almost line
/// up): cond₂ near 1e14, the rows route's bracket still holds the dense value; exactly
/// dependent ones are refused.
#[test]
fn nearly_dependent_rows_stay_bracketed() {
    let p = &crate::common::matrices::membranes((12, 12), 1, 9)[0];
    let k = sparse_k(p);
    let n = p.n();
    for gap in [1e-3, 1e-6] {
        let rows: Vec<Row> = vec![
            vec![(20, 1.0), (21, 1.0)],
            vec![(20, 1.0), (21, 1.0 + gap)],
            vec![(60, 0.6), (61, -0.8)],
            vec![(61, 1.0), (62, 0.5), (80, -0.5)],
        ];
        let r = cond2_saddle_rows(&k, &rows, SCHUR_TEST_MAX, None).unwrap();
        let q = with_rows(p, &rows);
        let kkt = lagrange::saddle_matrix(&q, &[0, 1, 2, 3]).to_dense();
        let dense = cond2_dense(kkt.as_ref(), true).unwrap();
        let slack = 64.0 * (n + 4) as f64 * f64::EPSILON * dense.cond2;
        let (lo, hi) = r.certificate.unwrap().cond2_bounds();
        eprintln!(
            "gap {gap:e}: cond₂ {:e} (dense {:e}), proven {}, [{lo:e}, {hi:e}]",
            r.cond2, dense.cond2, r.bounds_proven
        );
        assert!(
            dense.cond2 >= lo * (1.0 - slack) && dense.cond2 <= hi * (1.0 + slack),
            "gap {gap:e}: dense {:e} outside [{lo:e}, {hi:e}]",
            dense.cond2
        );
    }
    let same = vec![vec![(20, 1.0), (21, 1.0)], vec![(20, 2.0), (21, 2.0)]];
    assert!(matches!(
        cond2_saddle_rows(&k, &same, SCHUR_TEST_MAX, None),
        Err(Error::Singular(_))
    ));
}

/// Found by a referee: rows of very different scales are not dependent (rows 1e8·e₀ and e₁ on
/// K = I: cond₂ = 1.618e8, refused as dependent before the pivots were normalized by the rows'
/// norms); K with one triangle stored is refused (it was "proven" about another matrix); a
/// zero term still has its DOF checked.
#[test]
fn row_scales_and_half_stored_k() {
    use faer::sparse::{SparseColMat, Triplet};
    let eye = SparseColMat::<usize, f64>::try_new_from_triplets(
        3,
        3,
        &[
            Triplet::new(0, 0, 1.0),
            Triplet::new(1, 1, 1.0),
            Triplet::new(2, 2, 1.0),
        ],
    )
    .unwrap();
    let rows: Vec<Row> = vec![vec![(0, 1e8)], vec![(1, 1.0)]];
    let r = cond2_saddle_rows(&eye, &rows, SCHUR_TEST_MAX, None).unwrap();
    // Exact: the blocks [1 1e8; 1e8 0], [1 1; 1 0] and 1: σ_max = (1 + √(1 + 4e16))/2,
    // σ_min = (√5 − 1)/2.
    let exact = (1.0 + (1.0f64 + 4e16).sqrt()) / 2.0 / ((5.0f64.sqrt() - 1.0) / 2.0);
    let (lo, hi) = r.certificate.unwrap().cond2_bounds();
    assert!(
        lo <= exact * (1.0 + 1e-15) && exact <= hi * (1.0 + 1e-15),
        "[{lo:e}, {hi:e}]"
    );
    assert!(
        (r.cond2 / exact - 1.0).abs() <= 1e-12,
        "{:e} vs {exact:e}",
        r.cond2
    );
    let lower = SparseColMat::<usize, f64>::try_new_from_triplets(
        3,
        3,
        &[
            Triplet::new(0, 0, 2.0),
            Triplet::new(1, 0, -1.0),
            Triplet::new(1, 1, 2.0),
            Triplet::new(2, 1, -1.0),
            Triplet::new(2, 2, 2.0),
        ],
    )
    .unwrap();
    let half = cond2_saddle_rows(&lower, &[vec![(0, 1.0), (2, 1.0)]], SCHUR_TEST_MAX, None);
    assert!(matches!(half, Err(Error::Unsupported { .. })), "{half:?}");
    let zero_out = cond2_saddle_rows(&eye, &[vec![(0, 1.0), (7, 0.0)]], SCHUR_TEST_MAX, None);
    assert!(
        matches!(zero_out, Err(Error::DofOutOfRange { .. })),
        "{zero_out:?}"
    );
}
