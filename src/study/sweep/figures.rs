//! Sweep figures: conditioning, penetration and the ratio of main determinants against the
//! penalty, and the conditioning–penetration trade-off, one set per scene family.
//!
//! Every figure summarises the rows of one family over its scenes: for each (method, knob)
//! group the **median over scenes** is drawn, and for the classical `constant` penalty also a
//! band of the **10–90 % quantiles** over scenes (linear interpolation, see [`quantile`]).
//! Groups are formed by the knob: `eps` for `constant`, `factor` for `scaled`, `delta_rel`
//! (δ relative to the scene's displacement scale max_c |u0\[d_c\]|) or, when absent, the
//! absolute `delta` for `spring`, `paper`, `condensed`, and the tolerance (`delta_rel` or `delta`)
//! for `augmented` (whose ε the sweep picks per scene).
//! Only finite metric values enter a median; non-positive values are not drawn on log axes.
//!
//! Files written by [`render_all`] (each as `.png` and `.svg`), with `<family>` the family name
//! (`beam`, `membrane`, `spectrum`, `file`; other characters than ASCII letters, digits, `-`
//! and `_` become `_`):
//!
//! | stem | x | y |
//! |---|---|---|
//! | `cond_vs_eps_<family>` | ε (log) | cond₂(K + D E Dᵀ) (log) |
//! | `penetration_vs_eps_<family>` | ε (log) | max penetration (log)¹ |
//! | `pareto_<family>` | max penetration (log)¹ | cond₂(K + D E Dᵀ) (log); the `optimal` frontier drawn first, under the strategies |
//! | `log_det_ratio_vs_eps_<family>` | ε (log) | log10\|det(K + D E Dᵀ)\| − log10\|det K\| |
//!
//! ¹ Relative to each scene's displacement scale max_c |u0\[d_c\]| when that is known for every
//! scene of the family (it is `delta / delta_rel` of any row run with a relative δ — the sweep's
//! default), so that scenes of different size share one axis and the adaptive methods sit at
//! their relative δ; otherwise in absolute units of u. The axis label says which.
//!
//! In the three "vs ε" figures the adaptive methods (`spring`, `paper`, `condensed`) have no
//! single ε: each of their δ values is drawn at x = the median over scenes of the largest
//! penalty ε_c they used (`eps_max`). ε is in each scene's own stiffness units (the rows carry
//! no stiffness scale to normalise by), which the axis label says. A method that penalised
//! no constraint at any δ (no `eps_max`) has no place on that axis and gets a legend-only
//! entry saying so. A figure whose data are all missing (e.g. `cond2_system` not requested)
//! is not written.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::plot::{method_color, method_label, render, Band, Figure, Mark, Marker, Scale, Series};
use crate::stats::quantile;
use crate::strategy::{augmented, constant, lagrange, optimal, registry, scaled};
use crate::study::shape::Drawing;
use crate::study::sweep::rows::Row;
use crate::{Error, Result};

/// The figure kinds, i.e. the file-name prefixes: the files are `<kind>_<family>.{png,svg}`.
pub const FIGURE_KINDS: [&str; 4] = [
    "cond_vs_eps",
    "penetration_vs_eps",
    "pareto",
    "log_det_ratio_vs_eps",
];

/// Lower and upper quantile of the spread band drawn around the `constant` median.
const BAND_Q: (f64, f64) = (0.1, 0.9);

/// Image size of every sweep figure (px).
const SIZE: (u32, u32) = (1000, 700);

/// Label of the system matrix' condition number.
const COND_SYS: &str = "cond₂(K + D E Dᵀ)";
/// x label of the "vs ε" figures.
const EPS_LABEL: &str =
    "penalty ε (scene stiffness units; adaptive methods: largest ε_c used, median over scenes)";
/// Label of the penetration axis.
const PEN_LABEL: &str = "max penetration (units of u)";
/// Label of the penetration axis when normalised by each scene's displacement scale.
const PEN_REL_LABEL: &str = "max penetration / max_c |u0[d_c]|";

