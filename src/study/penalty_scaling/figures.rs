//! The figure of `penalty_scaling`: `penalty_scaling`, one column per discretization and
//! three rows of panels against h, log–log — cond₂ of the final system, cond₂ after Jacobi
//! scaling, and the penalty's own error ‖u − u_L‖∞/w (for `nts-2`, which Lagrange refuses,
//! the error against the exact field, ‖u − u_exact‖∞/w). One curve per rule and schedule:
//! the δ-rules and Lagrange in their colours; `constant` with the fixed ε in its colour, with
//! ε ∝ E/h in brown (palette 9), one glyph per ε_rel.

use super::Row;
use crate::plot::{method_color, share_legend, Figure, Glyph, Mark, Series};
use crate::study::shape::Drawing;

/// Reads one value off a row.
type Value = fn(&Row) -> Option<f64>;

/// The palette index of the `eps-e-over-h` curves (no rule has it).
const E_OVER_H_COLOUR: usize = 9;

/// Glyphs of successive ε_rel values.
const GLYPHS: [Glyph; 4] = [Glyph::Square, Glyph::Cross, Glyph::Triangle, Glyph::Diamond];

fn unique<T: PartialEq>(it: impl Iterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in it {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}

/// The series of one curve's `value` against h.
fn curve(rows: &[&Row], value: impl Fn(&Row) -> Option<f64>, eps_index: usize) -> Option<Series> {
    let first = rows.first()?;
    let (x, y): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| value(r).filter(|v| *v > 0.0).map(|v| (r.h, v)))
        .unzip();
    if x.is_empty() {
        return None;
    }
    let s = Series::new(first.label(), x, y, Mark::LinePoints);
    Some(match first.schedule.as_str() {
        "eps-fixed" => s
            .color(method_color(&first.method))
            .glyph(GLYPHS[eps_index % GLYPHS.len()]),
        "eps-e-over-h" => s
            .color(E_OVER_H_COLOUR)
            .glyph(GLYPHS[eps_index % GLYPHS.len()]),
        _ => s.method(&first.method),
    })
}

/// The panel of `what` against h for `disc`.
fn panel(rows: &[Row], disc: &str, what: &str, value: Value) -> Figure {
    let mut f = Figure::new(format!("{disc}: {what}"), "h (slave element size)", what).log_log();
    let eps = unique(rows.iter().filter_map(|r| r.eps_rel.map(f64::to_bits)));
    let of: Vec<&Row> = rows.iter().filter(|r| r.discretization == disc).collect();
    for key in unique(of.iter().map(|r| r.curve())) {
        let g: Vec<&Row> = of.iter().copied().filter(|r| r.curve() == key).collect();
        let k = key
            .3
            .and_then(|b| eps.iter().position(|e| *e == b))
            .unwrap_or(0);
        if let Some(s) = curve(&g, value, k) {
            f = f.with_series(s);
        }
    }
    f
}

/// Every drawing (module doc).
pub fn drawings(rows: &[Row]) -> crate::error::Result<Vec<Drawing>> {
    let discs = unique(rows.iter().map(|r| r.discretization.clone()));
    if discs.is_empty() {
        return Ok(Vec::new());
    }
    let mut panels = Vec::new();
    let metrics: [(&str, Value); 3] = [
        ("cond₂ of the final system", |r| r.cond2_system),
        ("cond₂ after Jacobi scaling", |r| r.cond2_jacobi),
        (
            "penalty error ‖u − u_L‖∞/w (nts-2: ‖u − u_exact‖∞/w)",
            |r| {
                if r.discretization == "nts-2" {
                    r.err_u
                } else {
                    r.err_penalty
                }
            },
        ),
    ];
    for (what, value) in metrics {
        for d in &discs {
            panels.push(panel(rows, d, what, value));
        }
    }
    let cols = discs.len();
    let size = (620 * cols as u32, 1500);
    share_legend(&mut panels, cols, size)?;
    Ok(vec![Drawing {
        name: "penalty_scaling".into(),
        panels,
        cols,
        size,
    }])
}
