//! A short tour of the library API: the paper's cantilever (Sec. 4.2, Fig. 2, Eq. 31–34) built
//! from its data, solved with the classical penalty and with the paper's rule (Eq. 28–29,
//! δ = 0.1), and the exact cond₂ of K and of each final system printed.
//!
//! ```sh
//! cargo run --release --example paper_beam
//! ```
//!
//! `tests/verification/example_paper_beam.rs` runs [`run`] and checks it against the paper's printed numbers.

use penalty_lab::conditioning::cond2;
use penalty_lab::metrics::system_matrix;
use penalty_lab::model::beam::{Frame, Section};
use penalty_lab::strategy::{solve, Method};
use penalty_lab::system::{Constraint, ConstraintKind, Problem};
use penalty_lab::Result;

/// One strategy's outcome: its name, ε per constraint, cond₂ of the final system.
pub type Outcome = (String, Vec<f64>, f64);

/// cond₂ of K, then one [`Outcome`] per strategy.
pub fn run() -> Result<(f64, Vec<Outcome>)> {
    // Three Euler–Bernoulli frame elements, 30 mm, E = 2100, 1×1 section (Eq. 30–31).
    let k = Frame::cantilever(3, 30.0, Section::rectangle(2100.0, 1.0, 1.0))?.assemble(false)?;
    let q = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -50.0, 1.0, 0.0]; // Eq. 32
    let kind = ConstraintKind::Bilateral; // Eq. 34: D, û
    let constraints = [(4, 3.0), (6, -1.0), (7, 30.0)]
        .map(|(dof, limit)| Constraint::on_dof(dof, limit, kind))
        .to_vec();
    let beam = Problem::new(k, q, constraints)?;
    let mut rows = Vec::new();
    for method in [Method::constant(1e4), Method::paper(0.1)] {
        let sol = solve(&beam, method)?;
        let cond = cond2(&system_matrix(&beam, &sol))?.cond2;
        rows.push((method.name().to_string(), sol.penalties, cond));
    }
    Ok((cond2(&beam.k)?.cond2, rows))
}

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let (cond_k, rows) = run()?;
        println!("cond2(K) = {cond_k:.4e}");
        for (name, eps, cond) in rows {
            println!("{name:>8}: eps = {eps:.1?}, cond2(K + D E D^T) = {cond:.4e}");
        }
        Ok(())
    })
}
