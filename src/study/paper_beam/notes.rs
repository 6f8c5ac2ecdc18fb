//! The notes of the record: one explanation per difference from the paper, (a)–(i), each with
//! the numbers computed for it (see `checks`).

use super::checks::Checks;
use super::record::CondRow;
use super::record::Note;
use super::solves::Solves;
use super::DELTA;
use crate::model::beam::paper;
use crate::study::text::{fmt_e, fmt_f, fmt_g};

/// `(v₁, v₂, …)` with `d` decimals.
fn fv(v: &[f64], d: usize) -> String {
    let items: Vec<String> = v.iter().map(|&x| fmt_f(x, d)).collect();
    format!("({})", items.join(", "))
}

/// `min–max` of `v` with one decimal.
fn range(v: &[f64]) -> String {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    format!("{lo:.1}–{hi:.1}")
}

fn note(key: &str, title: &str, text: String) -> Note {
    Note {
        key: key.into(),
        title: title.into(),
        text,
    }
}

fn a_tip_axial(s: &Solves, ch: &Checks) -> Note {
    let ea = ch.ea;
    note(
        "a",
        "Eq. 33, entry 7 is a misprint (−0.414 for −0.714)",
        format!(
            "Entry 7 is the axial displacement of the tip (node 4). Only the axial load −50 \
             acts at the tip, so the axial strain is uniform: u(x) = −50·x/EA with EA = {ea} \
             (paper units), u(10) = {}, u(20) = {}, u(30) = {}. Eq. 33 prints −0.238 and \
             −0.476 for the first two (agree) but −0.414 for the tip; ours is {}. A 7→4 \
             digit misprint only: Eq. 35–37, which all agree with ours (except note b), are \
             computed from the same K and q, i.e. with the true u_bk[7] = −0.714.",
            fmt_f(-50.0 * 10.0 / ea, 3),
            fmt_f(-50.0 * 20.0 / ea, 3),
            fmt_f(ch.tip_axial, 3),
            fmt_f(s.u0[6], 6),
        ),
    )
}

fn b_eq37_sign(s: &Solves, ch: &Checks) -> Note {
    let trunc3 = |v: f64| (v * 1000.0).trunc() / 1000.0;
    let g = &s.pap.sol.gaps;
    note(
        "b",
        "Eq. 37, entry 3 has the wrong sign (+0.007 for −0.008)",
        format!(
            "Eq. 37 is Dᵀu − û. From the paper's own Eq. 36: u[5] − 3 = 3.018 − 3 = {}, \
             u[7] − (−1) = −0.986 + 1 = {}, u[8] − 30 = 29.992 − 30 = {}. The first two are \
             Eq. 37's; the third is printed +0.007. Ours: {}. The tip ends on the far side \
             of û = 30 (u0 was 51.4; node 3 held at w ≈ 3 pulls it down), so the sign is \
             negative, and |g| = {:.5} rounds to 0.008, not 0.007. Truncation would give \
             0.007 but is not what the paper does elsewhere: ours {:.5} and {:.5} truncate \
             to {:.3} and {:.3}, the paper prints 0.018 and 0.014 (rounded). So: a sign \
             misprint, plus a last-digit difference (0.007 vs 0.008).",
            fmt_f(ch.eq36_gaps[0], 3),
            fmt_f(ch.eq36_gaps[1], 3),
            fmt_f(ch.eq36_gaps[2], 3),
            fv(g, 5),
            g[2].abs(),
            g[0],
            g[1],
            trunc3(g[0]),
            trunc3(g[1]),
        ),
    )
}

fn c_eq30_layout(ch: &Checks) -> Note {
    note(
        "c",
        "Eq. 30's element matrix layout is garbled; Eq. 31 is the standard frame element",
        format!(
            "Printed Eq. 30 (upper triangle + \"symm\") has 6 entries in every row: rows 2–4 \
             are shifted one column to the left (row 4 reads `0 0 EA/l 0 0 0`), row 5 is all \
             zeros, and its entries 12EJ/l³, −6EJ/l² appear in the last row before 4EJ/l. \
             Read that way, row 3 gives k_35 (θ1–w2) = +6EJ/l²; the standard Euler–Bernoulli \
             frame element (src/model/beam.rs) has k_35 = −6EJ/l² = {}, and the assembled \
             Eq. 31 indeed has K[3,5] = {}. All 81 entries of Eq. 31 are reproduced from E, \
             A, J and l with the standard element (max |difference| = {:.1e}; also \
             tests/verification/paper_beam.rs). Notation clash: the text calls the beam length l = 30 mm, \
             but Eq. 30 needs the element length l = 10 mm (EA/l = {} with l = 10, {} with \
             l = 30).",
            fmt_g(ch.k35_elem),
            fmt_g(ch.k35_eq31),
            ch.k_maxdiff,
            fmt_g(ch.ea_over_l_10),
            fmt_g(ch.ea_over_l_30)
        ),
    )
}

