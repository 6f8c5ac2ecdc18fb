//! The two comparison tables of the record: every number the paper prints (Eq. 31–37) against
//! ours, and the `condensed` strategy against methods.md and the exact requirement |g| ≤ δ.
// Several parallel per-constraint vectors are indexed by c.
#![allow(clippy::needless_range_loop)]

use super::checks::Checks;
use super::printed::{
    self, EQ31_COND_K, EQ31_DET_K, EQ33_U0, EQ35_COND, EQ35_DET, EQ35_EPS, EQ36_U, EQ37_GAPS,
    METHODS_MD_CONDENSED_COND, METHODS_MD_CONDENSED_EPS,
};
use super::record::Row;
use super::solves::Solves;
use super::DELTA;
use crate::metrics;
use crate::model::beam;
use crate::study::text::{fmt_f, fmt_g, minus};
use crate::system::Problem;

/// The reference of a compared number.
enum Reference<'a> {
    /// Printed number; its last digit sets the tolerance.
    Printed(&'a str, &'a str),
    /// Printed requirement with an explicit tolerance.
    Requirement(&'a str, f64),
    /// No reference value.
    None,
}

/// Builds a compared row (`source` of [`Reference::Printed`] is "paper" or "methods.md").
fn row(
    id: &str,
    equation: &str,
    quantity: &str,
    reference: Reference,
    ours: f64,
    contrast: Option<f64>,
    note: &str,
) -> Row {
    let (reference_printed, source, tolerance) = match reference {
        Reference::Printed(s, source) => (Some(s), source, None),
        Reference::Requirement(s, tol) => (Some(s), "requirement", Some(tol)),
        Reference::None => (None, "—", None),
    };
    let value = reference_printed.map(printed::value);
    let tol = tolerance.or_else(|| reference_printed.map(printed::half_unit));
    let agree = match (value, tol) {
        (Some(r), Some(t)) => Some(printed::within(ours, r, t)),
        _ => None,
    };
    let ours_printed = match reference_printed {
        Some(s) if tolerance.is_none() => printed::format_like(ours, s),
        _ => fmt_g(ours),
    };
    Row {
        id: id.into(),
        equation: equation.into(),
        quantity: quantity.into(),
        reference_printed: reference_printed.map(minus),
        reference: value,
        reference_source: source.into(),
        tolerance: tol,
        ours,
        ours_printed,
        contrast,
        agree,
        note: note.into(),
    }
}

/// A number printed in the paper.
fn paper(s: &str) -> Reference<'_> {
    Reference::Printed(s, "paper")
}

/// Name of DOF `d` of the paper's beam: `(node n, axial|w|θ)`.
fn dof_name(frame: &beam::Frame, d: usize) -> String {
    for node in 0..frame.nodes.len() {
        for k in 0..3 {
            if frame.dof(node, k) == Some(d) {
                let c = ["axial u", "transverse w", "rotation θ"][k];
                return format!("node {} {c}", node + 1);
            }
        }
    }
    format!("DOF {d}")
}

/// The names of `dofs`.
fn dof_names(frame: &beam::Frame, dofs: impl Iterator<Item = usize>) -> Vec<String> {
    dofs.map(|d| dof_name(frame, d)).collect()
}

/// One row per printed entry `k` (1-based) of a vector equation: id `<id>k`, quantity
/// `<quantity(k)>  <names[k − 1]>`, ours `ours[k − 1]`, note `note(k − 1)`.
fn entries(
    equation: &str,
    id: &str,
    quantity: impl Fn(usize) -> String,
    printed: &[&str],
    names: &[String],
    ours: &[f64],
    note: impl Fn(usize) -> String,
) -> Vec<Row> {
    (0..printed.len())
        .map(|i| {
            row(
                &format!("{id}{}", i + 1),
                equation,
                &format!("{}  {}", quantity(i + 1), names[i]),
                paper(printed[i]),
                ours[i],
                None,
                &note(i),
            )
        })
        .collect()
}

