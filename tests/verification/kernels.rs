//! The kernels the sweep's speed rests on, against independent implementations: the
//! one-vector simplicial solve and the cached-pattern factorization (`linalg`: permutation
//! applied once, row structure precomputed) against faer's own sparse Cholesky, bit for bit
//! (on the sweep's families and on random patterns); the one-pass sparse symmetry check against the
//! dense one; the preferred-storage scene reader against reading then converting.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::linalg::{DiagonalPattern, Factorization};
use penalty_lab::model::membrane;
use penalty_lab::scene::{read_scene, read_scene_preferred, write_scene_as, Storage};
use penalty_lab::system::{Problem, Stiffness};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Sparse SPD test matrices: a 5-point membrane (AMD fill) and the generated beams (banded).
fn spd_matrices() -> Vec<(String, SparseColMat<usize, f64>)> {
    let mut out = Vec::new();
    if let Stiffness::Sparse(m) = membrane::stiffness(20, 1.0).unwrap() {
        out.push(("membrane 400".to_string(), m));
    }
    let cfg = GeneratorConfig::default();
    for i in 0..3 {
        let g = generate(Family::Beam, i, 5, &cfg).unwrap();
        if let Stiffness::Sparse(m) = g.problem.in_preferred_storage().k {
            out.push((g.name, m));
        }
    }
    assert!(out.len() >= 3, "the test needs sparse matrices");
    out
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i * 7919) % 113) as f64 / 113.0 - 0.4)
        .collect()
}

/// faer's own solve of `a x = b`: `sp_cholesky` (the same symbolic defaults) and `Solve`.
fn faer_solve(a: &SparseColMat<usize, f64>, b: &[f64]) -> Vec<f64> {
    let llt = a.sp_cholesky(Side::Lower).expect("SPD");
    let x = llt.solve(Mat::from_fn(b.len(), 1, |i, _| b[i]));
    (0..b.len()).map(|i| x[(i, 0)]).collect()
}

fn same_bits(x: &[f64], y: &[f64]) -> bool {
    x.len() == y.len() && x.iter().zip(y).all(|(a, b)| a.to_bits() == b.to_bits())
}

#[test]
fn one_vector_solve_is_faers_solve_bit_for_bit() {
    for (name, a) in spd_matrices() {
        let f = Factorization::new(&Stiffness::Sparse(a.clone()), true).unwrap();
        let b = rhs(a.nrows());
        let ours = f.solve(&b);
        let theirs = faer_solve(&a, &b);
        assert!(
            same_bits(&ours, &theirs),
            "{name}: the simplicial one-vector solve differs from faer's"
        );
        // And the multi-right-hand-side path of the same factor (faer's solve).
        let mut m = Mat::from_fn(b.len(), 1, |i, _| b[i]);
        f.solve_mat_in_place(m.as_mut());
        assert!(
            (0..b.len()).all(|i| m[(i, 0)].to_bits() == ours[i].to_bits()),
            "{name}"
        );
    }
}

#[test]
fn shifted_factorizations_from_the_cached_permutation_are_faers() {
    for (name, a) in spd_matrices() {
        let pattern = DiagonalPattern::new(&a).unwrap();
        let b = rhs(a.nrows());
        for shift in [0.0, 1e-3, 0.5] {
            let mut v = pattern.values.clone();
            for &p in pattern.diag.iter() {
                v[p] += shift;
            }
            let ours = pattern.factor(&v).expect("SPD");
            let mut x = b.clone();
            ours.solve_vec_in_place(&mut x);
            let shifted = SparseColMat::new((*pattern.pattern).clone(), v);
            let theirs = faer_solve(&shifted, &b);
            assert!(
                same_bits(&x, &theirs),
                "{name}, shift {shift}: factor differs from faer's"
            );
        }
        // Not positive definite: refused on both paths.
        let mut v: Vec<f64> = pattern.values.iter().map(|x| -x).collect();
        v[pattern.diag[0]] -= 1.0;
        assert!(pattern.factor(&v).is_none(), "{name}: −A is not SPD");
    }
}

