//! The figures of forming runs, drawn from the saved JSON ([`SavedRuns`]): the paper's Fig. 7
//! (four panels: cond₂ of the system matrix and of K alone per step, the ratio to classical,
//! the determinant ratio, the equilibrated cond₂), what each step's system costs a solver
//! (Jacobi-scaled cond₂, CG iterations with Jacobi and IC(0), the direct solve's forward
//! error), punch force vs travel, thickness strain ln(t/t₀) vs initial radius at several
//! depths, deformed profiles with the tools.

use super::record::{SavedRun, SavedRuns};
use crate::forming::config::{ContactRule, FormingConfig};
use crate::forming::solver::StepRecord;
use crate::forming::tools::{Die, Punch};
use crate::plot::{method_color, Figure, Mark, Scale, Series};
use crate::study::shape::Drawing;

fn label(name: &str, run: &SavedRun) -> String {
    let text = rule_label(name, run);
    if run.valid {
        text
    } else {
        format!("{text} [INVALID run]")
    }
}

fn rule_label(name: &str, run: &SavedRun) -> String {
    match run.rule {
        ContactRule::Classical { eps } => format!(
            "{name}: constant ε = {}",
            crate::study::text::fmt_e_trim(eps, 3)
        ),
        ContactRule::PaperResidual { delta } => {
            format!("{name}: Eq. 28 on the residual, δ = {delta:.0e} in")
        }
        ContactRule::PaperLiteral { delta } => {
            format!("{name}: Eq. 28 literal, δ = {delta:.0e} in")
        }
        ContactRule::Condensed { delta } => {
            format!("{name}: exact δ-targeting, δ = {delta:.0e} in")
        }
    }
}

/// The four figures of a saved document: `<cond_stem>` (cond₂ per step;
/// `fig7_condition_per_step` for the deep draw, the paper's Fig. 7), `punch_force_vs_travel`,
/// `thickness_strain`, `deformed_profiles`.
pub fn drawings(doc: &SavedRuns, title: &str, cond_stem: &str) -> Vec<Drawing> {
    let mut files = Vec::new();
    let marked = invalid_title(doc, title);
    let title = marked.as_str();
    let fig7 = if cond_stem.starts_with("fig7") {
        " (paper Fig. 7)"
    } else {
        ""
    };
    let panels = condition_panels(doc, title, fig7);
    files.push(Drawing {
        name: cond_stem.into(),
        panels,
        cols: 2,
        size: (1400, 1040),
    });
    let cost = solver_cost_panels(doc, title);
    if !cost.is_empty() {
        files.push(Drawing {
            name: "solver_cost_per_step".into(),
            panels: cost,
            cols: 2,
            size: (1400, 1040),
        });
    }
    // Punch force vs travel.
    let mut ff = Figure::new(
        format!("{title}: punch force"),
        "punch travel (in)",
        "punch force (ton-force)",
    );
    // The curves coincide to line width for most runs: each run carries its glyph every
    // `stride` steps, staggered so that glyphs of coinciding curves do not cover each other.
    let stride = 2 * doc.runs.len().max(1);
    for (k, (name, run)) in doc.runs.iter().enumerate() {
        ff = ff.with_series(
            Series::new(
                label(name, run),
                run.steps.iter().map(|s| s.punch_travel).collect(),
                run.steps.iter().map(|s| s.punch_force).collect(),
                Mark::LinePoints,
            )
            .method(name)
            .glyph_every(2 * k + 1, stride),
        );
    }
    files.push(Drawing::single("punch_force_vs_travel", ff));
    // Thickness strain vs initial radius, one panel per run.
    let panels: Vec<Figure> = doc
        .runs
        .iter()
        .map(|(name, run)| {
            let panel = if doc.valid {
                label(name, run)
            } else {
                format!("INVALID {}", label(name, run))
            };
            let mut f = Figure::new(panel, "initial radius (in)", "thickness strain ln(t/t₀)");
            for (k, s) in run.snapshots.iter().enumerate() {
                f = f.with_series(
                    Series::new(
                        format!("travel {:.2} in", s.travel),
                        s.r0.clone(),
                        s.thickness_strain.clone(),
                        Mark::LinePoints,
                    )
                    .color(k),
                );
            }
            f
        })
        .collect();
    if !panels.is_empty() && panels.iter().all(|p| !p.series.is_empty()) {
        let cols = panels.len().min(3);
        files.push(Drawing {
            name: "thickness_strain".into(),
            panels,
            cols,
            size: (650 * cols as u32, 520),
        });
    }
    // Deformed profiles with tools (the classical run if present: its penetration is
    // negligible).
    let pick = doc
        .runs
        .get_key_value("classical")
        .or_else(|| doc.runs.iter().next())
        .filter(|(_, r)| !r.snapshots.is_empty());
    if let Some((name, run)) = pick {
        files.push(Drawing::single(
            "deformed_profiles",
            profiles_figure(&doc.config, name, run, title),
        ));
    }
    files
}

