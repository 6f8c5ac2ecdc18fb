//! One forming time step (Picard on μ* to convergence, contact set updates, exact cond₂ of the
//! step's final system, geometry update) of the Woo-like deep draw, taken from the state at
//! half travel (step 50 of 100, flange, die profile and punch all in contact), for each contact
//! rule. Answers: what one increment of the flow-approach solver costs, and what the adaptive
//! rules cost on top of the classical penalty (their extra Picard iterations and, for
//! `condensed`, the S = DᵀK⁻¹D solves).
//!
//! `cargo bench --bench forming`.

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use penalty_lab::forming::{ContactRule, FormingConfig, Simulation};
use std::time::Duration;

fn bench_step(c: &mut Criterion) {
    let cfg = FormingConfig::woo_deep_drawing();
    let mut g = c.benchmark_group("forming_step");
    g.sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let rules = [
        ("classical", ContactRule::Classical { eps: 1e7 }),
        (
            "adaptive_residual",
            ContactRule::PaperResidual { delta: 1e-5 },
        ),
        ("paper_literal", ContactRule::PaperLiteral { delta: 1e-5 }),
        ("condensed", ContactRule::Condensed { delta: 1e-5 }),
    ];
    for (name, rule) in rules {
        let mut sim = Simulation::new(&cfg, rule).expect("valid default configuration");
        for _ in 0..cfg.steps / 2 {
            sim.step().expect("the default draw runs");
        }
        g.bench_function(BenchmarkId::new(name, cfg.elements), |b| {
            b.iter_batched(
                || sim.clone(),
                |mut s| s.step().expect("step converges or reports"),
                BatchSize::SmallInput,
            )
        });
    }
    g.finish();
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