/// The precomputed-row-structure factorization on seeded random sparsity patterns (random
/// graphs, so AMD orderings and elimination trees of every shape): faer's factor bit for
/// bit, and a shift past λ_min refused on both paths.
#[test]
fn random_patterns_factor_as_faer_does() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    for case in 0..60 {
        let n = rng.random_range(1..90);
        let density = rng.random_range(0.01..0.3);
        let mut t = Vec::new();
        let mut row_sum = vec![0.0f64; n];
        for j in 0..n {
            for i in j + 1..n {
                if rng.random_bool(density) {
                    let v: f64 = rng.random_range(-1.0..1.0);
                    t.push(Triplet::new(i, j, v));
                    t.push(Triplet::new(j, i, v));
                    row_sum[i] += v.abs();
                    row_sum[j] += v.abs();
                }
            }
        }
        for (i, r) in row_sum.iter().enumerate() {
            t.push(Triplet::new(i, i, r + rng.random_range(0.01..1.0)));
        }
        let a = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let pattern = DiagonalPattern::new(&a).unwrap();
        let b = rhs(n);
        let ours = pattern
            .factor(&pattern.values)
            .expect("diagonally dominant");
        let mut x = b.clone();
        ours.solve_vec_in_place(&mut x);
        assert!(same_bits(&x, &faer_solve(&a, &b)), "case {case} (n {n})");
        // Past the Gershgorin bound: not positive definite.
        let big = row_sum.iter().fold(0.0f64, |m, r| m.max(2.0 * r + 1.0));
        let mut v = pattern.values.clone();
        for &p in pattern.diag.iter() {
            v[p] -= big;
        }
        assert!(
            pattern.factor(&v).is_none(),
            "case {case}: A − σI with σ > λ_max"
        );
    }
}

#[test]
fn one_pass_symmetry_agrees_with_the_dense_check() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    for case in 0..300 {
        let n = rng.random_range(1..9);
        let mut t = Vec::new();
        for j in 0..n {
            for i in j..n {
                if i == j || rng.random_bool(0.4) {
                    let v: f64 = rng.random_range(-2.0..2.0);
                    t.push(Triplet::new(i, j, v));
                    if i != j {
                        t.push(Triplet::new(j, i, v));
                    }
                }
            }
        }
        // Break it in one of several ways (or not).
        match case % 5 {
            1 if !t.is_empty() => {
                let k = rng.random_range(0..t.len());
                t[k].val += 1e-3; // one mirror off
            }
            2 => {
                let (i, j) = (rng.random_range(0..n), rng.random_range(0..n));
                if i != j && !t.iter().any(|e| e.row == i && e.col == j) {
                    t.push(Triplet::new(i, j, 0.5)); // an entry without a mirror
                }
            }
            3 => {
                let (i, j) = (rng.random_range(0..n), rng.random_range(0..n));
                if i != j && !t.iter().any(|e| e.row == i && e.col == j) {
                    t.push(Triplet::new(i, j, 0.0)); // an explicit zero without a mirror
                }
            }
            4 if !t.is_empty() => {
                let k = rng.random_range(0..t.len());
                t[k].val *= 1.0 + 2.0 * f64::EPSILON; // within the tolerance
            }
            _ => {}
        }
        let s = Stiffness::Sparse(SparseColMat::try_new_from_triplets(n, n, &t).unwrap());
        let d = Stiffness::Dense(s.to_dense());
        assert_eq!(s.is_symmetric(), d.is_symmetric(), "case {case}: {t:?}");
    }
}