/// `(step, y)` of one run's steps.
fn per_step(run: &SavedRun, y: impl Fn(&StepRecord) -> f64) -> (Vec<f64>, Vec<f64>) {
    (
        run.steps.iter().map(|s| s.step as f64).collect(),
        run.steps.iter().map(y).collect(),
    )
}

/// The four panels of the condition figure (paper Fig. 7 and its claims): (a) cond₂ of the
/// main system of every run and of K alone (no contact terms); (b) cond₂(classical) /
/// cond₂(run) per step; (c) log10 |K + D E Dᵀ| / |K|; (d) cond₂ after diagonal
/// equilibration (the scaling hypothesis for our absolute levels).
fn condition_panels(doc: &SavedRuns, title: &str, fig7: &str) -> Vec<Figure> {
    let mut a = Figure::new(
        format!("{title}: (a) cond₂ of the main system per step{fig7}"),
        "time step",
        "cond₂",
    )
    .scales(Scale::Linear, Scale::Log10);
    let mut b = Figure::new(
        "(b) cond₂ classical / run, > 1: run better (dashed: vs matched)",
        "time step",
        "ratio",
    )
    .scales(Scale::Linear, Scale::Log10)
    .hline(1.0, "1")
    .hline(100.0, "100");
    let mut c = Figure::new(
        "(c) determinant ratio log10 |K + D E Dᵀ| / |K|",
        "time step",
        "log10 det ratio",
    );
    let mut d = Figure::new(
        "(d) cond₂ after diagonal equilibration S A S, S ≈ diag(A)^(-1/2)",
        "time step",
        "cond₂ (equilibrated)",
    )
    .scales(Scale::Linear, Scale::Log10);
    let classical = doc.runs.get("classical");
    let matched = doc.runs.get(super::CLASSICAL_MATCHED);
    let ratio_to = |cl: &SavedRun, run: &SavedRun| -> (Vec<f64>, Vec<f64>) {
        cl.steps
            .iter()
            .zip(&run.steps)
            .map(|(c, r)| (r.step as f64, c.cond2 / r.cond2))
            .unzip()
    };
    for (name, run) in &doc.runs {
        let col = method_color(name);
        // Dashed: the matched classical run (it shares the classical colour) and condensed
        // (it lies on the adaptive curve in every panel).
        let mark = if name == super::CLASSICAL_MATCHED
            || matches!(run.rule, ContactRule::Condensed { .. })
        {
            Mark::Dashed
        } else {
            Mark::Line
        };
        let (x, y) = per_step(run, |s| s.cond2);
        a = a.with_series(Series::new(label(name, run), x, y, mark).color(col));
        if let (Some(cl), false) = (classical, name == "classical") {
            // Panel (b): solid against ε = 1e7, dashed against the matched run.
            let (x, y) = ratio_to(cl, run);
            let solid = if name == super::CLASSICAL_MATCHED {
                Mark::Dashed
            } else {
                Mark::Line
            };
            b = b.with_series(Series::new(name.clone(), x, y, solid).color(col));
        }
        let skip =
            matches!(run.rule, ContactRule::Classical { .. }) || super::diagnostic_only(&run.rule);
        if let (Some(cl), false) = (matched, skip) {
            let (x, y) = ratio_to(cl, run);
            let lab = format!("{name} vs {}", super::CLASSICAL_MATCHED);
            b = b.with_series(Series::new(lab, x, y, Mark::Dashed).color(col));
        }
        let (x, y) = per_step(run, |s| s.log10_det_ratio);
        c = c.with_series(Series::new(name.clone(), x, y, mark).color(col));
        let (x, y) = per_step(run, |s| s.cond2_equilibrated);
        d = d.with_series(Series::new(name.clone(), x, y, mark).color(col));
    }
    // K alone of one run (its μ* field; the runs' K alone agree to a few per cent).
    if let Some((name, run)) = doc
        .runs
        .get_key_value("adaptive")
        .or_else(|| doc.runs.iter().next())
    {
        let k = method_color("K alone");
        let (x, y) = per_step(run, |s| s.cond2_k);
        a = a.with_series(
            Series::new(
                format!("K alone, no contact terms ({name} run)"),
                x,
                y,
                Mark::Dashed,
            )
            .color(k),
        );
        let (x, y) = per_step(run, |s| s.cond2_k_equilibrated);
        d = d
            .with_series(Series::new(format!("K alone ({name} run)"), x, y, Mark::Dashed).color(k));
    }
    vec![a, b, c, d]
}

