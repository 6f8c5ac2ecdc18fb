//! The benchmark's figures, from the saved [`Summary`] (the printed tables: [`super::tables`]):
//! - `pressure_<case>`: nodal pressures on the finest mesh against the analytic curve, one
//!   panel per rule, one line per knob value (the flat punch is `pressure_flat-punch`);
//! - `convergence`: Lagrange's pressure error and peak-pressure error against h, per case,
//!   with the least-squares rate in the legend;
//! - `leaderboard_<case>`: penalty error against cond₂ as each rule's knob moves, one panel
//!   per mesh, the mesh's discretization error as a horizontal line;
//! - `domain`: the domain study ([`super::domain`]);
//! - `kappa_sensitivity`: the barrier's penalty error and cond₂ against a fixed κ, per Hertz
//!   case and d̂, with the κ each adaptive rule (`ipc`, `balanced`) ends at ([`super::kappa`]).

use super::record::floor_of;
use super::{analytic::Case, rule_of, BenchRow, Summary};
use crate::error::Result;
use crate::plot::{share_legend, Figure, Glyph, Mark, Marker, Scale, Series};
use crate::study::shape::Drawing;
use crate::study::text::fmt_e;
use std::path::{Path, PathBuf};

/// Errors below this are drawn at this value on log axes.
const FLOOR: f64 = 1e-16;

/// The rules in the rows, in order of first appearance.
fn rules(rows: &[BenchRow]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows {
        let k = rule_of(r);
        if !out.contains(&k) {
            out.push(k);
        }
    }
    out
}

/// The method behind a rule name (`augmented (adaptive)` → `augmented`).
fn method_of(rule: &str) -> &str {
    rule.split(' ').next().unwrap_or(rule)
}

/// A knob value as the legends write it: `ε = 1e2·E*/a`, `f = 10`, `δ = 1e−3·a`, `tol = …`.
pub(super) fn knob_label(knob: &str, k: Option<f64>) -> String {
    let Some(v) = k else {
        return "exact".to_string();
    };
    let v = crate::study::text::fmt_e_trim(v, 3);
    match knob {
        "eps" => format!("ε = {v}·E*/a"),
        "factor" => format!("f = {v}"),
        "delta" => format!("δ = {v}·a"),
        _ => format!("tol = {v}·a"),
    }
}

/// Nodal pressures against Hertz (or the flat punch's uniform pressure), one panel per rule.
fn pressure_panels(s: &Summary, case: Case) -> Vec<Figure> {
    let Some(exact) = s.rows.iter().find(|r| r.case == case.name()) else {
        return Vec::new();
    };
    let (a, p0) = (exact.a_exact, exact.p0_exact);
    let x_max = if case.is_uniform() { a } else { 1.6 * a };
    let xs: Vec<f64> = (0..=200).map(|k| x_max * k as f64 / 200.0).collect();
    let ex = super::analytic::Exact {
        a,
        p0,
        hertzian: !case.is_uniform(),
    };
    let reference = Series::new(
        if case.is_uniform() {
            "exact (uniform)"
        } else {
            "Hertz"
        },
        xs.iter().map(|x| x / a).collect(),
        xs.iter().map(|&x| ex.pressure(x) / p0).collect(),
        Mark::Dashed,
    )
    .color(crate::plot::BLACK_INDEX);
    let mut panels = Vec::new();
    for rule in rules(&s.rows) {
        let profs: Vec<_> = s
            .profiles
            .iter()
            .filter(|p| p.case == case.name() && p.rule == rule)
            .collect();
        if profs.is_empty() {
            continue;
        }
        let h = profs[0].h;
        let mut f = Figure::new(
            format!("{}: {rule} (h = {})", case.name(), fmt_e(h, 1)),
            "x / a",
            "p / p0",
        )
        .with_series(reference.clone());
        for (k, p) in profs.iter().enumerate() {
            // From the axis outwards (two-pass rows: both bodies' nodes, interleaved).
            let mut keep: Vec<usize> = (0..p.x.len()).filter(|&i| p.x[i] <= x_max).collect();
            keep.sort_by(|&i, &j| p.x[i].total_cmp(&p.x[j]));
            f = f.with_series(
                Series::new(
                    knob_label(&p.knob, p.knob_rel),
                    keep.iter().map(|&i| p.x[i] / a).collect(),
                    keep.iter().map(|&i| p.p[i] / p0).collect(),
                    Mark::LinePoints,
                )
                .color(k)
                .glyph(crate::plot::method_glyph(method_of(&rule))),
            );
        }
        panels.push(f);
    }
    panels
}