/// Builds every sweep figure without rendering it: `(file stem, figure)` pairs, families in
/// the order beam, membrane, spectrum, file, then any other alphabetically; within a family
/// in [`FIGURE_KINDS`] order. Figures without any drawable point are left out, so the result
/// may be empty (e.g. when no metric was requested).
pub fn build_figures(rows: &[Row]) -> Vec<(String, Figure)> {
    let mut out = Vec::new();
    for fam in families(rows) {
        let stem = |kind: &str| format!("{kind}_{}", file_safe(&fam.name));
        let figs = [
            cond_vs_eps(&fam),
            penetration_vs_eps(&fam),
            pareto(&fam),
            log_det_ratio_vs_eps(&fam),
        ];
        for (kind, fig) in FIGURE_KINDS.iter().zip(figs) {
            if has_data(&fig) {
                out.push((stem(kind), fig));
            }
        }
    }
    out
}

/// Renders every sweep figure (PNG + SVG) from rows into `dir`; returns the files written.
///
/// See the [module docs](self) for the file names and what each figure shows. `dir` is created
/// when missing. Figures that would have no data (e.g. `cond2_system` empty in every row) are
/// skipped, not an error.
///
/// Errors: [`Error::NoneGiven`] for an empty row set; [`Error::Io`] when `dir` or a file cannot be
/// written.
pub fn render_all(rows: &[Row], dir: &Path) -> Result<Vec<PathBuf>> {
    if rows.is_empty() {
        return Err(Error::none_given("sweep figures: rows to plot", ""));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir.display(), e))?;
    let mut written = Vec::new();
    for (stem, fig) in build_figures(rows) {
        written.extend(render(&fig, &dir.join(stem))?);
    }
    Ok(written)
}

/// [`build_figures`], one drawing each (none without rows).
pub fn drawings(rows: &[Row]) -> Vec<Drawing> {
    build_figures(rows)
        .into_iter()
        .map(|(stem, fig)| Drawing::single(stem, fig))
        .collect()
}

/// Renders the figures of the run in `out` from `out/rows.csv` into `out/figures`: the files
/// written, or an empty list when rows.csv holds no rows.
pub fn render_run(out: &Path) -> Result<Vec<PathBuf>> {
    let (rows, _) = super::rows::read_rows(&out.join("rows.csv"), false)?;
    if rows.is_empty() {
        return Ok(Vec::new());
    }
    render_all(&rows, &out.join("figures"))
}

// ---------------------------------------------------------------------------------------------
// Grouping and statistics
// ---------------------------------------------------------------------------------------------

/// The rows of one family. When every scene's displacement scale max_c |u0\[d_c\]| is known
/// (see [`scene_scales`]), `max_penetration` has been divided by it and `relative` is set.
struct Fam {
    name: String,
    rows: Vec<Row>,
    scenes: usize,
    relative: bool,
}

impl Fam {
    fn method(&self, name: &str) -> Vec<&Row> {
        self.rows.iter().filter(|r| r.method == name).collect()
    }
    fn all(&self) -> Vec<&Row> {
        self.rows.iter().collect()
    }
    fn title(&self, what: &str) -> String {
        let s = if self.scenes == 1 { "scene" } else { "scenes" };
        format!("{}: {what} ({} {s})", self.name, self.scenes)
    }
    fn pen_label(&self) -> &'static str {
        if self.relative {
            PEN_REL_LABEL
        } else {
            PEN_LABEL
        }
    }
}

/// Each scene's displacement scale max_c |u0\[d_c\]|, recovered as `delta / delta_rel` from
/// any row run with a relative δ (adaptive methods, augmented). `None` unless every scene has
/// one.
fn scene_scales<'a>(rows: &[&'a Row]) -> Option<BTreeMap<&'a str, f64>> {
    let mut out = BTreeMap::new();
    for r in rows {
        if let (Some(d), Some(rel)) = (r.delta, r.delta_rel) {
            let s = d / rel;
            if s.is_finite() && s > 0.0 {
                out.entry(r.scene.as_str()).or_insert(s);
            }
        }
    }
    rows.iter()
        .all(|r| out.contains_key(r.scene.as_str()))
        .then_some(out)
}