#[test]
fn preferred_reader_is_reading_then_converting() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = GeneratorConfig {
        beam_elements: (3, 30),
        membrane_side: (4, 9),
        ..GeneratorConfig::default()
    };
    let mut problems: Vec<(String, Problem)> = Vec::new();
    for family in [Family::Beam, Family::Membrane, Family::Spectrum] {
        for i in 0..3 {
            let g = generate(family, i, 3, &cfg).unwrap();
            problems.push((g.name, g.problem));
        }
    }
    // A dense K with −0.0 entries (kept by the dense reader, dropped by the conversion).
    let (_, p) = &problems[1];
    let mut k = p.k.to_dense();
    let n = k.nrows();
    for j in 0..n {
        for i in 0..n {
            if k[(i, j)] == 0.0 && (i + j) % 3 == 0 {
                k[(i, j)] = -0.0;
            }
        }
    }
    problems.push((
        "negative-zeros".into(),
        Problem::new(Stiffness::Dense(k), p.q.clone(), p.constraints.clone()).unwrap(),
    ));
    let entries = |k: &Stiffness| {
        let mut e = Vec::new();
        k.for_each_entry(|i, j, v| e.push((i, j, v.to_bits())));
        e
    };
    let mut sparse_seen = false;
    for (name, p) in &problems {
        let path = dir.path().join(format!("{name}.scene.json"));
        write_scene_as(&path, name, p, None, Storage::Dense).unwrap();
        let direct = read_scene_preferred(&path).unwrap().problem;
        let converted = read_scene(&path).unwrap().problem.in_preferred_storage();
        assert_eq!(direct.k.is_sparse(), converted.k.is_sparse(), "{name}");
        assert_eq!(entries(&direct.k), entries(&converted.k), "{name}");
        sparse_seen |= direct.k.is_sparse();
    }
    assert!(sparse_seen, "some scene is stored sparse");
}

/// `DiagonalPattern::new` reads A the same from compact storage and from storage whose
/// columns start past position 0 (slack entries before, never read): the same pattern,
/// values and diagonal positions; on the sweep's matrices (every diagonal stored, the copy
/// of the whole arrays) and with a diagonal missing (the entry-by-entry path).
#[test]
fn diagonal_pattern_reads_a_whatever_its_storage() {
    use faer::sparse::SymbolicSparseColMat;
    let mut cases = spd_matrices();
    // A diagonal entry missing: column 1 without (1, 1).
    let t: Vec<Triplet<usize, usize, f64>> = [(0, 0, 4.0), (1, 0, 1.0), (0, 1, 1.0), (2, 2, 3.0)]
        .map(|(r, c, v)| Triplet::new(r, c, v))
        .to_vec();
    cases.push((
        "missing diagonal".into(),
        SparseColMat::try_new_from_triplets(3, 3, &t).unwrap(),
    ));
    for (label, a) in cases {
        let (cp, ri) = (a.symbolic().col_ptr(), a.symbolic().row_idx());
        let slack = 3;
        let cp2: Vec<usize> = cp.iter().map(|p| p + slack).collect();
        let ri2: Vec<usize> = [0; 3].into_iter().chain(ri.iter().copied()).collect();
        let v2: Vec<f64> = [f64::NAN; 3]
            .into_iter()
            .chain(a.val().iter().copied())
            .collect();
        let n = a.nrows();
        let offset = SparseColMat::new(SymbolicSparseColMat::new_checked(n, n, cp2, None, ri2), v2);
        let (x, y) = (
            DiagonalPattern::new(&a).unwrap(),
            DiagonalPattern::new(&offset).unwrap(),
        );
        assert_eq!(x.pattern.col_ptr(), y.pattern.col_ptr(), "{label}");
        assert_eq!(x.pattern.row_idx(), y.pattern.row_idx(), "{label}");
        assert_eq!(x.diag, y.diag, "{label}");
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&x.values), bits(&y.values), "{label}");
        assert_eq!(x.pattern.col_ptr()[0], 0, "{label}");
        for (j, &p) in x.diag.iter().enumerate() {
            assert_eq!(x.pattern.row_idx()[p], j, "{label}");
        }
    }
}
