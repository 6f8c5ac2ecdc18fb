//! Figures of the stress study.

use super::*;
use crate::plot::{Figure, Mark, Scale, Series};
use crate::study::shape::Drawing;

/// Errors below this are drawn at this value on log axes (an exactly zero error has no
/// logarithm); the CSV keeps the raw values.
pub const PLOT_FLOOR: f64 = 1e-17;

fn floored(v: Option<f64>) -> f64 {
    v.map_or(f64::NAN, |x| x.max(PLOT_FLOOR))
}

/// Labels of the five solve variants in figures.
pub fn variant_label(name: &str) -> &'static str {
    match name {
        "plain" => "f64 Cholesky",
        "refined_working" => "+ refinement, f64 residual",
        "refined_extended" => "+ refinement, extended residual",
        "equilibrated" => "equilibrated",
        _ => "equilibrated + extended refinement",
    }
}

/// Figures of the ε study: per scene, forward error against ε for every variant with the
/// cond₂·ε_mach bound; per scene, error against the exact contact solution (penalty model
/// error, plain f64 total error, refined total error); and forward error against cond₂ over
/// all scenes.
pub fn figures(rows: &[EpsRow]) -> Vec<(String, Figure)> {
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    let mut figs = Vec::new();
    for sc in &scenes {
        let rs: Vec<&EpsRow> = rows.iter().filter(|r| r.scene == *sc).collect();
        figs.push((
            format!("forward_error_vs_eps_{sc}"),
            forward_error_vs_eps(sc, &rs),
        ));
        figs.push((
            format!("error_vs_lagrange_{sc}"),
            error_vs_lagrange(sc, &rs),
        ));
    }
    figs.push(("forward_error_vs_cond".into(), forward_error_vs_cond(rows)));
    if let Some(fig) = forward_error_vs_scaled_cond(rows) {
        figs.push(("forward_error_vs_scaled_cond".into(), fig));
    }
    figs
}

/// Forward error of every solve variant against ε on one scene, with the bound cond₂·ε_mach.
fn forward_error_vs_eps(sc: &str, rs: &[&EpsRow]) -> Figure {
    let x: Vec<f64> = rs.iter().map(|r| r.eps).collect();
    let mut fig = Figure::new(
        format!("Forward error vs penalty ε — {sc} (N = {})", rs[0].n),
        "uniform penalty ε",
        "‖u − u*‖ / ‖u*‖  (u* exact, double-double; 0 drawn at 1e-17)",
    )
    .scales(Scale::Log10, Scale::Log10);
    let get = |r: &EpsRow, name: &str| -> Option<f64> {
        r.forward
            .pairs()
            .iter()
            .find(|(n, _)| *n == name)
            .and_then(|p| p.1)
    };
    for (i, name, mark) in [
        (0, "plain", Mark::LinePoints),
        (1, "refined_working", Mark::Line),
        (2, "refined_extended", Mark::LinePoints),
    ] {
        let y: Vec<f64> = rs.iter().map(|r| floored(get(r, name))).collect();
        fig = fig.with_series(Series::new(variant_label(name), x.clone(), y, mark).color(i));
    }
    // Equilibrated Cholesky equals the plain one bit for bit wherever the plain
    // factorization is accepted: drawn only where it is refused.
    for (i, name) in [(3, "equilibrated"), (4, "equilibrated_refined_extended")] {
        let y: Vec<f64> = rs
            .iter()
            .map(|r| {
                if r.forward.plain.is_none() {
                    floored(get(r, name))
                } else {
                    f64::NAN
                }
            })
            .collect();
        if y.iter().any(|v| v.is_finite()) {
            let label = format!("{} (where plain is refused)", variant_label(name));
            fig = fig.with_series(Series::new(label, x.clone(), y, Mark::Points).color(i));
        }
    }
    let bound: Vec<f64> = rs.iter().map(|r| floored(r.cond_eps_mach)).collect();
    fig = fig.with_series(Series::new("cond₂ · ε_mach", x.clone(), bound, Mark::Dashed).color(6));
    fig
}

/// Error against the exact contact solution (lagrange) on one scene: the penalty's model
/// error and what f64 and refined solves reach.
fn error_vs_lagrange(sc: &str, rs: &[&EpsRow]) -> Figure {
    let x: Vec<f64> = rs.iter().map(|r| r.eps).collect();
    Figure::new(
        format!("Error vs exact contact solution — {sc}"),
        "uniform penalty ε",
        "‖u − u_lagrange‖ / ‖u_lagrange‖",
    )
    .scales(Scale::Log10, Scale::Log10)
    .with_series(
        Series::new(
            "penalty model error (exact u*)",
            x.clone(),
            rs.iter().map(|r| floored(r.penalty_error)).collect(),
            Mark::Dashed,
        )
        .color(6),
    )
    .with_series(
        Series::new(
            "f64 Cholesky",
            x.clone(),
            rs.iter().map(|r| floored(r.total_error_plain)).collect(),
            Mark::LinePoints,
        )
        .color(0),
    )
    .with_series(
        Series::new(
            "equilibrated + extended refinement",
            x.clone(),
            rs.iter().map(|r| floored(r.total_error_refined)).collect(),
            Mark::Line,
        )
        .color(4),
    )
}

