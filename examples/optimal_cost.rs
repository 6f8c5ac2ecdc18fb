//! Cost of the cond-optimal penalty (`strategy::optimal`) against n and m: cantilevers of
//! n/3 Euler–Bernoulli elements tied (bilateral) at m evenly spaced transverse DOFs, δ = 5 %
//! of the largest unconstrained gap, by each evaluation route (`dense` up to n = 400,
//! `sparse` from `spectrum::SPARSE_MIN_N`). Prints CSV: n, m, route, seconds, evaluations
//! (one eigendecomposition each: dense, or the sparse route's extreme windows), cond2,
//! starts, starts agreeing.
//!
//! `cargo run --release --example optimal_cost`

use penalty_lab::model::beam::{Frame, Section};
use penalty_lab::strategy::optimal::{self, spectrum, Route};
use penalty_lab::strategy::Context;
use penalty_lab::system::{Constraint, ConstraintKind, Problem};
use std::time::Instant;

fn problem(n_el: usize, m: usize) -> Problem {
    let frame = Frame::cantilever(n_el, 100.0, Section::rectangle(2100.0, 1.0, 1.0)).unwrap();
    let k = frame.assemble(false).unwrap();
    let n = frame.n_dofs();
    let mut q = vec![0.0; n];
    for node in 1..=n_el {
        q[frame.dof(node, 1).unwrap()] = -1.0;
    }
    let constraints = (1..=m)
        .map(|i| {
            Constraint::on_dof(
                frame.dof(i * n_el / m, 1).unwrap(),
                0.0,
                ConstraintKind::Bilateral,
            )
        })
        .collect();
    Problem::new(k, q, constraints).unwrap()
}

fn main() {
    println!("n,m,route,seconds,evaluations,cond2,starts,starts_agreeing");
    for n_el in [10, 30, 60, 120, 240, 480] {
        for m in [3, 10, 30] {
            if m > n_el {
                continue;
            }
            let p = problem(n_el, m);
            let u0 = p.k.solve(&p.q).unwrap();
            let delta = 0.05 * p.gaps(&u0).iter().fold(0.0f64, |a, g| a.max(g.abs()));
            for route in [Route::Dense, Route::Sparse] {
                let skip = match route {
                    Route::Dense => p.n() > 400,
                    Route::Sparse => p.n() < spectrum::SPARSE_MIN_N,
                };
                if skip {
                    continue;
                }
                let t0 = Instant::now();
                let sol = optimal::solve_by(Context::new(&p), delta, route).unwrap();
                let secs = t0.elapsed().as_secs_f64();
                let r = sol.stats.optimal.unwrap();
                println!(
                    "{},{m},{},{secs:.4},{},{:.6e},{},{}",
                    p.n(),
                    r.route,
                    r.evaluations,
                    r.cond2,
                    r.starts,
                    r.starts_agreeing
                );
            }
        }
    }
}
