//! The figures of `friction_bench`: the friction force's error and the tangent's cond₂
//! against ε_T, per rule and μ.

use super::FrictionRow;
use crate::plot::{Figure, Mark, Series};
use crate::study::shape::Drawing;

/// `friction_eps_t`: history error and cond₂ against ε_T (the sliding block's constant and
/// area rules; the δ_T rule's rows have no single ε_T and are in the table); nothing where
/// the run has no such row.
pub fn figures(rows: &[FrictionRow]) -> Vec<Drawing> {
    let drawn = |r: &&FrictionRow| {
        r.case == "sliding-block" && r.eps_t.is_some() && r.history_err.is_some_and(|e| e > 0.0)
    };
    if !rows.iter().any(|r| drawn(&r)) {
        return Vec::new();
    }
    let mut err = Figure::new(
        "Sliding block: friction force error vs ε_T (Lagrange = exact)",
        "ε_T (force/length)",
        "max |T − T_lagrange| / (μN)",
    )
    .log_log();
    let mut cond = Figure::new(
        "Sliding block: cond₂ of the tangent before full slip vs ε_T",
        "ε_T (force/length)",
        "cond₂",
    )
    .log_log();
    let mut mus: Vec<f64> = rows.iter().map(|r| r.mu).collect();
    mus.dedup();
    let mut color = 0;
    for &mu in &mus {
        for rule in ["constant", "area"] {
            let pick = |get: fn(&FrictionRow) -> Option<f64>| -> (Vec<f64>, Vec<f64>) {
                rows.iter()
                    .filter(|r| r.case == "sliding-block" && r.mu == mu && r.tangent_rule == rule)
                    .filter_map(|r| r.eps_t.zip(get(r)).filter(|(_, y)| *y > 0.0))
                    .unzip()
            };
            let label = format!("{rule}, μ = {mu}");
            let (x, y) = pick(|r| r.history_err);
            if !x.is_empty() {
                err = err.with_series(Series::new(&label, x, y, Mark::LinePoints).color(color));
            }
            let (x, y) = pick(|r| r.cond2_system);
            if !x.is_empty() {
                cond = cond.with_series(Series::new(&label, x, y, Mark::LinePoints).color(color));
            }
            color += 1;
        }
    }
    vec![Drawing {
        name: "friction_eps_t".into(),
        panels: vec![err, cond],
        cols: 2,
        size: (1600, 600),
    }]
}
