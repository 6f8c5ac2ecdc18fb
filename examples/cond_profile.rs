//! Where a certified cond₂ spends its time, in units of the operations it is made of: the
//! full-contact membrane of `engine_scale` (N = SIZE, default 10⁶), `condensed` at δ = 1e-3 of
//! the displacement scale (as `engine_scale`). Measures one numeric Cholesky factorization
//! of K and one solve with it (each the median of 3), then runs the certified cond₂ of K and
//! of the final system and splits each wall time into its factorizations (counted by the
//! certificate) times the factorization's time and the rest: its Lanczos steps (products with
//! A and solves with A, counted by the certificate; a solve costs about 0.17 factorizations at
//! 10⁶ unknowns), the Ritz vectors and the margins. Prints a table (markdown).
//!
//! `cargo run --release --example cond_profile [SIZE]`
//!
//! The split is an estimate: a factorization of a shifted matrix costs what one of K does
//! (same pattern).

use penalty_lab::conditioning::{self, CondReport};
use penalty_lab::linalg::DiagonalPattern;
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::model::scalable;
use penalty_lab::strategy::{self, Method};
use penalty_lab::system::Stiffness;
use std::time::Instant;

fn median3(mut f: impl FnMut() -> f64) -> f64 {
    let mut t = [f(), f(), f()];
    t.sort_by(f64::total_cmp);
    t[1]
}

fn row(what: &str, seconds: f64, r: &CondReport, t_fact: f64, t_solve: f64) {
    // Columns: wall, factorizations × the time of one, Lanczos steps, the rest in solves' time,
    // the wall in factorizations' time.
    let Some(c) = r.certificate else {
        println!(
            "| {what} | {seconds:.2} s | (no certificate: route {}) | | |",
            r.route.name()
        );
        return;
    };
    let fact = c.factorizations as f64 * t_fact;
    let rest = (seconds - fact).max(0.0);
    println!(
        "| {what} | {seconds:.2} s | {} × {t_fact:.2} s = {fact:.1} s | {} | {rest:.1} s ({:.0} solves' time) | {:.1} |",
        c.factorizations,
        c.lanczos_steps,
        rest / t_solve,
        seconds / t_fact
    );
}

fn main() -> penalty_lab::Result<()> {
    let size: usize = std::env::args()
        .nth(1)
        .map_or(Ok(1_000_000), |s| s.parse())
        .map_err(|e| penalty_lab::Error::input(format!("SIZE: {e}")))?;
    let scene = scalable::membrane_scene(size, usize::MAX)?;
    let p = &scene.problem;
    let Stiffness::Sparse(k) = &p.k else {
        return Err(penalty_lab::Error::input("the membrane is stored sparse"));
    };
    let pattern = DiagonalPattern::new(k)?;
    let t_fact = median3(|| {
        let t = Instant::now();
        let f = pattern.factor(&pattern.values).expect("K is SPD");
        let s = t.elapsed().as_secs_f64();
        drop(f);
        s
    });
    let f = pattern.factor(&pattern.values).expect("K is SPD");
    let mut x = p.q.clone();
    let t_solve = median3(|| {
        let t = Instant::now();
        f.solve_vec_in_place(&mut x);
        t.elapsed().as_secs_f64()
    });
    drop(f);
    let t = Instant::now();
    let ck = conditioning::cond2(&p.k)?;
    let seconds_k = t.elapsed().as_secs_f64();
    let delta = 1e-3 * scene.scale;
    let t = Instant::now();
    let sol = strategy::solve(p, Method::condensed(delta))?;
    let seconds_solve = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let set = MetricSet {
        cond: true,
        det: false,
        cond_tol: None,
    };
    let met = metrics::compute_with_k(p, &sol, set, None, None, None)?;
    let seconds_sys = t.elapsed().as_secs_f64();
    println!(
        "N = {}, m = {}; one factorization of K {t_fact:.2} s, one solve {t_solve:.3} s; \
         condensed solve {seconds_solve:.2} s ({} factorizations)\n",
        p.n(),
        p.m(),
        sol.stats.factorizations
    );
    println!(
        "| cond₂ of | wall | factorizations | Lanczos steps | rest | in factorizations' time |"
    );
    println!("|---|---|---|---|---|---|");
    row("K", seconds_k, &ck, t_fact, t_solve);
    match &met.cond2_system {
        Some(r) => row("K + DEDᵀ (final)", seconds_sys, r, t_fact, t_solve),
        None => println!("| K + DEDᵀ | not computed: {:?} | | | | |", met.unavailable),
    }
    Ok(())
}