/// Forward error against the exact cond₂, all scenes and ε.
fn forward_error_vs_cond(rows: &[EpsRow]) -> Figure {
    let mut fig = Figure::new(
        "Forward error vs exact cond₂, all scenes and ε",
        "cond₂(K + ε D Dᵀ)",
        "‖u − u*‖ / ‖u*‖",
    )
    .scales(Scale::Log10, Scale::Log10);
    for (i, name) in ["plain", "refined_extended", "equilibrated_refined_extended"]
        .iter()
        .enumerate()
    {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let e = r.forward.pairs().iter().find(|(n, _)| n == name)?.1?;
                Some((r.cond2?, e.max(PLOT_FLOOR)))
            })
            .collect();
        fig = fig.with_series(
            Series::new(
                variant_label(name),
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
                Mark::Points,
            )
            .color([0, 2, 4][i]),
        );
    }
    let mut cs: Vec<f64> = rows.iter().filter_map(|r| r.cond2).collect();
    cs.sort_by(f64::total_cmp);
    cs.dedup();
    if !cs.is_empty() {
        let xs = vec![cs[0], cs[cs.len() - 1]];
        let ys = xs
            .iter()
            .map(|c| (c * f64::EPSILON).max(PLOT_FLOOR))
            .collect();
        fig = fig.with_series(Series::new("cond₂ · ε_mach", xs, ys, Mark::Dashed).color(6));
    }
    fig
}

/// Forward error of f64 Cholesky against cond₂ of the equilibrated matrix (`None`: no point).
fn forward_error_vs_scaled_cond(rows: &[EpsRow]) -> Option<Figure> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter_map(|r| Some((r.cond2_scaled?, r.forward.plain?.max(PLOT_FLOOR))))
        .collect();
    if pts.is_empty() {
        return None;
    }
    let lo = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let hi = pts.iter().map(|p| p.0).fold(0.0f64, f64::max);
    let fig = Figure::new(
        "Forward error of f64 Cholesky vs cond₂ of the equilibrated matrix",
        "cond₂(S A S), S = diag(2^k) ≈ diag(A)^(-1/2)",
        "‖u − u*‖ / ‖u*‖",
    )
    .scales(Scale::Log10, Scale::Log10)
    .with_series(
        Series::new(
            variant_label("plain"),
            pts.iter().map(|p| p.0).collect(),
            pts.iter().map(|p| p.1).collect(),
            Mark::Points,
        )
        .color(0),
    )
    .with_series(
        Series::new(
            "cond₂(SAS) · ε_mach",
            vec![lo, hi],
            vec![
                (lo * f64::EPSILON).max(PLOT_FLOOR),
                (hi * f64::EPSILON).max(PLOT_FLOOR),
            ],
            Mark::Dashed,
        )
        .color(6),
    );
    Some(fig)
}

/// [`figures()`] laid out: the per-scene forward-error and error-against-Lagrange panels two a
/// row (1500 × 520 pixels a row), the forward error against cond₂ and the paper beam's
/// figures on their own.
pub fn drawings(eps_rows: &[EpsRow]) -> Vec<Drawing> {
    let figs = figures(eps_rows);
    let mut out = Vec::new();
    let panel = |prefix: &str| -> Vec<Figure> {
        figs.iter()
            .filter(|(name, _)| name.starts_with(prefix))
            .map(|(_, f)| f.clone())
            .collect()
    };
    for prefix in ["forward_error_vs_eps_", "error_vs_lagrange_"] {
        let fs = panel(prefix);
        if fs.is_empty() {
            continue;
        }
        let cols = 2;
        let rows = fs.len().div_ceil(cols) as u32;
        out.push(Drawing {
            name: prefix.trim_end_matches('_').into(),
            panels: fs,
            cols,
            size: (1500, 520 * rows),
        });
    }
    for (name, fig) in figs {
        if name.starts_with("forward_error_vs_") && !name.starts_with("forward_error_vs_eps_")
            || name.ends_with("_paper-beam")
        {
            out.push(Drawing::single(name, fig));
        }
    }
    out
}