fn families(rows: &[Row]) -> Vec<Fam> {
    let names: BTreeSet<&str> = rows.iter().map(|r| r.family.as_str()).collect();
    let rank = |n: &str| {
        [
            "beam",
            "membrane",
            "spectrum",
            "hertz",
            "flat-punch",
            "file",
        ]
        .iter()
        .position(|k| *k == n)
        .unwrap_or(6)
    };
    let mut names: Vec<&str> = names.into_iter().collect();
    names.sort_by_key(|n| (rank(n), *n));
    names
        .into_iter()
        .map(|name| {
            let refs: Vec<&Row> = rows.iter().filter(|r| r.family == name).collect();
            let scenes = refs
                .iter()
                .map(|r| r.scene.as_str())
                .collect::<BTreeSet<_>>()
                .len();
            let scales = scene_scales(&refs);
            let rows = refs
                .iter()
                .map(|r| {
                    let mut r = (*r).clone();
                    if let Some(s) = scales.as_ref().and_then(|m| m.get(r.scene.as_str())) {
                        r.max_penetration = r.max_penetration.map(|p| p / s);
                    }
                    r
                })
                .collect();
            Fam {
                name: name.to_string(),
                rows,
                scenes,
                relative: scales.is_some(),
            }
        })
        .collect()
}

fn file_safe(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "unnamed".to_string()
    } else {
        s
    }
}

/// Rows grouped by a knob, ascending; rows without a finite knob are dropped, knobs equal to
/// relative 1e-9 share a group.
fn groups<'a>(rows: &[&'a Row], key: impl Fn(&Row) -> Option<f64>) -> Vec<(f64, Vec<&'a Row>)> {
    let mut keyed: Vec<(f64, &Row)> = rows
        .iter()
        .filter_map(|r| key(r).filter(|k| k.is_finite()).map(|k| (k, *r)))
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, Vec<&Row>)> = Vec::new();
    for (k, r) in keyed {
        match out.last_mut() {
            Some((k0, g)) if (k - *k0).abs() <= 1e-9 * k.abs().max(k0.abs()) => g.push(r),
            _ => out.push((k, vec![r])),
        }
    }
    out
}

/// A metric of a row.
type Metric = fn(&Row) -> Option<f64>;

fn m_cond(r: &Row) -> Option<f64> {
    r.cond2_system
}
fn m_pen(r: &Row) -> Option<f64> {
    r.max_penetration
}
fn m_det(r: &Row) -> Option<f64> {
    r.log10_det_ratio
}
fn m_eps_max(r: &Row) -> Option<f64> {
    r.eps_max
}

/// Median and band quantiles over the finite values of a metric; `n` values.
#[derive(Clone, Copy)]
struct Stat {
    med: f64,
    lo: f64,
    hi: f64,
    n: usize,
}

fn stat(rows: &[&Row], m: Metric) -> Stat {
    let mut v: Vec<f64> = rows
        .iter()
        .filter_map(|r| m(r))
        .filter(|x| x.is_finite())
        .collect();
    Stat {
        med: quantile(&mut v, 0.5),
        lo: quantile(&mut v, BAND_Q.0),
        hi: quantile(&mut v, BAND_Q.1),
        n: v.len(),
    }
}

fn median(rows: &[&Row], m: Metric) -> f64 {
    stat(rows, m).med
}

/// Median of a per-scene quantity (one value per scene: the first finite one).
fn scene_median(rows: &[&Row], m: Metric) -> f64 {
    let mut seen = BTreeSet::new();
    let mut v: Vec<f64> = Vec::new();
    for r in rows {
        if let Some(x) = m(r).filter(|x| x.is_finite()) {
            if seen.insert(r.scene.as_str()) {
                v.push(x);
            }
        }
    }
    quantile(&mut v, 0.5)
}

/// The δ groups of one adaptive (or augmented) method: relative δ (`delta_rel`) where given,
/// absolute δ otherwise, kept apart.
struct DeltaSet<'a> {
    relative: bool,
    groups: Vec<(f64, Vec<&'a Row>)>,
}