/// Lagrange's errors against h, per case: the discretization error (Hertz: on the reference
/// block, [`super::domain`]; the rate is its fit), the error on the benchmark's block and its
/// domain error.
fn convergence(s: &Summary) -> Figure {
    let mut f = Figure::new(
        "Lagrange against the analytic solution",
        "h (element size at the contact)",
        "relative error",
    )
    .scales(Scale::Log10, Scale::Log10);
    for (k, case) in Case::ALL.into_iter().enumerate() {
        let lag: Vec<&BenchRow> = s
            .rows
            .iter()
            .filter(|r| r.case == case.name() && r.method == "lagrange" && r.solved())
            .collect();
        if lag.is_empty() {
            continue;
        }
        let rate = s
            .rates
            .iter()
            .find(|(c, _)| c == case.name())
            .and_then(|(_, r)| *r)
            .map_or(String::new(), |r| format!(", rate {r:.2}"));
        let h: Vec<f64> = lag.iter().map(|r| r.h).collect();
        let hertz = !case.is_uniform();
        let disc = if hertz {
            "discretization error (reference block)"
        } else {
            "L2 pressure error"
        };
        f = f.with_series(
            Series::new(
                format!("{}: {disc}{rate}", case.name()),
                h.clone(),
                lag.iter()
                    .map(|r| r.err_discretization.max(FLOOR))
                    .collect(),
                Mark::LinePoints,
            )
            .color(k),
        );
        if hertz {
            f = f.with_series(
                Series::new(
                    format!(
                        "{}: error on the benchmark's block (with its domain error)",
                        case.name()
                    ),
                    h.clone(),
                    lag.iter().map(|r| r.p_err_rel.max(FLOOR)).collect(),
                    Mark::Points,
                )
                .color(k)
                .glyph(Glyph::Square),
            );
            f = f.with_series(
                Series::new(
                    format!("{}: domain error of the benchmark's block", case.name()),
                    h.clone(),
                    lag.iter().map(|r| r.err_domain.max(FLOOR)).collect(),
                    Mark::Points,
                )
                .color(k)
                .glyph(Glyph::Cross),
            );
        }
        if hertz {
            f = f.with_series(
                Series::new(
                    format!(
                        "{}: |p0 − p0_exact| / p0_exact (benchmark's block)",
                        case.name()
                    ),
                    h,
                    lag.iter()
                        .map(|r| ((r.p0_num - r.p0_exact) / r.p0_exact).abs().max(FLOOR))
                        .collect(),
                    Mark::Dashed,
                )
                .color(k),
            );
        }
    }
    f
}

