//! `friction_bench`'s `cattaneo-mindlin` case ([`crate::friction::cattaneo`]): every method at
//! every mesh (`--cm-levels`, element size h/a at the contact), μ and target Q/(μP)
//! (`--q-over-mup`), one row each with `h_over_a`, `q_over_mup` (the ratio reached, within
//! [`RATIO_TOL`] of the target), `c_num`, `c_exact` and `shear_err_l2`; the report's table of
//! the stick zone and of the shear traction's L2 error with its rate in h; the figure
//! `cattaneo_mindlin` (that error against h, and c_num/c_exact, per method).
//!
//! Methods: `lagrange` (the reference), `augmented` (ε_N = ε_T = 10·G, tolerance 10⁻¹⁰ a),
//! and penalties with the normal rule `ε_N,c = eps_n·G·w_c/h_c` and the tangential rules
//! `area` (r of `--cm-eps-t`) and `delta` (δ_T/a of `--cm-delta-t`). cond₂ and GMRES counts
//! are left empty: the tangent has 6 000 – 32 000 unknowns at the default meshes and the
//! certified route for an unsymmetric matrix is dense (see the warning of each row).

use super::{BenchConfig, FrictionRow};
use crate::error::Result;
use crate::friction::cattaneo::{CattaneoMindlin, CattaneoResult, RATIO_TOL};
use crate::friction::{FrictionMethod, FrictionProblem, NormalRule, TangentRule};
use crate::plot::{Figure, Mark, Scale, Series};
use crate::progress::Progress;
use crate::study::checkpoint::Checkpoints;
use crate::study::shape::Drawing;
use crate::study::text::{fmt_e, table as aligned};
use rayon::prelude::*;

/// The case's name.
pub const CASE: &str = "cattaneo-mindlin";

/// Every (method, rule) of the case for shear modulus `g` (lengths in units of a): no
/// `constant` rows (on the uniform contact mesh they are the `area` rows).
fn methods(cfg: &BenchConfig, g: f64) -> Vec<(FrictionMethod, &'static str)> {
    cfg.methods_with(g, 1.0, (&cfg.cm_eps_t, false), &cfg.cm_delta_t)
}