fn delta_sets<'a>(rows: &[&'a Row]) -> Vec<DeltaSet<'a>> {
    let rel: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| r.delta_rel.is_some())
        .collect();
    let abs: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| r.delta_rel.is_none())
        .collect();
    [
        (true, groups(&rel, |r| r.delta_rel)),
        (false, groups(&abs, |r| r.delta)),
    ]
    .into_iter()
    .filter(|(_, g)| !g.is_empty())
    .map(|(relative, groups)| DeltaSet { relative, groups })
    .collect()
}

// ---------------------------------------------------------------------------------------------
// Labels
// ---------------------------------------------------------------------------------------------

/// `0.01 → "1e-2"`, `0.0025 → "2.5e-3"`, `1e4 → "1e4"` (3 significant digits at most).
fn num(v: f64) -> String {
    if !(v.is_finite() && v != 0.0) {
        return format!("{v}");
    }
    let k = v.abs().log10().floor();
    let mut m = v / 10f64.powf(k);
    let mut k = k as i64;
    m = (m * 100.0).round() / 100.0;
    if m.abs() >= 10.0 {
        m /= 10.0;
        k += 1;
    }
    let ms = format!("{m:.2}");
    let ms = ms.trim_end_matches('0').trim_end_matches('.');
    format!("{ms}e{k}")
}

/// `δ = 1e-1, 1e-2·|u0|` (relative) or `δ = 1e-3` (absolute), `what` instead of `δ` if given.
fn delta_list(what: &str, deltas: &[f64], relative: bool) -> String {
    let list: Vec<String> = deltas.iter().map(|&d| num(d)).collect();
    let unit = if relative { "·|u0|" } else { "" };
    format!("{what} = {}{unit}", list.join(", "))
}

// ---------------------------------------------------------------------------------------------
// Figures
// ---------------------------------------------------------------------------------------------

fn drawable(s: Scale, v: f64) -> bool {
    v.is_finite() && (s == Scale::Linear || v > 0.0)
}

fn has_data(fig: &Figure) -> bool {
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    fig.series.iter().any(|s| {
        s.x.iter()
            .zip(&s.y)
            .any(|(&x, &y)| drawable(xs, x) && drawable(ys, y))
    }) || fig.bands.iter().any(|b| {
        b.x.iter()
            .zip(b.lo.iter().zip(&b.hi))
            .any(|(&x, (&lo, &hi))| drawable(xs, x) && drawable(ys, lo) && drawable(ys, hi))
    }) || fig
        .markers
        .iter()
        .any(|m| drawable(xs, m.x) && drawable(ys, m.y))
}