fn d_units(ch: &Checks) -> Note {
    let u = &ch.units;
    note(
        "d",
        "Units: E = 210 GPa vs EA/l = 210 in Eq. 31 (force unit 100 N)",
        format!(
            "With E = 210 GPa = 210 000 N/mm², A = 1 mm², l = 10 mm: EA/l = 21 000 N/mm and \
             12EJ/l³ = 210 N/mm, but Eq. 31 has 210 and 2.1, i.e. K is in units of 100 N/mm \
             (E = {} in the example's units). Computed: K(E = 210 000)/K(Eq. 31) = {}. The \
             text says \"we skip units\"; every number of the example is consistent with a \
             force unit of 100 N: the loads −50 and 1 are −5 kN and 100 N, and ε is in \
             100 N/mm (in N/mm, Eq. 28 gives {}× Eq. 35). Displacements (mm) and cond₂ do not \
             depend on the force unit (q in N: max |Δu0| = {:.1e}; cond₂ K = {} either way), \
             but the determinants do: det K in (N/mm)⁹ is 10^{:.4} = {} = 100⁹ × Eq. 31's, so \
             the printed |K| = 4.597e11 and |K + ε| = 1.948e20 hold only in the 100 N unit. \
             (Equivalently E = 2.1 GPa with forces in N — not steel.)",
            fmt_g(paper::E),
            fmt_g(u.k_ratio),
            fmt_g(u.eps_si_ratio[0]),
            u.u_si_diff,
            fmt_e(u.cond_k_si, 6),
            u.log10_det_k_si,
            fmt_e(10f64.powf(u.log10_det_k_si), 4)
        ),
    )
}

fn e_overstiffening(s: &Solves, ch: &Checks) -> Note {
    let (pap, con, st) = (&s.pap.sol, &s.con.sol, &ch.stiff);
    let eps_over: Vec<f64> = pap
        .penalties
        .iter()
        .zip(&con.penalties)
        .map(|(a, b)| a / b)
        .collect();
    let delta_over_gap: Vec<f64> = pap.gaps.iter().map(|g| DELTA / g.abs()).collect();
    note(
        "e",
        "Gaps 5–13× below δ: Eq. 28 uses K̄ = DᵀKD ⪰ S⁻¹ (over-stiffens); q_i means q̄_i",
        format!(
            "Eq. 22 is written for all N DOFs: |Dû − u| = Dδ also asks u = 0 at every \
             unconstrained DOF, so Eq. 24–28 compute ε as if the rest of the beam were \
             clamped, with the stiffness K̄ = DᵀKD at the constrained DOFs. The stiffness \
             there with the other DOFs free is the Schur complement S⁻¹ = (DᵀK⁻¹D)⁻¹, and \
             K̄ − S⁻¹ is positive semidefinite (eigenvalues {}), so Eq. 28 over-stiffens. \
             Exactly, the penalized gaps are g = (I + S E)⁻¹ g0 with g0 = {}; Eq. 28's \
             ε = {} give g = {} (the same as the solve), δ/|g| = {}. The exact δ-targeting \
             ε = S⁻¹(g0 − g*)./g* (the condensed strategy) is {}, i.e. Eq. 28's penalties \
             are {}× too large for the target δ, and it yields |g| = δ exactly. The paper \
             attributes the effect to the diagonal form of ε̄; the cause is K̄ in place of \
             S⁻¹ (with S⁻¹ a diagonal ε̄ is exact). Eq. 28 also prints q_i where q̄_i = \
             (Dᵀq)_i is meant: read literally (q_1..q_3 of the full load vector, all 0) it \
             gives ε = {}, not Eq. 35; with q̄ = {}: {} (Eq. 35). The sum over k in \
             K̄_ik û_k and K̄_ik δ_k is implied.",
            fv(&st.diff_eigs, 3),
            fv(&st.g0, 3),
            fv(&pap.penalties, 1),
            fv(&st.g_pred, 5),
            fv(&delta_over_gap, 1),
            fv(&con.penalties, 2),
            range(&eps_over),
            fv(&st.eps_q_literal, 1),
            fv(&st.qbar, 0),
            fv(&st.eps_qbar, 1),
        ),
    )
}

