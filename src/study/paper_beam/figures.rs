//! The figures of the study, drawn from the saved data only (so `--render-only` reproduces
//! them): `fig3_deflection_free`, `fig4_deflection_contact`, `cond_vs_eps` and
//! `cond_vs_delta` (PNG + SVG).

use super::deflection::DeflectionRow;
use super::record::CondRow;
use super::record::ConstraintInfo;
use super::Study;
use crate::plot::{method_color, Figure, Mark, Marker, Series};
use crate::strategy::{condensed, lagrange, optimal, paper, spring};
use crate::study::shape::Drawing;
use crate::study::text::fmt_e;

/// Palette index per solution: the strategy's colour (one per method in every figure); the
/// solution without contact in black.
fn color_of(solution: &str) -> usize {
    match solution {
        "free" => crate::plot::BLACK_INDEX,
        s => method_color(s),
    }
}

fn label_of(solution: &str) -> &'static str {
    if solution == "free" {
        "without contact (Eq. 33)"
    } else if solution == paper::STRATEGY.name {
        "Eq. 28 penalties (paper), δ = 0.1"
    } else if solution == condensed::STRATEGY.name {
        "condensed (exact δ-target), δ = 0.1"
    } else if solution == lagrange::STRATEGY.name {
        "Lagrange (exact contact)"
    } else {
        ""
    }
}

fn curve(defl: &[DeflectionRow], solution: &str, kind: &str) -> Vec<DeflectionRow> {
    defl.iter()
        .filter(|r| r.solution == solution && r.kind == kind)
        .cloned()
        .collect()
}

/// A series of `rows` with `y` against x.
fn series(
    label: &str,
    rows: &[DeflectionRow],
    y: impl Fn(&DeflectionRow) -> f64,
    mark: Mark,
) -> Series {
    Series::new(
        label,
        rows.iter().map(|r| r.x).collect(),
        rows.iter().map(y).collect(),
        mark,
    )
}

/// A rigid surface at height `y` over `[x0, x1]` with hatching on the obstacle side
/// (`up` = obstacle above the line).
fn surface(fig: Figure, x0: f64, x1: f64, y: f64, up: bool, hx: f64, hy: f64) -> Figure {
    let mut f = fig.segment((x0, y), (x1, y), 6);
    let n = 8;
    for k in 0..n {
        let x = x0 + (x1 - x0 - hx) * k as f64 / (n - 1) as f64;
        let dy = if up { hy } else { -hy };
        f = f.segment((x, y), (x + hx, y + dy), 6);
    }
    f
}

/// The clamped end at x = 0: a wall over `[y0, y1]`, hatched on the left.
fn clamp(fig: Figure, y0: f64, y1: f64, hx: f64, hy: f64) -> Figure {
    let mut f = fig.segment((0.0, y0), (0.0, y1), 6);
    let n = 6;
    for k in 0..n {
        let y = y0 + (y1 - y0 - hy) * k as f64 / (n - 1) as f64;
        f = f.segment((0.0, y + hy), (-hx, y), 6);
    }
    f
}

/// Fig. 3: deflection without contact.
fn fig3(study: &Study) -> Figure {
    let defl = &study.deflection;
    let c = curve(defl, "free", "curve");
    let nd = curve(defl, "free", "node");
    let xmax = study.record.beam.length_mm;
    let fig = Figure::new(
        "Fig. 3 — beam deflection without contact (K u = q, Eq. 33)",
        "x [mm]",
        "w [mm] (transverse displacement)",
    )
    .with_series(
        series(
            "w(x): Hermite shape functions of the 3 elements",
            &c,
            |r| r.w,
            Mark::Line,
        )
        .color(0),
    )
    .with_series(series("nodes (Eq. 33)", &nd, |r| r.w, Mark::Points).color(1))
    .with_series(
        Series::new(
            "undeformed beam axis; clamped at x = 0",
            vec![0.0, xmax],
            vec![0.0, 0.0],
            Mark::Dashed,
        )
        .color(6),
    )
    .with_size(1000, 620);
    clamp(fig, -5.0, 5.0, 0.8, 1.2)
}

