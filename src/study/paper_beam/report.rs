//! The printed report of the study: the paper comparison, the `condensed` comparison, the
//! strategies and the notes as aligned text (the binary prints it).

use super::printed::format_like;
use super::record::{Optimum, Record, Row, StrategyLine};
use crate::strategy::{augmented, lagrange};
use crate::study::text::{fmt_e, fmt_g, table, wrap};

fn agree_text(a: Option<bool>) -> String {
    match a {
        Some(true) => "yes".into(),
        Some(false) => "NO".into(),
        None => "—".into(),
    }
}

fn printed_or_dash(r: &Row) -> String {
    r.reference_printed.clone().unwrap_or_else(|| "—".into())
}

fn header(rec: &Record) -> String {
    let pv = &rec.provenance;
    let commit = pv.git_commit.trim_end_matches("-dirty");
    format!(
        "The paper's beam (Sec. 4.2, Eq. 30–37): paper vs penalty-lab {} (commit {}{}), δ = {}\n\
         agree = |ours − paper| ≤ half a unit of the paper's last printed digit. Units: {}.\n\n",
        pv.crate_versions["penalty-lab"].as_str().unwrap_or("?"),
        &commit[..commit.len().min(12)],
        if commit.len() < pv.git_commit.len() {
            ", dirty"
        } else {
            ""
        },
        rec.delta,
        rec.beam.units
    )
}

fn paper_table(rec: &Record) -> String {
    let rows: Vec<Vec<String>> = rec
        .paper_comparison
        .iter()
        .map(|r| {
            vec![
                r.equation.clone(),
                r.quantity.clone(),
                printed_or_dash(r),
                r.ours_printed.clone(),
                agree_text(r.agree),
                r.note.clone(),
            ]
        })
        .collect();
    let mut out = table(
        &["eq.", "quantity", "paper", "ours", "agree", "note"],
        &rows,
        &[false, false, true, true, false, false],
    );
    let differ: Vec<&str> = rec
        .paper_comparison
        .iter()
        .filter(|r| r.agree == Some(false))
        .map(|r| r.id.as_str())
        .collect();
    out.push_str(&format!(
        "{} numbers compared, {} agree, {} differ: {}\n\n",
        rec.paper_comparison.len(),
        rec.paper_comparison.len() - differ.len(),
        differ.len(),
        differ.join(", ")
    ));
    out
}

fn condensed_table(rec: &Record) -> String {
    let rows: Vec<Vec<String>> = rec
        .condensed_comparison
        .iter()
        .map(|r| {
            let ours = match &r.reference_printed {
                _ if r.id == "condensed.det" => fmt_e(r.ours, 5),
                Some(s) if r.reference_source == "methods.md" => format_like(r.ours, s),
                _ => fmt_g(r.ours),
            };
            let contrast = match r.contrast {
                Some(v) if r.id == "condensed.det" => fmt_e(v, 5),
                Some(v) => fmt_g(v),
                None => "—".into(),
            };
            vec![
                r.quantity.clone(),
                printed_or_dash(r),
                r.reference_source.clone(),
                ours,
                contrast,
                agree_text(r.agree),
                r.note.clone(),
            ]
        })
        .collect();
    let headers = [
        "quantity",
        "reference",
        "source",
        "condensed",
        "Eq. 28",
        "agree",
        "note",
    ];
    format!(
        "Condensed strategy (exact δ-targeting, δ = {}) vs methods.md / the requirement, with \
         Eq. 28 (ours) for contrast:\n\n{}\n",
        rec.delta,
        table(
            &headers,
            &rows,
            &[false, true, false, true, true, false, false]
        )
    )
}

/// The warnings column: the clipped constraints when every warning is a clipped negative
/// penalty, else the count and the first warning.
fn warnings_text(s: &StrategyLine) -> String {
    if s.warnings.is_empty() {
        return String::new();
    }
    let clipped: Vec<String> = s
        .warnings
        .iter()
        .filter(|w| w.contains("negative penalty"))
        .filter_map(|w| {
            w.split("for constraint ")
                .nth(1)
                .and_then(|t| t.split_whitespace().next())
                .and_then(|c| c.parse::<usize>().ok())
                .map(|c| (c + 1).to_string())
        })
        .collect();
    if clipped.len() == s.warnings.len() {
        format!("ε < 0 clipped to 0 for c = {}", clipped.join(", "))
    } else {
        format!("{} warning(s): {}", s.warnings.len(), s.warnings[0])
    }
}

fn strategies_table(rec: &Record) -> String {
    let rows: Vec<Vec<String>> = rec
        .strategies
        .iter()
        .map(|s| {
            let eps = s
                .penalties
                .iter()
                .map(|e| fmt_g(*e))
                .collect::<Vec<_>>()
                .join(" ");
            let eps = if s.name == lagrange::STRATEGY.name {
                "— (multipliers)".to_string()
            } else if s.name == augmented::STRATEGY.name {
                format!("{eps} (final)")
            } else {
                eps
            };
            vec![
                s.name.clone(),
                s.knob.clone(),
                eps,
                fmt_e(s.cond2_system, 4),
                fmt_e(s.max_penetration, 3),
                fmt_e(s.error_vs_lagrange, 3),
                s.linear_solves.to_string(),
                warnings_text(s),
            ]
        })
        .collect();
    let headers = [
        "strategy",
        "knob",
        "ε_1 ε_2 ε_3",
        "cond₂(system)",
        "max pen.",
        "err vs Lagr.",
        "solves",
        "warnings",
    ];
    format!(
        "All strategies on the beam (error vs the Lagrange solution):\n\n{}\
         (cond₂(system) of lagrange is that of the saddle-point matrix [K D; Dᵀ 0].)\n\n",
        table(
            &headers,
            &rows,
            &[false, false, false, true, true, true, true, false]
        )
    )
}

/// The cond-optimal penalties next to Eq. 28 and `condensed` (ours: the paper prints none).
fn optimum_text(o: &Optimum) -> String {
    let v = |x: &[f64]| x.iter().map(|e| fmt_g(*e)).collect::<Vec<_>>().join(", ");
    let at: Vec<String> = o.at_delta.iter().map(|c| c.to_string()).collect();
    format!(
        "The cond-optimal penalties at δ = {} (ours; the paper prints no optimum; an outside \
         optimiser gives {}):\n  cond₂ optimal {} (Eq. 28 {}, condensed {}; certified \
         lower bound {}), ε = ({}), gaps = ({}); at δ: constraint(s) {}; KKT residual {}, \
         {} of {} optimised starts agree.\n\n",
        o.delta,
        o.outside_cond2,
        fmt_g(o.cond2),
        fmt_g(o.cond2_paper),
        fmt_g(o.cond2_condensed),
        fmt_g(o.cond2_lower_bound),
        v(&o.penalties),
        v(&o.gaps),
        at.join(", "),
        fmt_e(o.optimality, 1),
        o.starts_agreeing,
        o.starts
    )
}

/// The report printed by `paper_beam`: header, the paper and condensed comparisons, every
/// strategy and the notes, as text.
pub fn text(rec: &Record) -> String {
    let mut out = header(rec);
    out.push_str(&paper_table(rec));
    out.push_str(&condensed_table(rec));
    out.push_str(&strategies_table(rec));
    if let Some(o) = &rec.optimum {
        out.push_str(&optimum_text(o));
    }
    out.push_str("Notes on every difference:\n\n");
    for n in &rec.notes {
        out.push_str(&format!("({}) {}\n", n.key, n.title));
        out.push_str(&format!("    {}\n\n", wrap(&n.text, 100, 4)));
    }
    out
}