/// What each step's last system costs a solver, per run: (a) cond₂ after Jacobi scaling,
/// (b) CG iterations with Jacobi to the fixed error of the velocities, (c) with IC(0), (d) the
/// direct solve's forward error of the velocities. Empty for records written before these
/// metrics; steps whose run missed the error target are left out.
fn solver_cost_panels(doc: &SavedRuns, title: &str) -> Vec<Figure> {
    if !doc
        .runs
        .values()
        .any(|r| r.steps.iter().any(|s| s.cond2_jacobi.is_finite()))
    {
        return Vec::new();
    }
    let panel = |t: &str, y: &str| {
        Figure::new(format!("{title}: {t}"), "time step", y).scales(Scale::Linear, Scale::Log10)
    };
    let getters: [fn(&StepRecord) -> f64; 4] = [
        |s| s.cond2_jacobi,
        |s| s.jacobi_iters_to_err().map_or(f64::NAN, |i| i as f64),
        |s| s.ic0_iters_to_err().map_or(f64::NAN, |i| i as f64),
        |s| s.forward_err_u.max(1e-18),
    ];
    let titles = [
        (
            "(a) cond₂ of S A S, S = diag(A)^(−1/2)",
            "cond₂ (Jacobi-scaled)",
        ),
        (
            "(b) CG iterations, Jacobi, to ‖v − v*‖∞ ≤ 1e-6‖v*‖∞",
            "iterations",
        ),
        (
            "(c) CG iterations, IC(0), to ‖v − v*‖∞ ≤ 1e-6‖v*‖∞",
            "iterations",
        ),
        (
            "(d) direct solve: relative error of the velocities",
            "forward error (∞-norm)",
        ),
    ];
    titles
        .iter()
        .zip(getters)
        .map(|((t, y), get)| {
            let mut f = panel(t, y);
            for (name, run) in &doc.runs {
                let mark = if name == super::CLASSICAL_MATCHED
                    || matches!(run.rule, ContactRule::Condensed { .. })
                {
                    Mark::Dashed
                } else {
                    Mark::Line
                };
                let (x, y) = per_step(run, get);
                f = f.with_series(
                    Series::new(label(name, run), x, y, mark).color(method_color(name)),
                );
            }
            f
        })
        .collect()
}

/// The figure title prefix: `title`, or for a run outside the model's domain
/// `INVALID (<first reason>[, +k more]) <title>`.
fn invalid_title(doc: &SavedRuns, title: &str) -> String {
    match doc.invalid_reasons.split_first() {
        None if doc.valid => title.to_string(),
        None => format!("INVALID {title}"),
        Some((first, rest)) => {
            let more = if rest.is_empty() {
                String::new()
            } else {
                format!(", +{} more", rest.len())
            };
            format!("INVALID ({first}{more}) {title}")
        }
    }
}

fn profiles_figure(cfg: &FormingConfig, name: &str, run: &SavedRun, title: &str) -> Figure {
    let mut f = Figure::new(
        format!(
            "{title}: deformed mid-surface and tools ({})",
            label(name, run)
        ),
        "r (in)",
        "z (in)",
    )
    .with_size(1000, 600);
    let die = Die {
        opening_radius: cfg.die.opening_radius,
        profile_radius: cfg.die.profile_radius,
        face_z: -0.5 * cfg.thickness,
    };
    let depth = cfg.travel + 0.2;
    let pts = die.outline(depth, cfg.blank_radius * 1.05);
    f = f.with_series(
        Series::new(
            "die",
            pts.iter().map(|p| p[0]).collect(),
            pts.iter().map(|p| p[1]).collect(),
            Mark::Line,
        )
        .color(6),
    );
    for (k, s) in run.snapshots.iter().enumerate() {
        let punch = Punch {
            radius: cfg.punch.radius,
            profile_radius: cfg.punch.profile_radius.unwrap_or(cfg.punch.radius),
            tip_z: s.punch_tip_z,
        };
        let pts = punch.outline(cfg.punch.radius.max(0.3));
        f = f.with_series(
            Series::new(
                if k + 1 == run.snapshots.len() {
                    "punch".to_string()
                } else {
                    String::new()
                },
                pts.iter().map(|p| p[0]).collect(),
                pts.iter().map(|p| p[1]).collect(),
                Mark::Dashed,
            )
            .color(k),
        );
        f = f.with_series(
            Series::new(
                format!("sheet, travel {:.2} in", s.travel),
                s.r.clone(),
                s.z.clone(),
                Mark::LinePoints,
            )
            .color(k),
        );
    }
    f
}
