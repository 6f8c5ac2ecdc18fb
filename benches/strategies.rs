//! Each strategy's solve on a generated beam and membrane scene; assembly of the beam and
//! membrane stiffness; the condensed method's cost against the number of constraints m.
//!
//! `cargo bench --bench strategies`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::model::beam::{Frame, Section};
use penalty_lab::strategy::{self, Method};
use penalty_lab::system::{Constraint, ConstraintKind, Problem};
use std::hint::black_box;
use std::time::Duration;

fn quick<'a>(
    c: &'a mut Criterion,
    name: &str,
) -> criterion::BenchmarkGroup<'a, criterion::measurement::WallTime> {
    let mut g = c.benchmark_group(name);
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1));
    g
}

fn methods(scale: f64, kdiag: f64) -> Vec<Method> {
    vec![
        Method::constant(1e3 * kdiag),
        Method::scaled(1e3),
        Method::spring(1e-2 * scale),
        Method::paper(1e-2 * scale),
        Method::condensed(1e-2 * scale),
        Method::lagrange(),
        Method::augmented(kdiag, 1e-9 * scale, true),
    ]
}

fn bench_strategies(c: &mut Criterion) {
    let cfg = GeneratorConfig {
        beam_elements: (200, 200),
        membrane_side: (30, 30),
        ..Default::default()
    };
    for family in [Family::Beam, Family::Membrane] {
        let s = generate(family, 0, 2011, &cfg).expect("generated");
        let p = &s.problem;
        let u0 = strategy::Prepared::new(p).expect("K regular").u0().to_vec();
        let scale = p.displacement_scale(&u0);
        let kdiag = p
            .constraints
            .iter()
            .map(|c| p.k.diag(c.single_dof().unwrap()))
            .fold(0.0, f64::max);
        let mut g = quick(c, &format!("solve_{}", family.name()));
        for m in methods(scale, kdiag) {
            g.bench_function(BenchmarkId::new(m.name(), p.n()), |b| {
                b.iter(|| strategy::solve(black_box(p), m).expect("solves"))
            });
        }
        g.finish();
    }
}

fn bench_assembly(c: &mut Criterion) {
    let mut g = quick(c, "assembly");
    for el in [100usize, 1000, 10000] {
        let f = Frame::cantilever(el, 30.0, Section::rectangle(2100.0, 1.0, 1.0)).expect("frame");
        g.bench_with_input(BenchmarkId::new("cantilever_sparse", 3 * el), &f, |b, f| {
            b.iter(|| f.assemble(true).expect("assembles"))
        });
    }
    g.finish();
}

/// Condensed cost against m on one membrane (n = 2500, dense-S route below n = 2000 would not
/// apply: the elimination route is what runs here).
fn bench_condensed_vs_m(c: &mut Criterion) {
    let cfg = GeneratorConfig {
        membrane_side: (50, 50),
        ..Default::default()
    };
    let s = generate(Family::Membrane, 0, 7, &cfg).expect("generated");
    let base = &s.problem;
    let u0 = strategy::Prepared::new(base)
        .expect("K regular")
        .u0()
        .to_vec();
    let scale = base.displacement_scale(&u0);
    let mut g = quick(c, "condensed_vs_m");
    for stride in [64usize, 16, 4, 1] {
        let cons: Vec<Constraint> = base
            .constraints
            .iter()
            .step_by(stride)
            .map(|c| Constraint {
                kind: ConstraintKind::Lower,
                ..c.clone()
            })
            .collect();
        let p = Problem::new(base.k.clone(), base.q.clone(), cons).expect("valid");
        let m = Method::condensed(1e-2 * scale);
        g.bench_with_input(BenchmarkId::new("condensed", p.m()), &p, |b, p| {
            b.iter(|| strategy::solve(black_box(p), m).expect("solves"))
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    bench_strategies,
    bench_assembly,
    bench_condensed_vs_m
);
criterion_main!(benches);
