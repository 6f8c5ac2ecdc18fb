//! The benchmark's figures and printed tables, from the saved [`Summary`]:
//! - `pressure_<case>`: nodal pressures on the finest mesh against the analytic curve, one
//!   panel per rule, one line per knob value (the flat punch is `pressure_flat-punch`);
//! - `convergence`: Lagrange's pressure error and peak-pressure error against h, per case,
//!   with the least-squares rate in the legend;
//! - `leaderboard_<case>`: penalty error against cond₂ as each rule's knob moves, one panel
//!   per mesh, the mesh's discretization error as a horizontal line;
//! - `kappa_sensitivity`: the barrier's penalty error and cond₂ against a fixed κ, per Hertz
//!   case and d̂, with the κ each adaptive rule (`ipc`, `balanced`) ends at ([`super::kappa`]).

use super::{analytic::Case, rule_of, BenchRow, Summary};
use crate::error::Result;
use crate::plot::{render_panels, share_legend, Figure, Glyph, Mark, Marker, Scale, Series};
use crate::study::text::{fmt_e, table};
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
fn knob_label(knob: &str, k: Option<f64>) -> String {
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
    let x_max = if case == Case::FlatPunch { a } else { 1.6 * a };
    let xs: Vec<f64> = (0..=200).map(|k| x_max * k as f64 / 200.0).collect();
    let ex = super::analytic::Exact {
        a,
        p0,
        hertzian: case != Case::FlatPunch,
    };
    let reference = Series::new(
        if case == Case::FlatPunch {
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
            let keep: Vec<usize> = (0..p.x.len()).filter(|&i| p.x[i] <= x_max).collect();
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
            .filter(|r| r.case == case.name() && r.method == "lagrange")
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
        let hertz = case != Case::FlatPunch;
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
    for case in Case::ALL {
        let p = pressure_panels(s, case);
        if !p.is_empty() {
            let stem = dir.join(format!("pressure_{}", case.name()));
            files.extend(render_panels(
                &p,
                3,
                &stem,
                (1500, 420 * p.len().div_ceil(3) as u32),
            )?);
        }
        let mut l = leaderboard_panels(s, case);
        if !l.is_empty() {
            let stem = dir.join(format!("leaderboard_{}", case.name()));
            let (cols, size) = (l.len().min(3), (1700, 700));
            share_legend(&mut l, cols, size)?;
            files.extend(render_panels(&l, cols, &stem, size)?);
        }
    }
    let d = domain_panels(s);
    if !d.is_empty() {
        let stem = dir.join("domain");
        files.extend(render_panels(&d, 2, &stem, (1500, 560))?);
    }
    let k = kappa_panels(s);
    if !k.is_empty() {
        let stem = dir.join("kappa_sensitivity");
        files.extend(render_panels(
            &k,
            2,
            &stem,
            (1500, 520 * k.len().div_ceil(2) as u32),
        )?);
    }
    if s.rows.iter().any(|r| r.method == "lagrange") {
        let f = convergence(s);
        files.extend(render_panels(
            &[f],
            1,
            &dir.join("convergence"),
            (900, 620),
        )?);
    }
    Ok(files)
}

/// The printed report: Lagrange per mesh (a, p0, errors, rates), then the leaderboard.
pub fn tables(s: &Summary) -> String {
    let mut out = String::from("Lagrange against the analytic solution\n");
    let lag: Vec<Vec<String>> = s
        .rows
        .iter()
        .filter(|r| r.method == "lagrange")
        .map(|r| {
            vec![
                r.case.clone(),
                fmt_e(r.h, 2),
                r.n_dofs.to_string(),
                format!("{:.4}", r.a_num / r.a_exact),
                format!("{:.4}", r.p0_num / r.p0_exact),
                fmt_e(r.err_discretization, 2),
                fmt_e(r.p_err_rel, 2),
                fmt_e(r.err_domain, 2),
                if r.case == Case::FlatPunch.name() {
                    fmt_e(r.p_spread, 1)
                } else {
                    "—".into()
                },
                r.cond2_system.map_or("—".into(), |c| fmt_e(c, 3)),
                floor_of(s, &r.case, r.h).map_or("—".into(), |c| fmt_e(c, 3)),
            ]
        })
        .collect();
    out.push_str(&table(
        &[
            "case",
            "h",
            "DOFs",
            "a/a_exact",
            "p0/p0_exact",
            "discretization",
            "on the block",
            "domain",
            "spread",
            "cond₂",
            "penalty floor",
        ],
        &lag,
        &[
            false, true, true, true, true, true, true, true, true, true, true,
        ],
    ));
    for (case, rate) in &s.rates {
        out.push_str(&format!(
            "{case}: discretization error ∝ h^{}\n",
            rate.map_or("—".into(), |r| format!("{r:.2}"))
        ));
    }
    out.push_str(
        "\nLeaderboard: cheapest knob with penalty error ≤ 0.1 × the discretization error \
         (resolution: cond₂ step to the next softer knob tried; tie: within it of the mesh's best)\n",
    );
    out.push_str(&leader_table(s));
    out
}

/// The mesh's conditioning floor ([`super::Floor`]), where the summary has one.
fn floor_of(s: &Summary, case: &str, h: f64) -> Option<f64> {
    s.floors
        .iter()
        .find(|f| f.case == case && f.h == h)
        .map(|f| f.cond2_floor)
}

fn leader_table(s: &Summary) -> String {
    let rows: Vec<Vec<String>> = s
        .leaderboard
        .iter()
        .filter(|l| l.rule != "lagrange")
        .map(|l| {
            vec![
                l.case.clone(),
                fmt_e(l.h, 2),
                l.rule.clone(),
                match (l.knob_rel, l.tried) {
                    (Some(_), _) => knob_label(&l.knob, l.knob_rel),
                    (None, 0) => "no solve (see rows)".into(),
                    (None, _) => "none within".into(),
                },
                l.cond2_system.map_or("—".into(), |c| fmt_e(c, 3)),
                match (l.cond2_system, floor_of(s, &l.case, l.h)) {
                    (Some(c), Some(f)) if f.is_finite() => format!("{:.3}", c / f),
                    _ => "—".into(),
                },
                l.err_penalty.map_or("—".into(), |e| fmt_e(e, 2)),
                fmt_e(l.err_discretization, 2),
                l.resolution.map_or("—".into(), |r| fmt_e(r, 1)),
                match (l.cond2_system, l.tied_best) {
                    (Some(_), true) => "tie".into(),
                    _ => String::new(),
                },
            ]
        })
        .collect();
    table(
        &[
            "case",
            "h",
            "rule",
            "cheapest knob",
            "cond₂",
            "/ floor",
            "penalty err",
            "discr. err",
            "resolution",
            "best",
        ],
        &rows,
        &[
            false, true, false, true, true, true, true, true, true, false,
        ],
    )
}