fn f_unilateral(ch: &Checks) -> Note {
    let un = &ch.uni;
    note(
        "f",
        "\"Unilaterally restrained\" beam solved as bilateral (tied DOFs)",
        format!(
            "All three unconstrained gaps are positive (g0 = {}), so as obstacles they \
             would all be upper ones (u ≤ û), which can only push (r ≥ 0 in K u = q − D r). \
             The exact bilateral solution needs r = {}: constraint 3 (tip, w = 30) must \
             pull (r < 0), and the axial 'contact' at û = −1 is a wall that the undeformed \
             tip (u = 0) already penetrates by 1 mm. Read unilaterally (all upper), \
             Lagrange keeps only constraints {:?} active and the tip ends at w = {} (gap \
             {}, no contact). The paper's Eq. 22–28 use |·| and tie every constraint, so its \
             numbers — and ours in the tables — are for bilateral constraints (as in \
             methods.md).",
            fv(&ch.stiff.g0, 3),
            fv(&un.lag_forces, 3),
            un.active_up,
            fmt_f(un.lag_up.u[7], 3),
            fmt_f(un.lag_up.gaps[2], 3),
        ),
    )
}

fn g_cond_drop(s: &Solves, ch: &Checks) -> Note {
    let d = &ch.drop;
    note(
        "g",
        "\"Decrease of the condition number by two orders of magnitude\"",
        format!(
            "cond₂ K / cond₂(K + ε) = {} / {} = {:.1}, i.e. {:.2} decades: just under two \
             orders. The penalties stiffen the softest DOFs: σ_min rises from {} to {} while \
             σ_max moves from {} to {}. The exact δ-targeting penalties (smaller) give \
             cond₂ {} (σ_min {}, σ_max {}), another {:.2}×.",
            fmt_e(s.cond_k, 4),
            fmt_g(s.pap.cond2),
            d.cond_drop,
            d.cond_drop.log10(),
            fmt_g(d.sig_k.sigma_min),
            fmt_g(d.sig_pap.sigma_min),
            fmt_g(d.sig_k.sigma_max),
            fmt_g(d.sig_pap.sigma_max),
            fmt_g(s.con.cond2),
            fmt_g(d.sig_con.sigma_min),
            fmt_g(d.sig_con.sigma_max),
            s.pap.cond2 / s.con.cond2
        ),
    )
}

fn h_not_checkable() -> Note {
    note(
        "h",
        "Not checkable from the paper",
        "\"Even the worst result observed were still better than 5.0e3\" (after moving \
         the rigid surfaces) gives no surface positions, so it cannot be reproduced. \
         Figures 3 and 4 are images only; ours are drawn from Eq. 33 / 36 with the \
         element shape functions (Hermite cubics for w, linear for the axial \
         displacement)."
            .into(),
    )
}

fn i_equal_accuracy(s: &Solves, cond: &[CondRow]) -> Note {
    let uni_min = cond
        .iter()
        .filter(|r| r.series == "uniform")
        .min_by(|a, b| a.cond2.total_cmp(&b.cond2))
        .expect("uniform rows");
    note(
        "i",
        "Equal-accuracy comparison (ours, not in the paper)",
        format!(
            "Conditioning should be compared at equal accuracy. For max penetration δ = {}: \
             condensed cond₂ = {}, a uniform ε = {} (tuned by bisection) cond₂ = {} — \
             slightly lower, so the condensed penalties (the smallest that keep every \
             |g_c| ≤ δ) are not the best-conditioned choice here: cond₂ is not monotone in \
             ε near its minimum (uniform-ε grid: min {} at ε = {}). At the accuracy Eq. 28 \
             actually delivers (max penetration {:.5}): Eq. 28 cond₂ = {}, condensed with \
             δ = {:.5} gives {}, uniform ε = {} gives {}. The δ-driven choices save the \
             trial-and-error tuning of ε, not conditioning at a given accuracy.",
            DELTA,
            fmt_g(s.con.cond2),
            fmt_g(s.eps_tuned),
            fmt_g(s.tuned.cond2),
            fmt_g(uni_min.cond2),
            fmt_g(uni_min.eps),
            s.pen_pap,
            fmt_g(s.pap.cond2),
            s.pen_pap,
            fmt_g(s.con_at_pap.cond2),
            fmt_g(s.eps_at_pap),
            fmt_g(s.uni_at_pap.cond2),
        ),
    )
}

/// The notes (a)–(i).
pub fn notes(s: &Solves, ch: &Checks, cond: &[CondRow]) -> Vec<Note> {
    vec![
        a_tip_axial(s, ch),
        b_eq37_sign(s, ch),
        c_eq30_layout(ch),
        d_units(ch),
        e_overstiffening(s, ch),
        f_unilateral(ch),
        g_cond_drop(s, ch),
        h_not_checkable(),
        i_equal_accuracy(s, cond),
    ]
}