/// Eq. 31 (K, det, cond) and Eq. 33 (u without contact).
fn eq31_eq33(frame: &beam::Frame, s: &Solves, ch: &Checks) -> Vec<Row> {
    let mut rows = Vec::new();
    let mut k_row = row(
        "eq31.K",
        "Eq. 31",
        "K: max |ours − printed| (81 entries)",
        Reference::None,
        ch.k_maxdiff,
        None,
        "(c),(d) assembled from E, A, J, l = 10",
    );
    k_row.reference_source = "paper".into();
    k_row.tolerance = Some(0.05);
    k_row.reference_printed = Some("matrix".into());
    k_row.agree = Some(ch.k_maxdiff <= 0.05);
    rows.push(k_row);
    rows.push(row(
        "eq31.det_K",
        "Eq. 31",
        "det K",
        paper(EQ31_DET_K),
        10f64.powf(s.log10_det_k),
        None,
        "(d) paper's units; 1e18× larger in N",
    ));
    rows.push(row(
        "eq31.cond_K",
        "Eq. 31",
        "cond₂ K",
        paper(EQ31_COND_K),
        s.cond_k,
        None,
        "",
    ));
    rows.extend(entries(
        "Eq. 33",
        "eq33.u",
        |k| format!("u_bk[{k}]"),
        &EQ33_U0,
        &dof_names(frame, 0..s.u0.len()),
        &s.u0,
        |i| match i {
            6 => format!("(a) MISPRINT: −50·30/EA = {}", fmt_f(ch.tip_axial, 3)),
            _ => String::new(),
        },
    ));
    rows
}

/// Every number the paper prints for the beam (Eq. 31–37) against ours.
pub fn paper_comparison(p: &Problem, frame: &beam::Frame, s: &Solves, ch: &Checks) -> Vec<Row> {
    let (pap, con) = (&s.pap, &s.con);
    let dofs: Vec<usize> = p.constraints.iter().map(|c| c.lead_dof()).collect(); // the beam: single-DOF constraints
    let mut rows = eq31_eq33(frame, s, ch);
    let names = dof_names(frame, dofs.iter().copied());
    rows.extend(entries(
        "Eq. 35",
        "eq35.eps",
        |k| format!("ε{k}"),
        &EQ35_EPS,
        &names,
        &pap.sol.penalties,
        |c| format!("(e) exact δ-target: {}", fmt_g(con.sol.penalties[c])),
    ));
    let det = 10f64.powf(pap.log10_det);
    rows.push(row(
        "eq35.det",
        "Eq. 35",
        "det(K + ε)",
        paper(EQ35_DET),
        det,
        None,
        "",
    ));
    rows.push(row(
        "eq35.cond",
        "Eq. 35",
        "cond₂(K + ε)",
        paper(EQ35_COND),
        pap.cond2,
        None,
        &format!("(g) {:.0}× below cond₂ K", ch.drop.cond_drop),
    ));
    rows.extend(entries(
        "Eq. 36",
        "eq36.u",
        |k| format!("u[{k}]"),
        &EQ36_U,
        &dof_names(frame, 0..pap.sol.u.len()),
        &pap.sol.u,
        |_| String::new(),
    ));
    rows.extend(entries(
        "Eq. 37",
        "eq37.g",
        |k| format!("(Dᵀu − û){k}"),
        &EQ37_GAPS,
        &names,
        &pap.sol.gaps,
        |c| match c {
            2 => format!(
                "(b) MISPRINT: Eq. 36 gives {} − {} = {}",
                EQ36_U[7],
                fmt_g(p.constraints[2].limit),
                fmt_f(ch.eq36_gaps[2], 3)
            ),
            _ => format!("(e) {:.2}·δ", pap.sol.gaps[c] / DELTA),
        },
    ));
    rows
}