/// Common part of the three "vs ε" figures: `constant` median + 10–90 % band over its ε grid,
/// and the adaptive methods at (median largest ε_c, median metric) per δ.
fn eps_figure(fam: &Fam, metric: Metric, title: &str, y_label: &str, y_scale: Scale) -> Figure {
    let mut fig = Figure::new(fam.title(title), EPS_LABEL, y_label)
        .scales(Scale::Log10, y_scale)
        .with_size(SIZE.0, SIZE.1);

    let constant = groups(&fam.method(constant::STRATEGY.name), |r| r.eps);
    if !constant.is_empty() {
        let xs: Vec<f64> = constant.iter().map(|g| g.0).collect();
        let st: Vec<Stat> = constant.iter().map(|g| stat(&g.1, metric)).collect();
        if st.iter().any(|s| s.n >= 2) {
            fig = fig.with_band(
                Band::new(
                    "constant ε: 10–90 % of scenes",
                    xs.clone(),
                    st.iter().map(|s| s.lo).collect(),
                    st.iter().map(|s| s.hi).collect(),
                )
                .color(method_color(constant::STRATEGY.name)),
            );
        }
        fig = fig.with_series(
            Series::new(
                "constant ε: median over scenes",
                xs,
                st.iter().map(|s| s.med).collect(),
                Mark::Line,
            )
            .method(constant::STRATEGY.name),
        );
    }

    // The δ-driven rules, in registry order (colours and legend names from their
    // descriptors, as in every figure).
    for name in registry::delta_rules().into_iter().map(|s| s.name) {
        let legend = method_label(name);
        for set in delta_sets(&fam.method(name)) {
            let pts: Vec<(f64, f64, f64)> = set
                .groups
                .iter()
                .map(|(d, g)| (*d, median(g, m_eps_max), median(g, metric)))
                .collect();
            // Legend: δ values in the order the points appear from left to right.
            let mut shown: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| drawable(Scale::Log10, p.1) && drawable(y_scale, p.2))
                .map(|p| (p.1, p.0))
                .collect();
            if shown.is_empty() {
                // Solved, but no penalty anywhere (e.g. every ε_c ≤ 0 was set to 0): there is
                // no ε to place it at; say so in the legend rather than dropping it silently.
                let solved = set
                    .groups
                    .iter()
                    .any(|(_, g)| g.iter().any(|r| metric(r).is_some_and(f64::is_finite)));
                let penalised = set.groups.iter().any(|(_, g)| {
                    g.iter()
                        .any(|r| r.eps_max.is_some_and(|e| e.is_finite() && e > 0.0))
                });
                if solved && !penalised {
                    fig = fig.with_series(
                        Series::new(
                            format!("{legend}: no constraint penalised at any δ (not drawn)"),
                            Vec::new(),
                            Vec::new(),
                            Mark::LinePoints,
                        )
                        .method(name),
                    );
                }
                continue;
            }
            shown.sort_by(|a, b| a.0.total_cmp(&b.0));
            let deltas: Vec<f64> = shown.iter().map(|p| p.1).collect();
            let order = if deltas.len() > 1 {
                " (left to right)"
            } else {
                ""
            };
            let label = format!(
                "{legend} at {}{order}",
                delta_list("δ", &deltas, set.relative)
            );
            fig = fig.with_series(
                Series::new(
                    label,
                    pts.iter().map(|p| p.1).collect(),
                    pts.iter().map(|p| p.2).collect(),
                    Mark::LinePoints,
                )
                .method(name),
            );
        }
    }
    let x_of = |r: &Row| {
        if r.method == constant::STRATEGY.name {
            r.eps
        } else {
            r.eps_max
        }
    };
    mark_not_converged(fig, &fam.rows, x_of, metric)
}

/// Marks every solve whose strategy did not converge (`converged = false`) at its own (x, y),
/// in black, with one legend entry that counts them: medians hide single rows, these do not.
fn mark_not_converged(
    mut fig: Figure,
    rows: &[Row],
    x: impl Fn(&Row) -> Option<f64>,
    y: Metric,
) -> Figure {
    let bad: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.converged == Some(false))
        .filter_map(|r| Some((x(r)?, y(r)?)))
        .collect();
    for (i, &(x, y)) in bad.iter().enumerate() {
        let label = if i == 0 {
            match bad.len() {
                1 => "NOT CONVERGED (1 solve, at its own value)".to_string(),
                n => format!("NOT CONVERGED ({n} solves, each at its own value)"),
            }
        } else {
            String::new()
        };
        fig = fig.with_marker(Marker::new(label, x, y));
    }
    fig
}

fn cond_vs_eps(fam: &Fam) -> Figure {
    let mut fig = eps_figure(
        fam,
        m_cond,
        "conditioning of the penalized system vs ε",
        COND_SYS,
        Scale::Log10,
    );
    let k = scene_median(&fam.all(), |r| r.cond2_k);
    if drawable(Scale::Log10, k) && has_data(&fig) {
        fig = fig.hline(k, format!("cond₂(K) = {} (median over scenes)", num(k)));
    }
    fig
}

fn penetration_vs_eps(fam: &Fam) -> Figure {
    eps_figure(
        fam,
        m_pen,
        "penetration vs ε",
        fam.pen_label(),
        Scale::Log10,
    )
}

fn log_det_ratio_vs_eps(fam: &Fam) -> Figure {
    eps_figure(
        fam,
        m_det,
        "ratio of main determinants vs ε",
        "log10|det(K + D E Dᵀ)| − log10|det K|",
        Scale::Linear,
    )
}

/// Median (penetration, cond) per knob group, in knob order.
fn pareto_points(groups: &[(f64, Vec<&Row>)]) -> (Vec<f64>, Vec<f64>) {
    groups
        .iter()
        .map(|(_, g)| (median(g, m_pen), median(g, m_cond)))
        .unzip()
}

