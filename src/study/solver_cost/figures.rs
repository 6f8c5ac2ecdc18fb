//! The figures of `solver_cost`:
//! - `iterations_ic0`, `iterations_jacobi`: Krylov iterations to the fixed error of u
//!   (`krylov_err_target`) against h per rule (CG with IC(0) / Jacobi for the penalties,
//!   MINRES for Lagrange in both), one panel per family, at the `discretization` accuracy;
//!   runs that missed the target are left out;
//! - `digits_lost`: the direct solve's forward error of u and of the contact forces against
//!   cond₂ of the system, every row, with the first-order bound ε_mach·cond₂;
//! - `raw_vs_jacobi`: cond₂ of the Jacobi-scaled system against the raw one, every row, with
//!   the diagonal;
//! - `leaderboard_pcg`: IC(0)-CG iterations to the error target (MINRES for Lagrange) of
//!   every rule on each family's finest level, at both accuracies;
//! - `eps_map`: the ε map (`constant` over 11 decades of ε on one level per family):
//!   Jacobi-, IC(0)- and scalar-AMG-CG iterations to the error target, misses marked.
//!
//! The ε map's rows appear in `eps_map` only.

use super::Row;
use crate::plot::{method_label, share_legend, Figure, Mark, Series};
use crate::study::shape::Drawing;

/// Reads one value off a row.
type Value = fn(&Row) -> Option<f64>;

/// Reads a Krylov count and whether it reached its target off a row.
type CountOf = fn(&Row) -> (Option<usize>, Option<bool>);

/// Smallest error drawn (an exact value has error 0, which a log axis cannot show).
const FLOOR: f64 = 1e-18;

fn families(rows: &[Row]) -> Vec<String> {
    let mut f: Vec<String> = Vec::new();
    for r in rows {
        if !f.contains(&r.family) {
            f.push(r.family.clone());
        }
    }
    f
}

fn methods(rows: &[Row]) -> Vec<String> {
    let mut m: Vec<String> = Vec::new();
    for r in rows {
        if !m.contains(&r.method) {
            m.push(r.method.clone());
        }
    }
    m
}

/// Panels of iterations against h, one per family.
fn iteration_panels(rows: &[Row], ic0: bool) -> Vec<Figure> {
    let pre = if ic0 { "IC(0)" } else { "Jacobi" };
    families(rows)
        .iter()
        .map(|fam| {
            let mut f = Figure::new(
                format!("{fam}: CG iterations ({pre}; Lagrange: MINRES), error = discretization"),
                "h",
                "iterations to ‖u − u*‖∞ ≤ e‖u*‖∞",
            )
            .log_log();
            for m in methods(rows) {
                let (x, y): (Vec<f64>, Vec<f64>) = rows
                    .iter()
                    .filter(|r| &r.family == fam && r.method == m && r.accuracy != "penetration")
                    .filter_map(|r| {
                        // Lagrange (MINRES) in both panels; a penalty's own preconditioner.
                        let it = if ic0 || r.method == "lagrange" {
                            r.krylov_iters()
                        } else {
                            r.jacobi_iters()
                        };
                        it.map(|i| (r.h, i as f64))
                    })
                    .unzip();
                if !x.is_empty() {
                    f = f.with_series(
                        Series::new(method_label(&m), x, y, Mark::LinePoints).method(&m),
                    );
                }
            }
            f
        })
        .collect()
}

/// Every row as a point `(x, y)`, one series per rule; with the range of x drawn.
fn scatter(
    mut f: Figure,
    rows: &[Row],
    x: Value,
    y: impl Fn(&Row) -> Option<f64>,
) -> (Figure, f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for m in methods(rows) {
        let (xs, ys): (Vec<f64>, Vec<f64>) = rows
            .iter()
            .filter(|r| r.method == m)
            .filter_map(|r| Some((x(r)?, y(r)?)))
            .unzip();
        for &c in &xs {
            (lo, hi) = (lo.min(c), hi.max(c));
        }
        if !xs.is_empty() {
            f = f.with_series(Series::new(method_label(&m), xs, ys, Mark::Points).method(&m));
        }
    }
    (f, lo, hi)
}

/// Forward errors against cond₂ with the ε_mach·cond₂ line.
fn digits_panels(rows: &[Row]) -> Vec<Figure> {
    let pick: [(&str, Value); 2] = [
        ("u", |r| r.forward_err_u),
        ("contact forces", |r| r.forward_err_force),
    ];
    pick.iter()
        .map(|(what, get)| {
            let mut f = Figure::new(
                format!("Direct solve: relative error of {what} vs cond₂ (every row)"),
                "cond₂ of the final system",
                format!("relative error of {what} (∞-norm)"),
            )
            .log_log();
            let (g, lo, hi) = scatter(
                f,
                rows,
                |r| r.cond2_system,
                |r| get(r).map(|v| v.max(FLOOR)),
            );
            f = g;
            if hi > 0.0 {
                let e = f64::EPSILON;
                f = f.with_series(Series::new(
                    "ε_mach · cond₂",
                    vec![lo, hi],
                    vec![e * lo, e * hi],
                    Mark::Dashed,
                ));
            }
            f
        })
        .collect()
}

/// Jacobi-scaled against raw cond₂.
fn raw_vs_jacobi(rows: &[Row]) -> Figure {
    let f = Figure::new(
        "cond₂ after Jacobi scaling vs raw cond₂ (every row)",
        "cond₂ of the final system",
        "cond₂ of S·A·S, S = diag(A)^−½",
    )
    .log_log()
    .with_size(1000, 700);
    let (mut f, lo, hi) = scatter(f, rows, |r| r.cond2_system, |r| r.cond2_jacobi);
    if hi > 0.0 {
        f = f.with_series(Series::new(
            "no change",
            vec![lo, hi],
            vec![lo, hi],
            Mark::Dashed,
        ));
    }
    f
}

