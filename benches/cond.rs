//! Exact cond₂ by route against one Cholesky of the same matrix (the floor of any exact
//! method): sparse inertia route, dense symmetric eigenvalues, dense SVD — on the membrane
//! stiffness (5-point Laplacian) at several sizes, single-threaded.
//!
//! `cargo bench --bench cond`. For larger sizes and a table, see `cargo run --release --bin
//! cond_cost`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use penalty_lab::conditioning::{cond2_dense, cond2_sparse_spd};
use penalty_lab::linalg::Factorization;
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

criterion_group!(benches, bench_cond);
criterion_main!(benches);
