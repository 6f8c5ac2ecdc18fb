//! The figure of the engine study: solve wall time and factorizations against N per method.

use super::{scale_method_names, ScaleRow};
use crate::plot::{Figure, Mark, Series};
use crate::study::shape::Drawing;

/// Two panels against N (log–log), one series per method: wall time of the solve, and
/// numeric factorizations.
pub fn drawings(rows: &[ScaleRow]) -> Vec<Drawing> {
    let mut time = Figure::new(
        "Solve wall time, full-contact membranes",
        "N (DOFs)",
        "seconds",
    )
    .log_log();
    let mut fact = Figure::new(
        "Numeric factorizations per solve",
        "N (DOFs)",
        "factorizations",
    )
    .log_log();
    for name in scale_method_names() {
        let r: Vec<&ScaleRow> = rows.iter().filter(|r| r.method == name).collect();
        if r.is_empty() {
            continue;
        }
        let x: Vec<f64> = r.iter().map(|r| r.n as f64).collect();
        time = time.with_series(
            Series::new(
                name,
                x.clone(),
                r.iter().map(|r| r.seconds_solve).collect(),
                Mark::LinePoints,
            )
            .method(name),
        );
        fact = fact.with_series(
            Series::new(
                name,
                x,
                r.iter().map(|r| r.factorizations as f64).collect(),
                Mark::LinePoints,
            )
            .method(name),
        );
    }
    vec![Drawing {
        name: "engine_scale".into(),
        panels: vec![time, fact],
        cols: 2,
        size: (1120, 460),
    }]
}