/// Panels (a) w, (b) axial u and (c) w − w_Lagrange of Fig. 4 with the solution curves.
fn fig4_curves(defl: &[DeflectionRow]) -> [Figure; 3] {
    let mut fa = Figure::new("(a) transverse displacement w(x)", "x [mm]", "w [mm]");
    let mut fb = Figure::new("(b) axial displacement u(x)", "x [mm]", "u [mm]");
    let mut fc = Figure::new(
        "(c) difference from the exact (Lagrange) solution",
        "x [mm]",
        "w − w_Lagrange [mm]",
    );
    let lagrange = lagrange::STRATEGY.name;
    let lag_c = curve(defl, lagrange, "curve");
    let lag_n = curve(defl, lagrange, "node");
    for s in [paper::STRATEGY.name, condensed::STRATEGY.name, lagrange] {
        let c = curve(defl, s, "curve");
        let nd = curve(defl, s, "node");
        let col = color_of(s);
        let dash = if s == lagrange {
            Mark::Dashed
        } else {
            Mark::Line
        };
        fa = fa
            .with_series(series(label_of(s), &c, |r| r.w, dash).color(col))
            .with_series(series("", &nd, |r| r.w, Mark::Points).color(col));
        fb = fb
            .with_series(series(label_of(s), &c, |r| r.axial, dash).color(col))
            .with_series(series("", &nd, |r| r.axial, Mark::Points).color(col));
        if s != lagrange && c.len() == lag_c.len() {
            let diff = |a: &[DeflectionRow], b: &[DeflectionRow]| -> Vec<f64> {
                a.iter().zip(b).map(|(a, b)| a.w - b.w).collect()
            };
            let xs = |a: &[DeflectionRow]| -> Vec<f64> { a.iter().map(|r| r.x).collect() };
            fc = fc
                .with_series(
                    Series::new(label_of(s), xs(&c), diff(&c, &lag_c), Mark::Line).color(col),
                )
                .with_series(Series::new("", xs(&nd), diff(&nd, &lag_n), Mark::Points).color(col));
        }
    }
    [fa, fb, fc]
}