/// The domain study: each Hertz mesh's distance from the reference block against the block
/// size, with a tenth of the finest mesh's discretization error for scale.
fn domain_panels(s: &Summary) -> Vec<Figure> {
    let mut panels = Vec::new();
    for case in [Case::HertzPlane, Case::HertzAxi] {
        let rows: Vec<_> = s.domain.iter().filter(|r| r.case == case.name()).collect();
        let Some(reference) = rows.iter().map(|r| r.block_over_a).reduce(f64::max) else {
            continue;
        };
        let mut f = Figure::new(
            format!(
                "{}: domain error against the {reference}a block (Lagrange)",
                case.name()
            ),
            "block size / a",
            "‖p_block − p_reference‖ / ‖p_exact‖",
        )
        .scales(Scale::Log10, Scale::Log10);
        let mut hs: Vec<f64> = rows.iter().map(|r| r.h).collect();
        hs.sort_by(|a, b| b.total_cmp(a));
        hs.dedup();
        for (k, &h) in hs.iter().enumerate() {
            let (x, y): (Vec<f64>, Vec<f64>) = rows
                .iter()
                .filter(|r| r.h == h && r.block_over_a < reference)
                .map(|r| (r.block_over_a, r.err_domain.max(FLOOR)))
                .unzip();
            f = f.with_series(
                Series::new(format!("h = {}·a", fmt_e(h, 2)), x, y, Mark::LinePoints).color(k),
            );
        }
        let finest = s
            .rows
            .iter()
            .filter(|r| r.case == case.name() && r.method == "lagrange")
            .min_by(|a, b| a.h.total_cmp(&b.h));
        if let Some(r) = finest {
            f = f.hline(
                0.1 * r.err_discretization,
                "a tenth of the finest mesh's discretization error",
            );
        }
        panels.push(f);
    }
    panels
}

/// Penalty error against cond₂ per rule, one panel per mesh.
fn leaderboard_panels(s: &Summary, case: Case) -> Vec<Figure> {
    let mut hs: Vec<f64> = s
        .rows
        .iter()
        .filter(|r| r.case == case.name())
        .map(|r| r.h)
        .collect();
    hs.sort_by(|a, b| b.total_cmp(a));
    hs.dedup();
    let mut panels = Vec::new();
    for h in hs {
        let rows: Vec<&BenchRow> = s
            .rows
            .iter()
            .filter(|r| r.case == case.name() && r.h == h && r.error.is_empty())
            .collect();
        let Some(first) = rows.first() else { continue };
        // Without a Lagrange reference (dependent rows) there is no penalty error to draw.
        if first.err_discretization.is_nan() {
            continue;
        }
        let mut f = Figure::new(
            format!(
                "{}: h = {}, {} DOFs",
                case.name(),
                fmt_e(h, 1),
                first.n_dofs
            ),
            "cond₂ of the system matrix",
            "penalty error ‖p − p_lagrange‖ / ‖p_exact‖",
        )
        .scales(Scale::Log10, Scale::Log10)
        .hline(first.err_discretization, "discretization error");
        // The cond₂ no penalties can go below on this mesh (λ_max(K)/λ_min(K_FF)).
        if let Some(fl) = floor_of(s, case.name(), h).filter(|fl| fl.is_finite()) {
            f = f.vline(fl, "floor");
        }
        for rule in rules(&s.rows) {
            if rule == "lagrange" {
                continue;
            }
            // In knob order, so that the line follows the knob.
            let mut pts: Vec<(f64, f64, f64)> = rows
                .iter()
                .filter(|r| rule_of(r) == rule)
                .filter_map(|r| Some((r.knob_rel?, r.cond2_system?, r.err_penalty.max(FLOOR))))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            if pts.is_empty() {
                continue;
            }
            let dashed = rule.contains("adaptive");
            f = f.with_series(
                // One legend (`plot::share_legend`): the rules are the same in every panel.
                Series::new(
                    rule.clone(),
                    pts.iter().map(|p| p.1).collect(),
                    pts.iter().map(|p| p.2).collect(),
                    if dashed {
                        Mark::Points
                    } else {
                        Mark::LinePoints
                    },
                )
                .method(method_of(&rule)),
            );
        }
        panels.push(f);
    }
    panels
}

