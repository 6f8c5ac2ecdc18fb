//! Setup and one V-cycle of the smoothed-aggregation AMG (`linalg::amg`, scalar, B = ones) on
//! the penalized membranes of `scripts/amg_reference.py` (side 127 and 255: 16 129 and 65 025
//! unknowns), for the comparison with PyAMG's setup time (the target: within 5×).
//!
//! `cargo bench --bench amg`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use penalty_lab::linalg::amg::{Amg, AmgOptions};
use penalty_lab::linalg::krylov::Preconditioner;
use penalty_lab::system::Stiffness;
use std::hint::black_box;
use std::time::Duration;

/// The membrane of `scripts/amg_reference.py` at penalty 1e2·K_dd.
fn membrane(side: usize) -> Stiffness {
    let h = 1.0 / (side as f64 + 1.0);
    let id = |i: usize, j: usize| i * side + j;
    let mut t = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let (x, y) = ((i + 1) as f64 * h, (j + 1) as f64 * h);
            let r2 = (x - 0.5).powi(2) + (y - 0.5).powi(2);
            let eps = if r2 < 0.1 { 400.0 } else { 0.0 };
            t.push((id(i, j), id(i, j), 4.0 + eps));
            for (di, dj) in [(1usize, 0usize), (0, 1)] {
                if i + di < side && j + dj < side {
                    t.push((id(i, j), id(i + di, j + dj), -1.0));
                    t.push((id(i + di, j + dj), id(i, j), -1.0));
                }
            }
        }
    }
    Stiffness::from_triplets(side * side, &t).expect("a valid membrane")
}

fn bench_amg(c: &mut Criterion) {
    let mut g = c.benchmark_group("amg");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    for side in [127usize, 255] {
        let a = membrane(side).to_sparse();
        g.bench_with_input(BenchmarkId::new("setup", side), &side, |b, _| {
            b.iter(|| Amg::new(black_box(a.as_ref()), &AmgOptions::default()).unwrap())
        });
        let amg = Amg::new(a.as_ref(), &AmgOptions::default()).unwrap();
        let r = vec![1.0; side * side];
        let mut z = vec![0.0; side * side];
        g.bench_with_input(BenchmarkId::new("v_cycle", side), &side, |b, _| {
            b.iter(|| amg.apply(black_box(&r), &mut z))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_amg);
criterion_main!(benches);
