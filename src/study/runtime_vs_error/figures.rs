//! The figures of `runtime_vs_error`, drawn from `rows.json`: time against error and against
//! penetration per family and size, and time against N.

use super::PerfRow;
use crate::plot::{Figure, Mark, Scale, Series};
use crate::strategy;
use crate::study::shape::Drawing;

/// Errors below this are drawn at this value on log axes.
pub const PLOT_FLOOR: f64 = 1e-17;

/// `fig` with one method's points as a line-and-points series in the method's colour and
/// glyph (unchanged where there are none).
fn with_method(fig: Figure, method: &str, pts: &[(f64, f64)]) -> Figure {
    if pts.is_empty() {
        return fig;
    }
    fig.with_series(
        Series::new(
            method,
            pts.iter().map(|p| p.0).collect(),
            pts.iter().map(|p| p.1).collect(),
            Mark::LinePoints,
        )
        .method(method),
    )
}

/// Figures: per family, time against `‖u − u_ref‖/‖u_ref‖` and time against relative max
/// penetration, one panel per size, one line per strategy through its knob values (lagrange,
/// exact, as a horizontal line at its time); and time against N per strategy (at the middle
/// knob value).
pub fn figures(rows: &[PerfRow]) -> Vec<(String, Vec<Figure>)> {
    let mut out = Vec::new();
    let mut families: Vec<&str> = rows.iter().map(|r| r.family.as_str()).collect();
    families.dedup();
    families.sort_unstable();
    families.dedup();
    let mut methods: Vec<&str> = Vec::new();
    for r in rows {
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    for fam in &families {
        let mut sizes: Vec<usize> = rows
            .iter()
            .filter(|r| r.family == *fam)
            .map(|r| r.n)
            .collect();
        sizes.sort_unstable();
        sizes.dedup();
        for (what, label, get) in [
            (
                "time_vs_error",
                "‖u − u_ref‖ / ‖u_ref‖",
                (|r: &PerfRow| r.error_vs_ref) as fn(&PerfRow) -> Option<f64>,
            ),
            (
                "time_vs_penetration",
                "max penetration / displacement scale",
                |r: &PerfRow| r.penetration_rel,
            ),
        ] {
            let mut panels = Vec::new();
            for &n in &sizes {
                let mut fig = Figure::new(
                    format!("{fam}, N = {n}"),
                    label,
                    "time to solution (s, median)",
                )
                .scales(Scale::Log10, Scale::Log10);
                // lagrange (exact: zero error and penetration) as a horizontal reference
                // line at its time.
                if let Some(t) = rows
                    .iter()
                    .find(|r| {
                        r.family == *fam
                            && r.n == n
                            && r.method == strategy::lagrange::STRATEGY.name
                    })
                    .and_then(|r| r.seconds)
                {
                    fig = fig.hline(t, "lagrange (exact)");
                }
                for m in methods
                    .iter()
                    .filter(|m| **m != strategy::lagrange::STRATEGY.name)
                {
                    let pts: Vec<(f64, f64)> = rows
                        .iter()
                        .filter(|r| r.family == *fam && r.n == n && r.method == *m)
                        .filter_map(|r| Some((get(r)?.max(PLOT_FLOOR), r.seconds?)))
                        .collect();
                    fig = with_method(fig, m, &pts);
                }
                if !fig.series.is_empty() {
                    panels.push(fig);
                }
            }
            if !panels.is_empty() {
                out.push((format!("{what}_{fam}"), panels));
            }
        }
    }
    // Time against N, per family, at the middle knob value of each method.
    let mut panels = Vec::new();
    for fam in &families {
        let mut fig = Figure::new(
            format!("{fam}: time vs size (middle knob value)"),
            "N (DOFs)",
            "time to solution (s, median)",
        )
        .scales(Scale::Log10, Scale::Log10);
        for m in &methods {
            let mut vals: Vec<f64> = rows
                .iter()
                .filter(|r| r.family == *fam && r.method == *m)
                .map(|r| r.value_rel)
                .collect();
            vals.sort_by(f64::total_cmp);
            vals.dedup();
            if vals.is_empty() {
                continue;
            }
            let mid = vals[vals.len() / 2];
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.family == *fam && r.method == *m && r.value_rel == mid)
                .filter_map(|r| Some((r.n as f64, r.seconds?)))
                .collect();
            fig = with_method(fig, m, &pts);
        }
        if !fig.series.is_empty() {
            panels.push(fig);
        }
    }
    if !panels.is_empty() {
        out.push(("time_vs_size".into(), panels));
    }
    out
}

/// [`figures`] laid out: at most three panels a row, 560 × 460 pixels each.
pub fn drawings(rows: &[PerfRow]) -> Vec<Drawing> {
    figures(rows)
        .into_iter()
        .map(|(name, panels)| {
            let cols = panels.len().min(3);
            let nrows = panels.len().div_ceil(cols) as u32;
            Drawing {
                name,
                panels,
                cols,
                size: (560 * cols as u32, 460 * nrows),
            }
        })
        .collect()
}