/// Fig. 4: deflection with contact, three panels, with the rigid surfaces and ±δ.
fn fig4(study: &Study) -> [Figure; 3] {
    let defl = &study.deflection;
    let constraints = &study.record.beam.constraints;
    let of = |component: &str| -> Vec<&ConstraintInfo> {
        constraints
            .iter()
            .filter(|c| c.component == component)
            .collect()
    };
    let (trans, axial) = (of("transverse"), of("axial"));
    let [mut fa, mut fb, mut fc] = fig4_curves(defl);
    // Rigid surfaces: the obstacle lies on the side the unconstrained solution went to.
    let free_nodes = curve(defl, "free", "node");
    let free_at = |x: f64, f: fn(&DeflectionRow) -> f64| {
        free_nodes
            .iter()
            .find(|r| (r.x - x).abs() < 1e-9)
            .map_or(0.0, f)
    };
    fa = clamp(fa, -4.0, 4.0, 0.8, 1.0);
    fb = clamp(fb, -0.08, 0.08, 0.8, 0.03);
    for c in &trans {
        let up = free_at(c.x, |r| r.w) > c.limit;
        fa = surface(fa, c.x - 3.0, c.x + 3.0, c.limit, up, 0.7, 1.6);
    }
    for c in &axial {
        let up = free_at(c.x, |r| r.axial) > c.limit;
        fb = surface(fb, c.x - 3.0, c.x + 3.0, c.limit, up, 0.7, 0.06);
    }
    let limits_txt = |cs: &[&ConstraintInfo]| {
        cs.iter()
            .map(|c| format!("û(x = {}) = {}", c.x, c.limit))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let legend = |label: String| Series::new(label, vec![], vec![], Mark::Line).color(6);
    fa = fa.with_series(legend(format!("rigid surfaces {}", limits_txt(&trans))));
    fb = fb.with_series(legend(format!("rigid surface {}", limits_txt(&axial))));
    for c in &trans {
        fc = fc.vline(c.x, format!("node {}", c.node));
    }
    let delta = study.record.delta;
    fc = fc
        .hline(0.0, "")
        .hline(delta, format!("+δ = {delta}"))
        .hline(-delta, format!("−δ = −{delta}"));
    [fa, fb, fc]
}

/// The two empty panels of `cond_vs_eps` with the uniform-ε curve and cond₂ K.
fn cond_panels(cond: &[CondRow]) -> (Figure, Figure) {
    let uni: Vec<&CondRow> = cond.iter().filter(|r| r.series == "uniform").collect();
    let cond_k = cond
        .iter()
        .find(|r| r.series == "K")
        .map(|r| r.cond2)
        .unwrap_or(f64::NAN);
    let panel = |title: &str, xlabel: &str, x: fn(&CondRow) -> f64| {
        Figure::new(title, xlabel, "cond₂(K + D E Dᵀ)")
            .log_log()
            .with_series(
                Series::new(
                    "uniform ε (classical penalty)",
                    uni.iter().map(|r| x(r)).collect(),
                    uni.iter().map(|r| r.cond2).collect(),
                    Mark::Line,
                )
                .color(0),
            )
            .hline(cond_k, format!("cond₂ K = {}", fmt_e(cond_k, 4)))
    };
    (
        panel(
            "(a) condition number vs penalty",
            "penalty ε (uniform: ε on all 3 constraints; δ-driven: max_c ε_c)",
            |r| r.eps,
        ),
        panel(
            "(b) condition number vs achieved accuracy",
            "max penetration max_c |g_c| [mm]",
            |r| r.max_penetration,
        ),
    )
}

/// `cond_vs_eps`: cond₂ against ε and against the max penetration, uniform ε and the
/// δ-driven strategies.
fn cond_vs_eps(cond: &[CondRow], delta: f64) -> [Figure; 2] {
    let (mut f1, mut f2) = cond_panels(cond);
    let deltas: Vec<f64> = {
        let mut d: Vec<f64> = cond.iter().filter_map(|r| r.delta).collect();
        d.sort_by(|a, b| b.total_cmp(a));
        d.dedup();
        d
    };
    let dl = deltas
        .iter()
        .map(|d| format!("{d}"))
        .collect::<Vec<_>>()
        .join(", ");
    for (s, name) in [
        (paper::STRATEGY.name, "Eq. 28 (paper)"),
        (condensed::STRATEGY.name, "condensed (exact δ)"),
        (spring::STRATEGY.name, "spring Eq. 17"),
    ] {
        let pts: Vec<&CondRow> = cond.iter().filter(|r| r.series == s).collect();
        // Constraints left unpenalized at every δ (negative ε clipped to 0).
        let zero: Vec<String> = (0..3)
            .filter(|&c| {
                !pts.is_empty() && pts.iter().all(|r| [r.eps_1, r.eps_2, r.eps_3][c] == 0.0)
            })
            .map(|c| format!("ε_{}", c + 1))
            .collect();
        let lab = if zero.is_empty() {
            format!("{name}, δ = {dl}")
        } else {
            format!("{name}, δ = {dl} ({} = 0)", zero.join(" = "))
        };
        let line = |lab: String, x: fn(&CondRow) -> f64| {
            Series::new(
                lab,
                pts.iter().map(|r| x(r)).collect(),
                pts.iter().map(|r| r.cond2).collect(),
                Mark::LinePoints,
            )
            .color(color_of(s))
        };
        f1 = f1.with_series(line(lab.clone(), |r| r.eps));
        f2 = f2.with_series(line(lab, |r| r.max_penetration));
        for r in pts.iter().filter(|r| r.delta == Some(delta)) {
            let lab = if s == paper::STRATEGY.name {
                format!("δ = {delta} (the paper's example)")
            } else {
                String::new()
            };
            f1 = f1.with_marker(Marker::new(lab.clone(), r.eps, r.cond2));
            f2 = f2.with_marker(Marker::new(lab, r.max_penetration, r.cond2));
        }
    }
    for d in &deltas {
        f2 = f2.vline(*d, format!("δ = {d}"));
    }
    [f1, f2]
}

/// `cond_vs_delta`: cond₂ against δ for Eq. 28, `condensed`, `spring` and the cond-optimal
/// penalties, with the certified lower bound of the optimum.
fn cond_vs_delta(rows: &[CondRow], lower: Option<f64>, delta: f64) -> Figure {
    let mut f = Figure::new(
        format!(
            "condition number reachable at allowed penetration δ (dashed: the paper's δ = {delta})"
        ),
        "allowed penetration δ [mm]",
        "cond₂(K + D E Dᵀ)",
    )
    .log_log();
    for (s, name) in [
        (paper::STRATEGY.name, "Eq. 28 (paper)"),
        (
            spring::STRATEGY.name,
            "spring Eq. 17 (penetration may exceed δ)",
        ),
        (
            condensed::STRATEGY.name,
            "condensed (every penalized gap at δ)",
        ),
        (
            optimal::STRATEGY.name,
            "optimal (min cond₂ s.t. penetration ≤ δ)",
        ),
    ] {
        let pts: Vec<&CondRow> = rows.iter().filter(|r| r.series == s).collect();
        f = f.with_series(
            Series::new(
                name,
                pts.iter().filter_map(|r| r.delta).collect(),
                pts.iter().map(|r| r.cond2).collect(),
                Mark::LinePoints,
            )
            .color(color_of(s)),
        );
    }
    if let Some(lb) = lower {
        f = f.hline(
            lb,
            format!(
                "certified lower bound λmax(K)/λmin(K_FF) = {}",
                fmt_e(lb, 4)
            ),
        );
    }
    f.vline(delta, "")
}

/// Renders the three figures into `out` from a saved study ([`super::load`]); returns the
/// files written.
pub fn drawings(study: &Study) -> Vec<Drawing> {
    let mut written = vec![
        Drawing::single("fig3_deflection_free", fig3(study)),
        Drawing {
            name: "fig4_deflection_contact".into(),
            panels: fig4(study).to_vec(),
            cols: 3,
            size: (2100, 700),
        },
        Drawing {
            name: "cond_vs_eps".into(),
            panels: cond_vs_eps(&study.cond, study.record.delta).to_vec(),
            cols: 2,
            size: (1900, 720),
        },
    ];
    if !study.cond_delta.is_empty() {
        let lower = study.record.optimum.as_ref().map(|o| o.cond2_lower_bound);
        written.push(Drawing::single(
            "cond_vs_delta",
            cond_vs_delta(&study.cond_delta, lower, study.record.delta),
        ));
    }
    written
}