/// The row of one solve (or of its failure, `error`) of the case whose frictional problem is
/// `p`: the `area` rules' ε at the contact point x = 0 (element size h on both sides).
fn row(
    case: &CattaneoMindlin,
    (method, rule): &(FrictionMethod, &'static str),
    target: f64,
    solved: std::result::Result<CattaneoResult, String>,
    p: &FrictionProblem,
) -> FrictionRow {
    let (n, mid) = (p.n(), p.m() / 2);
    let (eps_n, eps_t, delta_t) = match method {
        FrictionMethod::Lagrange => (None, None, None),
        FrictionMethod::Augmented { eps_n, eps_t, .. } => (Some(*eps_n), Some(*eps_t), None),
        FrictionMethod::Penalty {
            normal, tangent, ..
        } => {
            let en = match normal {
                NormalRule::Area(r) => Some(p.area_penalty(*r, mid)),
                _ => None,
            };
            match *tangent {
                TangentRule::Area(r) => (en, Some(p.area_penalty(r, mid)), None),
                TangentRule::Delta(d) => (en, None, Some(d)),
                TangentRule::Constant(e) => (en, Some(e), None),
            }
        }
    };
    let mut warnings = vec![format!(
        "cond2 and GMRES counts not computed: N = {n} unknowns, the certified route for an \
         unsymmetric tangent is dense"
    )];
    let (res, converged) = match solved {
        Ok(r) => (Some(r), true),
        Err(e) => {
            warnings.push(format!("error: {e}"));
            (None, false)
        }
    };
    if let Some(r) = &res {
        warnings.extend(r.solution.warnings.iter().cloned());
    }
    let sol = res.as_ref().map(|r| &r.solution);
    FrictionRow {
        case: CASE.into(),
        discretization: Some("node-to-node".into()),
        theta: None,
        h_over_a: Some(case.h_over_a),
        mu: case.mu,
        method: method.name().into(),
        tangent_rule: (*rule).into(),
        law: match method {
            FrictionMethod::Penalty { law, .. } => format!("{law:?}").to_lowercase(),
            _ => "coulomb".into(),
        },
        eps_n,
        eps_t,
        delta_t,
        q_over_mup: Some(res.as_ref().map_or(target, |r| r.ratio)),
        c_num: res.as_ref().and_then(|r| r.c_num),
        c_exact: res.as_ref().map(|r| r.c_exact),
        shear_err_l2: res.as_ref().map(|r| r.shear_err_l2),
        onset_ratio: None,
        onset_travel: None,
        onset_travel_err: None,
        history_err: None,
        pressure_err_max: None,
        shear_err_max: None,
        increments: sol.map_or(0, |s| s.increments.len()),
        newton_iters: sol.map_or(0, |s| s.newton_iters()),
        factorizations: sol.map_or(0, |s| s.factorizations),
        converged: converged && sol.is_some_and(|s| s.converged),
        cond2_system: None,
        cond2_lo: None,
        cond2_hi: None,
        cond2_bounds_proven: None,
        cond_route: None,
        gmres_iters_jacobi_to_err: None,
        gmres_iters_jacobi_to_err_converged: None,
        warnings: warnings.join("; "),
    }
}

/// Every row of the case: (mesh, μ) in parallel, each method and target in turn; with
/// `checkpoints`, each (mesh, μ) is kept at once and, with `--resume`, read back instead of
/// solved ([`crate::study::checkpoint`]). A method's
/// numerical failure is its row (unconverged, the error in `warnings`); bad input an error.
/// `done`: the progress steps of the other cases, counted before these.
pub fn rows(
    cfg: &BenchConfig,
    progress: &Progress,
    done: usize,
    checkpoints: Option<&Checkpoints>,
) -> Result<Vec<FrictionRow>> {
    let cases: Vec<CattaneoMindlin> = cfg
        .cm_levels
        .iter()
        .flat_map(|&h| {
            cfg.mu
                .iter()
                .map(move |&mu| CattaneoMindlin { h_over_a: h, mu })
        })
        .collect();
    let g = crate::friction::cattaneo::shear_modulus();
    let per = methods(cfg, g).len() * cfg.q_over_mup.len();
    progress.set_total(done + cases.len() * per);
    let out: Vec<Vec<FrictionRow>> = cases
        .par_iter()
        .map(|case| {
            let key = format!("{CASE}-h{}-mu{}", case.h_over_a, case.mu);
            let solve = || case_rows(cfg, case, g, per, progress);
            let (rows, resumed) = Checkpoints::get_or_maybe(checkpoints, &key, solve)?;
            if resumed {
                for _ in 0..per {
                    progress.step(&format!("friction_bench: {key} (checkpoint)"));
                }
            }
            Ok(rows)
        })
        .collect::<Result<_>>()?;
    Ok(out.into_iter().flatten().collect())
}

/// The rows of one (mesh, μ): each method and target in turn, one progress step per row.
fn case_rows(
    cfg: &BenchConfig,
    case: &CattaneoMindlin,
    g: f64,
    per: usize,
    progress: &Progress,
) -> Result<Vec<FrictionRow>> {
    let built = case.build()?;
    let p = built.problem(0.0)?;
    let mut rows = Vec::with_capacity(per);
    for m in methods(cfg, g) {
        for &t in &cfg.q_over_mup {
            let solved = match built.solve_at(&m.0, t) {
                Err(e) if e.is_input() => return Err(e),
                other => other.map_err(|e| e.to_string()),
            };
            rows.push(row(case, &m, t, solved, &p));
            progress.step(&format!(
                "friction_bench: {CASE}, h = a/{}, μ = {}, {} {}, Q/μP = {t}",
                1.0 / case.h_over_a,
                case.mu,
                m.0.name(),
                m.1
            ));
        }
    }
    Ok(rows)
}

/// The knob of a row as printed: ε_T or δ_T.
fn knob(r: &FrictionRow) -> String {
    match (r.eps_t, r.delta_t) {
        (_, Some(d)) => format!("δ_T {}", fmt_e(d, 0)),
        (Some(e), None) if r.method == "penalty" => format!("ε_T {}", fmt_e(e, 1)),
        _ => String::new(),
    }
}

/// The case's rows as a table: per (method, knob, μ, Q/(μP)), c_num/c_exact − 1 and the shear
/// traction's L2 error at each mesh, and that error's rate between the two finest meshes.
pub fn table(rows: &[FrictionRow]) -> String {
    let cm: Vec<&FrictionRow> = rows.iter().filter(|r| r.case == CASE).collect();
    if cm.is_empty() {
        return String::new();
    }
    let mut levels: Vec<f64> = cm.iter().filter_map(|r| r.h_over_a).collect();
    levels.sort_by(|a, b| b.total_cmp(a));
    levels.dedup();
    let mut headers = vec![
        "method".to_string(),
        "knob".into(),
        "μ".into(),
        "Q/μP".into(),
    ];
    for h in &levels {
        headers.push(format!("c err a/{}", (1.0 / h).round()));
    }
    for h in &levels {
        headers.push(format!("q L2 a/{}", (1.0 / h).round()));
    }
    headers.push("rate".into());
    headers.push("converged".into());
    // A line per (method and rule, knob, μ, Q/μP), the reached ratios within 1e-3 of each
    // other (they are within RATIO_TOL of the target).
    type Key = (String, String, f64, f64);
    let key = |r: &FrictionRow| -> Key {
        (
            format!("{} {}", r.method, r.tangent_rule),
            knob(r),
            r.mu,
            r.q_over_mup.unwrap_or(f64::NAN),
        )
    };
    let same =
        |a: &Key, b: &Key| a.0 == b.0 && a.1 == b.1 && a.2 == b.2 && (a.3 - b.3).abs() <= 1e-3;
    let mut keys: Vec<Key> = Vec::new();
    for r in &cm {
        let k = key(r);
        if !keys.iter().any(|o| same(o, &k)) {
            keys.push(k);
        }
    }
    let body: Vec<Vec<String>> = keys
        .iter()
        .map(|k| {
            let at = |h: f64| {
                cm.iter()
                    .find(|r| r.h_over_a == Some(h) && same(&key(r), k))
            };
            let mut line = vec![
                k.0.clone(),
                k.1.clone(),
                k.2.to_string(),
                format!("{:.2}", k.3),
            ];
            for &h in &levels {
                let c = at(h).and_then(|r| r.c_num.zip(r.c_exact));
                line.push(c.map_or("—".into(), |(n, e)| fmt_e(n / e - 1.0, 2)));
            }
            let errs: Vec<Option<f64>> = levels
                .iter()
                .map(|&h| at(h).and_then(|r| r.shear_err_l2))
                .collect();
            for e in &errs {
                line.push(e.map_or("—".into(), |e| fmt_e(e, 2)));
            }
            let n = levels.len();
            let rate = (n >= 2)
                .then(|| errs[n - 2].zip(errs[n - 1]))
                .flatten()
                .map(|(a, b)| (a / b).ln() / (levels[n - 2] / levels[n - 1]).ln());
            line.push(rate.map_or("—".into(), |r| format!("{r:.2}")));
            let conv = levels.iter().all(|&h| at(h).is_none_or(|r| r.converged));
            line.push(if conv { "yes" } else { "NO" }.into());
            line
        })
        .collect();
    let right: Vec<bool> = (0..headers.len())
        .map(|i| (2..headers.len() - 1).contains(&i))
        .collect();
    let hdr: Vec<&str> = headers.iter().map(String::as_str).collect();
    let mut t = aligned(&hdr, &body, &right);
    t.push_str(&format!(
        "cattaneo-mindlin: c err = c_num/c_exact − 1 (c_exact = a(P)·√(1 − Q/μP), Hertz's a \
         for the computed P); q L2 = the shear traction's relative L2 error over the contact \
         face; rate = log of its ratio between the two finest meshes over log of their h \
         ratio. Q/μP reached within {RATIO_TOL:.0e} of the target by a secant on the slide.\n"
    ));
    t
}

/// `cattaneo_mindlin`: per target Q/(μP) (a column each), the shear traction's L2 error
/// (top) and c_num/c_exact (bottom) against h/a, one line per (method, knob), at the first μ
/// (the others coincide for every rule but `delta`, whose δ_T does not scale with μ);
/// nothing without rows of the case.
pub fn figures(rows: &[FrictionRow]) -> Vec<Drawing> {
    let cm: Vec<&FrictionRow> = rows
        .iter()
        .filter(|r| r.case == CASE && r.shear_err_l2.is_some())
        .collect();
    let Some(mu) = cm.first().map(|r| r.mu) else {
        return Vec::new();
    };
    let label = |r: &FrictionRow| format!("{} {}", r.method, knob(r)).trim().to_string();
    let mut labels: Vec<String> = Vec::new();
    let mut targets: Vec<f64> = Vec::new();
    for r in cm.iter().filter(|r| r.mu == mu) {
        if !labels.contains(&label(r)) {
            labels.push(label(r));
        }
        let t = r.q_over_mup.unwrap_or(0.0);
        if !targets.iter().any(|q| (q - t).abs() <= 1e-3) {
            targets.push(t);
        }
    }
    let mut top = Vec::new();
    let mut bottom = Vec::new();
    for &t in &targets {
        let mut err = Figure::new(
            format!("Q/μP = {t:.2}, μ = {mu}: shear traction error"),
            "h / a",
            "‖q − q_exact‖₂ / ‖q_exact‖₂",
        )
        .log_log();
        let mut stick = Figure::new(
            format!("Q/μP = {t:.2}, μ = {mu}: stick half-width"),
            "h / a",
            "c_num / c_exact",
        )
        .scales(Scale::Log10, Scale::Linear);
        for (color, name) in labels.iter().enumerate() {
            let pts: Vec<&&FrictionRow> = cm
                .iter()
                .filter(|r| {
                    r.mu == mu
                        && label(r) == *name
                        && r.q_over_mup.is_some_and(|v| (v - t).abs() <= 1e-3)
                })
                .collect();
            let (x, y): (Vec<f64>, Vec<f64>) = pts
                .iter()
                .filter_map(|r| r.h_over_a.zip(r.shear_err_l2))
                .unzip();
            err = err.with_series(Series::new(name, x, y, Mark::LinePoints).color(color));
            let (x, y): (Vec<f64>, Vec<f64>) = pts
                .iter()
                .filter_map(|r| r.h_over_a.zip(r.c_num.zip(r.c_exact).map(|(n, e)| n / e)))
                .unzip();
            stick = stick.with_series(Series::new(name, x, y, Mark::LinePoints).color(color));
        }
        top.push(err);
        bottom.push(stick);
    }
    let cols = targets.len();
    top.extend(bottom);
    vec![Drawing {
        name: "cattaneo_mindlin".into(),
        panels: top,
        cols,
        size: (600 * cols as u32, 1100),
    }]
}
