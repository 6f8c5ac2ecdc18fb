//! The figure of `cond_accuracy` (written into `--out` itself, as before the shared entry).

use super::{Row, ROUTES};
use crate::plot::{Figure, Mark, Series};
use crate::study::shape::Drawing;

/// Smallest error drawn (an exact value has error 0, which a log axis cannot show).
pub const ERROR_FLOOR: f64 = 1e-17;

/// `cond_accuracy`: relative error of cond₂ against wall time, one marker colour per route,
/// log–log; errors below [`ERROR_FLOOR`] drawn at it.
pub fn figures(rows: &[Row]) -> Vec<Drawing> {
    let mut fig = Figure::new(
        "cond₂ by route: relative error against the double-double reference vs wall time",
        "wall time (s, median, 1 thread)",
        "|cond₂ / reference − 1|",
    )
    .log_log()
    .with_size(1000, 650);
    for (k, route) in ROUTES.iter().enumerate() {
        let (x, y): (Vec<f64>, Vec<f64>) = rows
            .iter()
            .filter(|r| r.route == *route)
            .map(|r| (r.seconds, r.rel_error.max(ERROR_FLOOR)))
            .unzip();
        if !x.is_empty() {
            fig = fig.with_series(Series::new(*route, x, y, Mark::Points).color(k));
        }
    }
    vec![Drawing::single("cond_accuracy", fig)]
}