fn pareto(fam: &Fam) -> Figure {
    let mut fig = Figure::new(
        fam.title("conditioning vs penetration, medians over scenes"),
        format!("{}, median over scenes", fam.pen_label()),
        format!("{COND_SYS}, median over scenes"),
    )
    .log_log()
    .with_size(SIZE.0, SIZE.1);

    fn add(fig: Figure, label: String, groups: &[(f64, Vec<&Row>)], method: &str) -> Figure {
        if groups.is_empty() {
            return fig;
        }
        let (x, y) = pareto_points(groups);
        fig.with_series(Series::new(label, x, y, Mark::LinePoints).method(method))
    }
    let range = |ks: &[f64]| match (ks.first(), ks.last()) {
        (Some(a), Some(b)) if ks.len() > 1 => format!("{} … {}", num(*a), num(*b)),
        (Some(a), _) => num(*a),
        _ => String::new(),
    };

    // The optimal frontier first, so that the strategies' curves are drawn over it.
    // Rows skipped outside `optimal_families` have no cond₂: no legend entry without data.
    let optimal: Vec<&Row> = fam
        .method(optimal::STRATEGY.name)
        .into_iter()
        .filter(|r| r.cond2_system.is_some())
        .collect();
    for set in delta_sets(&optimal) {
        let ks: Vec<f64> = set.groups.iter().map(|g| g.0).collect();
        let unit = if set.relative { "·|u0|" } else { "" };
        fig = add(
            fig,
            format!(
                "optimal frontier (min cond₂ at δ), δ = {}{unit}",
                range(&ks)
            ),
            &set.groups,
            optimal::STRATEGY.name,
        );
    }
    let constant = groups(&fam.method(constant::STRATEGY.name), |r| r.eps);
    let ks: Vec<f64> = constant.iter().map(|g| g.0).collect();
    fig = add(
        fig,
        format!("constant, ε = {}", range(&ks)),
        &constant,
        constant::STRATEGY.name,
    );
    let scaled = groups(&fam.method(scaled::STRATEGY.name), |r| r.factor);
    let ks: Vec<f64> = scaled.iter().map(|g| g.0).collect();
    fig = add(
        fig,
        format!("scaled, f = {} (ε_c = f·K[d_c,d_c])", range(&ks)),
        &scaled,
        scaled::STRATEGY.name,
    );
    // The δ-driven rules, in registry order (colours and legend names from their
    // descriptors, as in every figure).
    for name in registry::delta_rules().into_iter().map(|s| s.name) {
        let legend = method_label(name);
        for set in delta_sets(&fam.method(name)) {
            let ks: Vec<f64> = set.groups.iter().map(|g| g.0).collect();
            let unit = if set.relative { "·|u0|" } else { "" };
            fig = add(
                fig,
                format!("{legend}, δ = {}{unit}", range(&ks)),
                &set.groups,
                name,
            );
        }
    }
    // augmented: grouped by tolerance only (its ε is chosen per scene by the sweep).
    let augmented = fam.method(augmented::STRATEGY.name);
    let eps_note = match groups(&augmented, |r| r.eps).as_slice() {
        [(eps, _)] => format!(", ε = {}", num(*eps)),
        _ => String::new(),
    };
    for set in delta_sets(&augmented) {
        let ks: Vec<f64> = set.groups.iter().map(|g| g.0).collect();
        let unit = if set.relative { "·|u0|" } else { "" };
        fig = add(
            fig,
            format!("augmented{eps_note}, tol = {}{unit}", range(&ks)),
            &set.groups,
            augmented::STRATEGY.name,
        );
    }
    if has_data(&fig) {
        let lag = median(&fam.method(lagrange::STRATEGY.name), m_cond);
        if drawable(Scale::Log10, lag) {
            fig = fig.hline(lag, "lagrange (exact, saddle point; penetration 0)");
        }
        let k = scene_median(&fam.all(), |r| r.cond2_k);
        if drawable(Scale::Log10, k) {
            fig = fig.hline(k, "cond₂(K), median");
        }
    }
    mark_not_converged(fig, &fam.rows, m_pen, m_cond)
}