/// IC(0) iterations of every rule on each family's finest level: x = the rule's place.
fn leaderboard_panels(rows: &[Row]) -> Vec<Figure> {
    let ms = methods(rows);
    families(rows)
        .iter()
        .map(|fam| {
            let finest = rows
                .iter()
                .filter(|r| &r.family == fam)
                .map(|r| r.level)
                .max()
                .unwrap_or(0);
            let mut f = Figure::new(
                format!("{fam}, finest level: Krylov iterations by rule"),
                "rule (legend order); left of each: error = discretization, right: penetration = δ",
                "IC(0)-CG iterations to the error target (Lagrange: MINRES)",
            )
            .scales(crate::plot::Scale::Linear, crate::plot::Scale::Log10);
            for (k, m) in ms.iter().enumerate() {
                for (acc, dx) in [("discretization", -0.15), ("penetration", 0.15)] {
                    let y: Vec<f64> = rows
                        .iter()
                        .filter(|r| &r.family == fam && &r.method == m && r.level == finest)
                        .filter(|r| {
                            r.accuracy == acc || (r.accuracy == "exact" && acc == "discretization")
                        })
                        .filter_map(|r| r.krylov_iters().map(|i| i as f64))
                        .collect();
                    if !y.is_empty() {
                        let x = vec![(k + 1) as f64 + dx; y.len()];
                        let label = if acc == "discretization" {
                            method_label(m)
                        } else {
                            ""
                        };
                        f = f.with_series(Series::new(label, x, y, Mark::Points).method(m));
                    }
                }
            }
            f
        })
        .collect()
}

/// The ε map: per family, iterations to the error target against ε/k_scale, Jacobi and
/// IC(0); a run that missed the target is drawn as a cross at the iterations it spent (the
/// iteration limit, or where the preconditioned CG broke down).
fn eps_map_panels(map: &[Row]) -> Vec<Figure> {
    families(map)
        .iter()
        .map(|fam| {
            let coupled = super::Family::ALL
                .iter()
                .any(|f| f.name() == fam && f.coupled());
            let rows: Vec<&Row> = map.iter().filter(|r| &r.family == fam).collect();
            let (level, n) = rows.first().map_or((0, 0), |r| (r.level, r.n_dofs));
            let mut f = Figure::new(
                format!(
                    "{fam} ({}), level {level}, {n} DOFs: constant",
                    if coupled {
                        "coupled rows"
                    } else {
                        "one-DOF rows"
                    }
                ),
                "ε / k_scale",
                "CG iterations to ‖u − u*‖∞ ≤ e‖u*‖∞",
            )
            .log_log();
            let pick: [(&str, CountOf); 4] = [
                ("Jacobi", |r| {
                    (
                        r.pcg_iters_jacobi_to_err,
                        r.pcg_iters_jacobi_to_err_converged,
                    )
                }),
                ("IC(0)", |r| {
                    (r.pcg_iters_ic0_to_err, r.pcg_iters_ic0_to_err_converged)
                }),
                ("AMG (scalar)", |r| {
                    (
                        r.pcg_iters_amg_scalar_to_err,
                        r.pcg_iters_amg_scalar_to_err_converged,
                    )
                }),
                ("AMG (nodal)", |r| {
                    (
                        r.pcg_iters_amg_nodal_to_err,
                        r.pcg_iters_amg_nodal_to_err_converged,
                    )
                }),
            ];
            for (k, (name, get)) in pick.iter().enumerate() {
                let point = |ok: bool| {
                    rows.iter()
                        .filter_map(|r| match get(r) {
                            (Some(i), Some(c)) if c == ok => {
                                Some((r.knob_rel?, (i as f64).max(1.0)))
                            }
                            _ => None,
                        })
                        .unzip::<f64, f64, Vec<f64>, Vec<f64>>()
                };
                let (x, y) = point(true);
                if !x.is_empty() {
                    f = f.with_series(
                        Series::new(format!("{name}-CG"), x, y, Mark::LinePoints).color(k),
                    );
                }
                let (x, y) = point(false);
                if !x.is_empty() {
                    f = f.with_series(
                        Series::new(format!("{name}-CG: target missed"), x, y, Mark::Points)
                            .color(k)
                            .glyph(crate::plot::Glyph::Cross),
                    );
                }
            }
            f
        })
        .collect()
}

/// Every drawing (module doc).
pub fn drawings(all: &[Row]) -> crate::error::Result<Vec<Drawing>> {
    let (map, rows): (Vec<Row>, Vec<Row>) = all.iter().cloned().partition(|r| r.in_eps_map());
    let rows = &rows[..];
    let mut out = Vec::new();
    if rows.iter().all(|r| r.cond2_system.is_none()) {
        return Ok(out);
    }
    let grid = |n: usize| (2usize.min(n), (1500u32, 560 * n.div_ceil(2) as u32));
    let mut push = |name: &str, mut panels: Vec<Figure>| -> crate::error::Result<()> {
        if panels.is_empty() {
            return Ok(());
        }
        let (cols, size) = grid(panels.len());
        share_legend(&mut panels, cols, size)?;
        out.push(Drawing {
            name: name.into(),
            panels,
            cols,
            size,
        });
        Ok(())
    };
    push("iterations_ic0", iteration_panels(rows, true))?;
    push("iterations_jacobi", iteration_panels(rows, false))?;
    push("digits_lost", digits_panels(rows))?;
    push("leaderboard_pcg", leaderboard_panels(rows))?;
    push("eps_map", eps_map_panels(&map))?;
    out.push(Drawing::single("raw_vs_jacobi", raw_vs_jacobi(rows)));
    Ok(out)
}
