//! Exact cond₂ by route against one Cholesky of the same matrix (the floor of any exact
//! method): sparse inertia route, dense symmetric eigenvalues, dense SVD — on the membrane
//! stiffness (5-point Laplacian) at several sizes, single-threaded; and one sparse solve of
//! one right-hand side by the one-vector path against faer's multi-RHS solve, and one numeric
//! factorization of a cached simplicial pattern against faer's.
//!
//! `cargo bench --bench cond`. For larger sizes and a table, see `cargo run --release --bin
//! cond_cost`.

use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion};
use penalty_lab::conditioning::{cond2_dense, cond2_sparse_spd};
use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::linalg::{DiagonalPattern, Factorization};
use penalty_lab::model::membrane;
use penalty_lab::system::Stiffness;
use std::hint::black_box;
use std::time::Duration;

fn bench_cond(c: &mut Criterion) {
    let mut g = c.benchmark_group("cond2_by_route");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for side in [20usize, 32, 64, 128] {
        let a = membrane::stiffness(side, 1.0).expect("valid membrane");
        let n = a.n();
        let Stiffness::Sparse(m) = &a else {
            unreachable!()
        };
        g.bench_with_input(BenchmarkId::new("cholesky", n), &a, |b, a| {
            b.iter(|| Factorization::new(black_box(a), true).expect("SPD"))
        });
        g.bench_with_input(BenchmarkId::new("sparse_inertia", n), m, |b, m| {
            b.iter(|| cond2_sparse_spd(black_box(m)).expect("SPD"))
        });
        if n <= 1100 {
            let d = a.to_dense();
            g.bench_with_input(BenchmarkId::new("dense_symmetric_eigen", n), &d, |b, d| {
                b.iter(|| cond2_dense(black_box(d.as_ref()), true).expect("finite"))
            });
            g.bench_with_input(BenchmarkId::new("dense_svd", n), &d, |b, d| {
                b.iter(|| cond2_dense(black_box(d.as_ref()), false).expect("finite"))
            });
        }
    }
    g.finish();
}

/// The 400-DOF membrane and a generated beam (138 DOFs) — the sizes of the benchmark
/// scene folder (`scripts/folder.toml`) — in their preferred (sparse) storage.
fn folder_sizes() -> [(&'static str, Stiffness); 2] {
    let beam = generate(Family::Beam, 0, 2011, &GeneratorConfig::default())
        .expect("valid beam")
        .problem
        .in_preferred_storage()
        .k;
    let membrane = membrane::stiffness(20, 1.0).expect("valid membrane");
    [("membrane", membrane), ("beam", beam)]
}

/// A group for microsecond kernels: 20 samples, 0.3 s warm-up, 1 s of measurement.
fn kernel_group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut g = c.benchmark_group(name);
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    g
}

/// One solve with a sparse Cholesky factor of one right-hand side: the one-vector path
/// (`Factorization::solve_vec_in_place`, simplicial factors) against faer's multi-RHS solve
/// of the same factor (`solve_mat_in_place` with one column), on the 400-DOF membrane and a
/// generated beam — the sizes of the benchmark scene folder.
fn bench_one_vector_solve(c: &mut Criterion) {
    let mut g = kernel_group(c, "one_vector_solve");
    for (name, a) in folder_sizes() {
        let f = Factorization::new(&a, true).expect("SPD");
        let n = a.n();
        let b: Vec<f64> = (0..n).map(|i| (i % 7) as f64 - 3.0).collect();
        g.bench_function(BenchmarkId::new(format!("{name}/one_vector"), n), |bench| {
            let mut x = b.clone();
            bench.iter(|| {
                x.copy_from_slice(&b);
                f.solve_vec_in_place(black_box(&mut x));
            })
        });
        g.bench_function(
            BenchmarkId::new(format!("{name}/faer_multi_rhs"), n),
            |bench| {
                let mut x = faer::Mat::<f64>::zeros(n, 1);
                bench.iter(|| {
                    for (i, v) in b.iter().enumerate() {
                        x[(i, 0)] = *v;
                    }
                    f.solve_mat_in_place(black_box(x.as_mut()));
                })
            },
        );
    }
    g.finish();
}

