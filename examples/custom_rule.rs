//! Your own penalty rule, from outside the crate, beside the paper's and ours.
//!
//! ```text
//! cargo run --release --example custom_rule [OUT] [--count N]
//! ```
//!
//! The rule here is a gap-scaled stiffness penalty,
//!
//! `ε_c = f · K[d_c, d_c] · (1 + |g0_c| / δ)`,   f = [`F`], g0 = Dᵀu0 − û,
//!
//! stiffer where the unconstrained solution overshoots its limit by more. A rule is one
//! `static` [`Strategy`] (name, summary, legend label, knob, colour, what it needs) and its
//! `solve`, written with the crate's public drivers ([`fixed_point`] re-evaluates ε on each
//! active set, [`per_active`] evaluates a per-constraint formula); [`registry::register`] makes
//! it known to the sweep, `Method::from_name` and the figures. This file is all it takes.
//!
//! The run: the default sweep families with `paper`, `condensed` and this rule (and the
//! `lagrange` reference), rows in `OUT/rows.csv` (default `results/custom_rule`), the figures
//! (`cond_vs_eps_*`, `pareto_*`, …) in `OUT/figures`, and a table on stdout: median over the
//! rows of each method of max penetration / δ and of cond₂(K + D E Dᵀ).

use penalty_lab::strategy::{
    fixed_point, per_active, registry, Context, Glyph, Knob, Look, Method, Solution, Strategy,
};
use penalty_lab::study::sweep::{self, figures, rows::Row, RunOptions, SweepConfig};
use penalty_lab::{stats, Error, Result};
use std::path::{Path, PathBuf};

/// The rule's stiffness factor f.
pub const F: f64 = 1.0;

/// The rule, declared once: everything the registry, the CLI and the figures need.
pub static GAP_SCALED: Strategy = Strategy {
    name: "gap-scaled",
    summary: "ε_c = f·K_dd·(1 + |g0_c|/δ) (examples/custom_rule.rs)",
    knob: Knob::Delta,
    needs_k_inverse: true,
    solve: solve_gap_scaled,
    look: Look {
        label: "gap-scaled (f·K_dd·(1 + |g0|/δ))",
        rule_label: "gap-scaled",
        colour: 8,
        glyph: Glyph::Circle,
    },
    ..Strategy::BASE
};

/// `ε_c = F · K_dd · (1 + |g0_c|/δ)` on the active set, re-evaluated by [`fixed_point`] until
/// the active set repeats.
fn solve_gap_scaled(ctx: Context, method: &Method) -> Result<Solution> {
    let delta = method.need_delta()?;
    fixed_point(ctx, *method, |active, ctx| {
        let g0 = ctx.g0()?;
        let p = ctx.problem;
        Ok(per_active(p, active, |c, con| {
            F * p.k.diag(con.single_dof().unwrap()).abs() * (1.0 + g0[c].abs() / delta)
        }))
    })
}

/// Registers the rule and sweeps `count` scenes per default family into `out`; returns the
/// rows and the figure files written.
pub fn run(out: &Path, count: usize) -> Result<(Vec<Row>, Vec<PathBuf>)> {
    registry::register(&GAP_SCALED)?;
    let cfg = SweepConfig {
        count,
        methods: registry::lookup_all(&["paper", "condensed", GAP_SCALED.name])?,
        ..SweepConfig::default()
    };
    let opts = RunOptions {
        out: out.to_path_buf(),
        threads: None,
        shard: None,
        resume: false,
        write_scenes: None,
        dense_scenes: false,
        progress: false,
        provenance: None,
    };
    sweep::run(&cfg, &opts)?;
    let (rows, _) = sweep::rows::read_rows(&out.join("rows.csv"), false)?;
    let figures = figures::render_run(out)?;
    Ok((rows, figures))
}

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let mut args = std::env::args().skip(1);
        let (mut out, mut count) = (PathBuf::from("results/custom_rule"), 4);
        while let Some(a) = args.next() {
            match a.as_str() {
                "--count" => {
                    count = args
                        .next()
                        .and_then(|v| v.parse().ok())
                        .filter(|&c| c > 0)
                        .ok_or_else(|| Error::input("--count needs an integer ≥ 1"))?;
                }
                _ if a.starts_with('-') => return Err(Error::input(format!("unknown option {a}"))),
                _ => out = PathBuf::from(a),
            }
        }
        let (rows, figs) = run(&out, count)?;
        println!("| method | rows | median max penetration / δ | median cond₂(K + D E Dᵀ) |");
        println!("|---|---:|---:|---:|");
        for name in ["paper", "condensed", GAP_SCALED.name] {
            let of: Vec<&Row> = rows.iter().filter(|r| r.method == name).collect();
            let ratio: Vec<f64> = of
                .iter()
                .filter_map(|r| Some(r.max_penetration? / r.delta?))
                .collect();
            let cond: Vec<f64> = of.iter().filter_map(|r| r.cond2_system).collect();
            println!(
                "| {name} | {} | {:.3} | {:.3e} |",
                of.len(),
                stats::median(&ratio).unwrap_or(f64::NAN),
                stats::median(&cond).unwrap_or(f64::NAN)
            );
        }
        eprintln!(
            "{} rows, {} figure files → {}",
            rows.len(),
            figs.len(),
            out.display()
        );
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use penalty_lab::strategy::{self, Knobs};

    /// The rule runs through the sweep beside `paper` and `condensed`: rows for every δ of
    /// every scene, converged, and figures drawn.
    #[test]
    fn sweeps_beside_the_built_in_rules() {
        let dir = tempfile::tempdir().unwrap();
        let (rows, figs) = run(dir.path(), 1).unwrap();
        let ours: Vec<&Row> = rows
            .iter()
            .filter(|r| r.method == GAP_SCALED.name)
            .collect();
        let paper = rows.iter().filter(|r| r.method == "paper").count();
        assert!(!ours.is_empty());
        assert_eq!(ours.len(), paper, "one row per (scene, δ), as for paper");
        for r in &ours {
            assert!(r.converged == Some(true) && r.warnings.is_empty(), "{r:?}");
            assert!(r.cond2_system.is_some_and(|c| c.is_finite() && c >= 1.0));
        }
        assert!(!figs.is_empty());
    }

    /// On a lone spring k with load q (u0 = q/k, limit 0), the penalty is the formula's and
    /// the solve is the spring's: u = q / (k + ε).
    #[test]
    fn the_penalty_is_the_formula() {
        use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
        registry::register(&GAP_SCALED).unwrap();
        let (k, q, delta) = (4.0, 2.0, 0.1);
        let con = Constraint::on_dof(0, 0.0, ConstraintKind::Upper);
        let p = Problem::new(
            Stiffness::from_rows(&[vec![k]]).unwrap(),
            vec![q],
            vec![con],
        )
        .unwrap();
        let knobs = Knobs::delta(delta);
        let m = Method::from_name(GAP_SCALED.name, knobs).unwrap();
        let sol = strategy::solve(&p, m).unwrap();
        let eps = F * k * (1.0 + (q / k) / delta);
        let tol = 4.0 * f64::EPSILON;
        assert!(
            (sol.penalties[0] - eps).abs() <= tol * eps,
            "{:?}",
            sol.penalties
        );
        assert!(
            (sol.u[0] - q / (k + eps)).abs() <= tol * q / k,
            "{:?}",
            sol.u
        );
    }
}