/// The condensed penalties, gaps and max penetration against methods.md and |g| ≤ δ.
fn condensed_penalties_and_gaps(
    frame: &beam::Frame,
    dofs: &[usize],
    s: &Solves,
    g0: &[f64],
) -> Vec<Row> {
    let (pap, con) = (&s.pap.sol, &s.con.sol);
    let required = Reference::Requirement("0.1", 1e-9 * DELTA);
    let mut rows = Vec::new();
    for (c, &e) in METHODS_MD_CONDENSED_EPS.iter().enumerate() {
        rows.push(row(
            &format!("condensed.eps{}", c + 1),
            "ε",
            &format!("ε{}  {}", c + 1, dof_name(frame, dofs[c])),
            Reference::Printed(e, "methods.md"),
            con.penalties[c],
            Some(pap.penalties[c]),
            &format!(
                "{:.1}× smaller than Eq. 28",
                pap.penalties[c] / con.penalties[c]
            ),
        ));
    }
    for c in 0..dofs.len() {
        let side = if con.gaps[c].signum() == g0[c].signum() {
            "same side as"
        } else {
            "opposite side to"
        };
        rows.push(row(
            &format!("condensed.gap{}", c + 1),
            "|g|",
            &format!("|Dᵀu − û|{}", c + 1),
            Reference::Requirement("0.1", 1e-9 * DELTA),
            con.gaps[c].abs(),
            Some(pap.gaps[c].abs()),
            &format!(
                "signed {}: {side} u0 (g0 = {})",
                fmt_g(con.gaps[c]),
                fmt_g(g0[c])
            ),
        ));
    }
    rows.push(row(
        "condensed.max_pen",
        "|g|",
        "max penetration",
        required,
        con.max_penetration,
        Some(pap.max_penetration),
        "= δ; smallest ε with |g| ≤ δ, yet not the best-conditioned: see (i)",
    ));
    rows
}

/// The `condensed` strategy at δ against methods.md and the exact requirement, with Eq. 28
/// (ours) for contrast.
pub fn condensed_comparison(p: &Problem, frame: &beam::Frame, s: &Solves, ch: &Checks) -> Vec<Row> {
    let (pap, con) = (&s.pap, &s.con);
    let dofs: Vec<usize> = p.constraints.iter().map(|c| c.lead_dof()).collect(); // the beam: single-DOF constraints
    let mut rows = condensed_penalties_and_gaps(frame, &dofs, s, &ch.stiff.g0);
    rows.push(row(
        "condensed.cond",
        "cond",
        "cond₂(K + ε)",
        Reference::Printed(METHODS_MD_CONDENSED_COND, "methods.md"),
        con.cond2,
        Some(pap.cond2),
        &format!(
            "{:.2}× better than Eq. 28; {:.0}× below cond₂ K",
            pap.cond2 / con.cond2,
            s.cond_k / con.cond2
        ),
    ));
    rows.push(row(
        "condensed.det",
        "det",
        "det(K + ε)",
        Reference::None,
        10f64.powf(con.log10_det),
        Some(10f64.powf(pap.log10_det)),
        &format!("paper's Eq. 28 value: {EQ35_DET}"),
    ));
    let paper_ratio = (printed::value(EQ35_DET) / printed::value(EQ31_DET_K)).log10();
    rows.push(row(
        "condensed.det_ratio",
        "det",
        "log10 det(K + ε)/det K",
        Reference::None,
        con.log10_det_ratio,
        Some(pap.log10_det_ratio),
        &format!("paper: log10({EQ35_DET}/{EQ31_DET_K}) = {paper_ratio:.3}"),
    ));
    for i in 0..p.n() {
        let note = match dofs.iter().position(|&d| d == i) {
            Some(c) => format!("û{} = {}", c + 1, fmt_g(p.constraints[c].limit)),
            None => String::new(),
        };
        rows.push(row(
            &format!("condensed.u{}", i + 1),
            "u",
            &format!("u[{}]  {}", i + 1, dof_name(frame, i)),
            Reference::None,
            con.sol.u[i],
            Some(pap.sol.u[i]),
            &note,
        ));
    }
    rows.push(row(
        "condensed.err",
        "err",
        "‖u − u_Lagrange‖/‖u_Lagrange‖",
        Reference::None,
        metrics::relative_error(&con.sol.u, &s.lag.sol.u),
        Some(metrics::relative_error(&pap.sol.u, &s.lag.sol.u)),
        "the price of the larger (allowed) gaps",
    ));
    rows
}