/// One numeric sparse Cholesky of a cached simplicial pattern: ours (`DiagonalPattern::factor`:
/// permutation gathered through the cached map, row structure precomputed) against faer's
/// `factorize_numeric_llt` with the same symbolic analysis (which permutes A and walks the
/// elimination tree at every call), on the membrane and beam of `one_vector_solve`.
fn bench_simplicial_numeric(c: &mut Criterion) {
    use faer::dyn_stack::{MemBuffer, MemStack};
    let mut g = kernel_group(c, "simplicial_numeric");
    for (name, a) in folder_sizes() {
        let Stiffness::Sparse(m) = a else {
            panic!("{name}: expected sparse storage")
        };
        let n = m.nrows();
        let pattern = DiagonalPattern::new(&m).expect("valid pattern");
        g.bench_function(BenchmarkId::new(format!("{name}/ours"), n), |bench| {
            bench.iter(|| pattern.factor(black_box(&pattern.values)).expect("SPD"))
        });
        let a = faer::sparse::SparseColMat::new((*pattern.pattern).clone(), pattern.values.clone());
        let symbolic = pattern.symbolic.clone();
        let mut values = vec![0.0; symbolic.len_val()];
        let req = symbolic.factorize_numeric_llt_scratch::<f64>(faer::Par::Seq, Default::default());
        let mut mem = MemBuffer::new(req);
        g.bench_function(BenchmarkId::new(format!("{name}/faer"), n), |bench| {
            bench.iter(|| {
                symbolic
                    .factorize_numeric_llt(
                        black_box(&mut values),
                        a.as_ref(),
                        faer::Side::Lower,
                        Default::default(),
                        faer::Par::Seq,
                        MemStack::new(&mut mem),
                        Default::default(),
                    )
                    .expect("SPD");
            })
        });
    }
    g.finish();
}

/// The a-posteriori margin of a Cholesky test (`certify::posterior_margin`: the residual
/// `L̂L̂ᵀ − A` by compensated sums) against the factorization it certifies, on the membrane and
/// beam of `one_vector_solve`; and what replaces both at λ_min where it can (`temple`: one LDLᵀ
/// inertia test, Lemma 8's margin and Temple's bound with its compensated residual).
fn bench_posterior_margin(c: &mut Criterion) {
    use penalty_lab::conditioning::residual::posterior_margin;
    use penalty_lab::conditioning::temple;
    let mut g = kernel_group(c, "posterior_margin");
    for (name, a) in folder_sizes() {
        let Stiffness::Sparse(m) = a else {
            panic!("{name}: expected sparse storage")
        };
        let n = m.nrows();
        let pattern = DiagonalPattern::new(&m).expect("valid pattern");
        let f = pattern.factor(&pattern.values).expect("SPD");
        g.bench_function(BenchmarkId::new(format!("{name}/factor"), n), |bench| {
            bench.iter(|| pattern.factor(black_box(&pattern.values)).expect("SPD"))
        });
        g.bench_function(BenchmarkId::new(format!("{name}/posterior"), n), |bench| {
            bench.iter(|| {
                posterior_margin(
                    &f.lower_factor(),
                    pattern.pat(),
                    black_box(&pattern.values),
                    1.0,
                    0.0,
                )
                .expect("positive diagonal")
            })
        });
        let diag: Vec<f64> = pattern.diag.iter().map(|&p| pattern.values[p]).collect();
        let s_hat: Vec<f64> = diag.iter().map(|d| d.sqrt()).collect();
        let x = vec![1.0; n];
        let mu = 2.0 * pattern.max_diagonal();
        g.bench_function(BenchmarkId::new(format!("{name}/temple"), n), |bench| {
            bench.iter(|| {
                let test = pattern
                    .ldlt(black_box(&pattern.values))
                    .expect("simplicial");
                let m = temple::ldlt_margin(&test, &s_hat, &diag).expect("finite");
                let mu = temple::lambda2_lower(mu, m, mu, None);
                temple::temple_lower(pattern.pat(), &pattern.values, &x, mu)
            })
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    bench_cond,
    bench_one_vector_solve,
    bench_simplicial_numeric,
    bench_posterior_margin
);
criterion_main!(benches);
