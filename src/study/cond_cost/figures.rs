//! The figure of `cond_cost` (written into `--out` itself, as before the shared entry).

use super::{Row, SLOPE_MIN_N};
use crate::plot::{Figure, Mark, Series};
use crate::stats::loglog_slope;
use crate::study::shape::Drawing;

/// Reads one route's wall time (s) off a row; `None` where the route was skipped.
type RouteTime = fn(&Row) -> Option<f64>;

/// `cond_cost`: time against n per route and family, log–log, with the least-squares slopes
/// in the legend.
pub fn figures(rows: &[Row]) -> Vec<Drawing> {
    let mut fig = Figure::new(
        "Exact cond₂: cost by route vs one sparse Cholesky (median, 1 thread)",
        "unknowns n",
        "wall time (s)",
    )
    .log_log()
    .with_size(1000, 650);
    let routes: [(&str, RouteTime); 4] = [
        ("one sparse Cholesky", |r| Some(r.cholesky_s)),
        ("sparse exact (Lanczos + inertia)", |r| {
            Some(r.sparse_exact_s)
        }),
        ("dense symmetric eigenvalues", |r| r.dense_eigen_s),
        ("dense SVD", |r| r.dense_svd_s),
    ];
    let mut color = 0;
    for family in ["membrane", "beam"] {
        for (name, get) in routes.iter() {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.family == family)
                .filter_map(|r| get(r).map(|t| (r.n as f64, t)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
            // The growth rate is fitted where the asymptotics show (n ≥ SLOPE_MIN_N): the small
            // sizes measure the sweep's crossover, where fixed costs dominate.
            let (xs, ys): (Vec<f64>, Vec<f64>) =
                x.iter().zip(&y).filter(|(n, _)| **n >= SLOPE_MIN_N).unzip();
            let label = match loglog_slope(&xs, &ys) {
                Some(s) => format!("{family}: {name} (slope {s:.2})"),
                None => format!("{family}: {name}"),
            };
            let mark = if family == "membrane" {
                Mark::LinePoints
            } else {
                Mark::Dashed
            };
            fig = fig.with_series(Series::new(label, x, y, mark).color(color % 8));
            color += 1;
        }
        color = 0;
    }
    vec![Drawing::single("cond_cost", fig)]
}