/// The κ study's panels: per Hertz case, penalty error and cond₂ against κ, one line per d̂,
/// each rule's end point a marker.
fn kappa_panels(s: &Summary) -> Vec<Figure> {
    let mut panels = Vec::new();
    for case in [Case::HertzPlane, Case::HertzAxi] {
        let rows: Vec<&BenchRow> = s.kappa.iter().filter(|r| r.case == case.name()).collect();
        if rows.is_empty() {
            continue;
        }
        type Measure = fn(&BenchRow) -> Option<f64>;
        let measures: [(&str, Measure); 2] = [
            ("penalty error (distance from Lagrange)", |r| {
                Some(r.err_penalty.max(FLOOR)).filter(|v| v.is_finite())
            }),
            ("cond₂ of the final system", |r| r.cond2_system),
        ];
        for (what, y_of) in measures {
            let h = rows[0].h;
            let mut f = Figure::new(
                format!("{} (h = {}·a): barrier, {what}", case.name(), fmt_e(h, 2)),
                "κ (fixed)",
                what,
            )
            .scales(Scale::Log10, Scale::Log10);
            let mut dhats: Vec<f64> = rows.iter().filter_map(|r| r.knob_rel).collect();
            dhats.sort_by(|a, b| b.total_cmp(a));
            dhats.dedup();
            for (k, &d) in dhats.iter().enumerate() {
                let at = |rule: &'static str| {
                    rows.iter().filter(move |r| {
                        r.knob_rel == Some(d) && r.kappa_rule.as_deref() == Some(rule)
                    })
                };
                let (x, y): (Vec<f64>, Vec<f64>) = at("fixed")
                    .filter_map(|r| Some((r.kappa_final?, y_of(r)?)))
                    .unzip();
                f = f.with_series(
                    Series::new(
                        format!("fixed κ, d̂ = {}·a", fmt_e(d, 0)),
                        x,
                        y,
                        Mark::LinePoints,
                    )
                    .color(k),
                );
                for (j, rule) in ["ipc", "balanced"].into_iter().enumerate() {
                    for r in at(rule) {
                        if let (Some(kx), Some(v)) = (r.kappa_final, y_of(r)) {
                            f = f.with_marker(
                                Marker::new(format!("{rule} rule, d̂ = {}·a", fmt_e(d, 0)), kx, v)
                                    .color(2 + 2 * k + j),
                            );
                        }
                    }
                }
            }
            panels.push(f);
        }
    }
    panels
}

/// Renders every figure into `out/figures`; returns the files written.
pub fn render(out: &Path, s: &Summary) -> Result<Vec<PathBuf>> {
    let dir = out.join("figures");
    let mut files = Vec::new();
    for d in drawings(s)? {
        files.extend(d.render(&dir)?);
    }
    Ok(files)
}

/// Every figure of the record, as [`crate::study::shape::main`] draws them into `OUT/figures`.
pub fn drawings(s: &Summary) -> Result<Vec<Drawing>> {
    let mut out = Vec::new();
    let mut push = |name: String, panels: Vec<Figure>, cols: usize, size: (u32, u32)| {
        out.push(Drawing {
            name,
            panels,
            cols,
            size,
        })
    };
    for case in Case::ALL {
        let p = pressure_panels(s, case);
        if !p.is_empty() {
            let size = (1500, 420 * p.len().div_ceil(3) as u32);
            push(format!("pressure_{}", case.name()), p, 3, size);
        }
        let mut l = leaderboard_panels(s, case);
        if !l.is_empty() {
            let (cols, size) = (l.len().min(3), (1700, 700));
            share_legend(&mut l, cols, size)?;
            push(format!("leaderboard_{}", case.name()), l, cols, size);
        }
    }
    let d = domain_panels(s);
    if !d.is_empty() {
        push("domain".into(), d, 2, (1500, 560));
    }
    let k = kappa_panels(s);
    if !k.is_empty() {
        let size = (1500, 520 * k.len().div_ceil(2) as u32);
        push("kappa_sensitivity".into(), k, 2, size);
    }
    if s.rows.iter().any(|r| r.method == "lagrange" && r.solved()) {
        push("convergence".into(), vec![convergence(s)], 1, (900, 620));
    }
    Ok(out)
}
