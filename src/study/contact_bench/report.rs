//! The benchmark's printed report: Lagrange per mesh against the analytic solution, the
//! rates, the leaderboard (one line per knob found; the entries without one grouped per case
//! and reason), then the rows solved, failed and skipped per method.

use super::figures::knob_label;
use super::record::floor_of;
use super::record::Leader;
use super::{analytic::Case, Summary};
use crate::study::outcomes::Tally;
use crate::study::text::{fmt_e, table, wrap};

/// The printed report: Lagrange per mesh (a, p0, errors, rates), then the leaderboard.
pub fn tables(s: &Summary) -> String {
    let mut out = String::from("Lagrange against the analytic solution\n");
    let lag: Vec<Vec<String>> = s
        .rows
        .iter()
        .filter(|r| r.method == "lagrange" && r.solved())
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
                if Case::from_name(&r.case).is_some_and(Case::is_uniform) {
                    fmt_e(r.p_spread, 1)
                } else {
                    "—".into()
                },
                r.cond2_system.map_or("—".into(), |c| fmt_e(c, 3)),
                floor_of(s, &r.case, r.h)
                    .filter(|c| c.is_finite())
                    .map_or("—".into(), |c| fmt_e(c, 3)),
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
    // A case whose rows Lagrange refuses (two-pass node-to-segment) has no reference.
    for r in s
        .rows
        .iter()
        .filter(|r| r.method == "lagrange" && !r.solved())
    {
        out.push_str(&format!(
            "{} h = {}: Lagrange failed, no reference for the other rules: {}\n",
            r.case,
            fmt_e(r.h, 2),
            r.error
        ));
    }
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
    out.push_str(&misses(s));
    out.push_str("\nRows per method\n");
    out.push_str(&tally(s).text(90));
    out
}

/// The rows solved, failed and skipped per method ([`crate::study::outcomes`]): a row whose
/// `error` starts with `skipped:` was not run, a row without a lift failed, any other solved
/// (an error of its metrics aside).
pub fn tally(s: &Summary) -> Tally {
    let mut t = Tally::default();
    for r in &s.rows {
        if r.error.starts_with("skipped:") {
            t.add(&r.method, &r.error);
        } else if !r.solved() {
            t.add(&r.method, &format!("error: {}", r.error));
        } else {
            t.add(&r.method, "");
        }
    }
    t
}

/// Why a leaderboard entry has no knob, or `None` where it has one.
fn miss_reason(l: &Leader) -> Option<&'static str> {
    match (l.knob_rel, l.tried) {
        (Some(_), _) => None,
        (None, 0) => Some("no solve (see the rows)"),
        (None, _) if l.err_discretization.is_nan() => Some("no Lagrange reference"),
        (None, _) => Some("no knob within the margin"),
    }
}

/// The leaderboard entries without a knob, one wrapped line per case and reason:
/// `case: reason: rule (h = …, …), rule (h = …)`.
fn misses(s: &Summary) -> String {
    type Group = ((String, &'static str), Vec<(String, Vec<String>)>);
    let mut groups: Vec<Group> = Vec::new();
    for l in s.leaderboard.iter().filter(|l| l.rule != "lagrange") {
        let Some(reason) = miss_reason(l) else {
            continue;
        };
        let key = (l.case.clone(), reason);
        let i = match groups.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                groups.push((key, Vec::new()));
                groups.len() - 1
            }
        };
        let rules = &mut groups[i].1;
        let j = match rules.iter().position(|(r, _)| *r == l.rule) {
            Some(j) => j,
            None => {
                rules.push((l.rule.clone(), Vec::new()));
                rules.len() - 1
            }
        };
        rules[j].1.push(fmt_e(l.h, 2));
    }
    let mut out = String::new();
    for ((case, reason), rules) in groups {
        let list: Vec<String> = rules
            .iter()
            .map(|(r, hs)| format!("{r} (h = {})", hs.join(", ")))
            .collect();
        out.push_str(&wrap(
            &format!("{case}: {reason}: {}", list.join(", ")),
            100,
            4,
        ));
        out.push('\n');
    }
    out
}

/// The leaderboard entries with a knob (the others: [`misses`]).
fn leader_table(s: &Summary) -> String {
    let rows: Vec<Vec<String>> = s
        .leaderboard
        .iter()
        .filter(|l| l.rule != "lagrange" && miss_reason(l).is_none())
        .map(|l| {
            vec![
                l.case.clone(),
                fmt_e(l.h, 2),
                l.rule.clone(),
                knob_label(&l.knob, l.knob_rel),
                l.cond2_system.map_or("—".into(), |c| fmt_e(c, 3)),
                match (l.cond2_system, floor_of(s, &l.case, l.h)) {
                    (Some(c), Some(f)) if f.is_finite() => format!("{:.3}", c / f),
                    _ => "—".into(),
                },
                l.err_penalty.map_or("—".into(), |e| fmt_e(e, 2)),
                if l.err_discretization.is_nan() {
                    "—".into()
                } else {
                    fmt_e(l.err_discretization, 2)
                },
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
