//! The computations behind the notes, (a)–(g): the closed-form tip displacement, the gaps of
//! the paper's own Eq. 36, the element layout of Eq. 30, the units, the over-stiffening of
//! Eq. 28, the unilateral reading and the drop of the condition number.

use super::printed::{self, EQ31_K, EQ33_U0, EQ36_U, EQ37_GAPS};
use super::solves::Solves;
use super::DELTA;
use crate::conditioning::{self, CondReport};
use crate::error::{Error, Result};
use crate::model::beam::{self, paper};
use crate::strategy::{self, Method, Solution};
use crate::system::{ConstraintKind, Problem};
use nalgebra::{DMatrix, DVector};
use serde_json::{json, Value};

/// (d) The same beam with E = 210 000 N/mm² and forces in N.
pub struct Units {
    pub e_si: f64,
    /// K(E = 210 000) / K(Eq. 31).
    pub k_ratio: f64,
    pub log10_det_k_si: f64,
    pub cond_k_si: f64,
    /// max |Δu0| with q in N.
    pub u_si_diff: f64,
    /// ε(N) / ε(Eq. 35) per constraint.
    pub eps_si_ratio: Vec<f64>,
}

/// (e) K̄ = DᵀKD against S⁻¹ = (DᵀK⁻¹D)⁻¹, and Eq. 28 read with q̄ and with q.
pub struct Overstiffening {
    pub kbar: DMatrix<f64>,
    pub s_flex: DMatrix<f64>,
    pub s_inv: DMatrix<f64>,
    /// Eigenvalues of K̄ − S⁻¹ (symmetric part), ascending.
    pub diff_eigs: Vec<f64>,
    /// Gaps without contact.
    pub g0: Vec<f64>,
    /// Eq. 28's gaps / δ.
    pub gap_ratio: Vec<f64>,
    /// (I + S E)⁻¹ g0 with Eq. 28's penalties.
    pub g_pred: Vec<f64>,
    /// q̄ = Dᵀq.
    pub qbar: Vec<f64>,
    pub eps_qbar: Vec<f64>,
    pub eps_q_literal: Vec<f64>,
}

/// (f) Bilateral multipliers and the unilateral (upper obstacles) reading.
pub struct Unilateral {
    pub lag_forces: Vec<f64>,
    pub lag_up: Solution,
    pub pap_up: Solution,
    pub con_up: Solution,
    /// Active constraints of the unilateral Lagrange solution, 1-based.
    pub active_up: Vec<usize>,
}

/// (g) cond₂ K / cond₂(K + ε) and the extreme singular values.
pub struct CondDrop {
    pub cond_drop: f64,
    pub sig_k: CondReport,
    pub sig_pap: CondReport,
    pub sig_con: CondReport,
}

/// All checks.
pub struct Checks {
    pub ea: f64,
    /// (a) −50·30/EA.
    pub tip_axial: f64,
    /// (b) Eq. 36 as printed and the gaps computed from it.
    pub eq36: Vec<f64>,
    pub eq36_gaps: Vec<f64>,
    /// (c) element length and the entries of Eq. 30 / 31 discussed.
    pub l_el: f64,
    pub k35_elem: f64,
    pub k35_eq31: f64,
    pub ea_over_l_10: f64,
    pub ea_over_l_30: f64,
    /// max |K − Eq. 31| over the 81 entries.
    pub k_maxdiff: f64,
    pub units: Units,
    pub stiff: Overstiffening,
    pub uni: Unilateral,
    pub drop: CondDrop,
}

/// max |K − printed Eq. 31| over all entries.
fn k_maxdiff(p: &Problem) -> f64 {
    let n = p.n();
    let kd = p.k.to_dense();
    let mut kp = vec![vec![0.0; n]; n];
    for &(i, j, v) in &EQ31_K {
        kp[i][j] = v;
        kp[j][i] = v;
    }
    (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .map(|(i, j)| (kd[(i, j)] - kp[i][j]).abs())
        .fold(0.0, f64::max)
}

fn units(p: &Problem, s: &Solves) -> Result<Units> {
    let e_si = 210_000.0;
    let k_si = beam::Frame::cantilever(
        paper::N_ELEMENTS,
        paper::LENGTH,
        beam::Section::rectangle(e_si, 1.0, 1.0),
    )?
    .assemble(false)?;
    let k_ratio = k_si.get(0, 0) / p.k.get(0, 0);
    let log10_det_k_si = conditioning::log10_abs_det(&k_si)?;
    let cond_k_si = conditioning::cond2(&k_si)?.cond2;
    let q_si: Vec<f64> = p.q.iter().map(|v| v * k_ratio).collect();
    let p_si = Problem::new(k_si, q_si, p.constraints.clone())?;
    let u0_si = strategy::Context::new(&p_si).u0()?.to_vec();
    let u_si_diff =
        s.u0.iter()
            .zip(&u0_si)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
    let pap_si = strategy::solve(&p_si, Method::paper(DELTA))?;
    let eps_si_ratio = pap_si
        .penalties
        .iter()
        .zip(&s.pap.sol.penalties)
        .map(|(a, b)| a / b)
        .collect();
    Ok(Units {
        e_si,
        k_ratio,
        log10_det_k_si,
        cond_k_si,
        u_si_diff,
        eps_si_ratio,
    })
}

fn overstiffening(p: &Problem, s: &Solves) -> Result<Overstiffening> {
    let dofs: Vec<usize> = p.constraints.iter().map(|c| c.lead_dof()).collect(); // the beam: single-DOF constraints
    let m = dofs.len();
    let kn = p.k.to_nalgebra();
    let kinv = kn
        .clone()
        .try_inverse()
        .ok_or_else(|| Error::Numerical("K is singular".into()))?;
    let kbar = DMatrix::from_fn(m, m, |i, j| kn[(dofs[i], dofs[j])]);
    let s_flex = DMatrix::from_fn(m, m, |i, j| kinv[(dofs[i], dofs[j])]);
    let s_inv = s_flex
        .clone()
        .try_inverse()
        .ok_or_else(|| Error::Numerical("S is singular".into()))?;
    let diff = &kbar - &s_inv;
    let diff_sym = (&diff + diff.transpose()) * 0.5;
    let mut diff_eigs: Vec<f64> = diff_sym.symmetric_eigenvalues().iter().copied().collect();
    diff_eigs.sort_by(f64::total_cmp);
    let g0 = p.gaps(&s.u0);
    let gap_ratio = s.pap.sol.gaps.iter().map(|g| g / DELTA).collect();
    // Eq. 28 with ε̄ written via S⁻¹ instead of K̄ — the same targets but the exact stiffness:
    // the penalized gaps solve g = (I + S E)⁻¹ g0.
    let e_pap = DMatrix::from_diagonal(&DVector::from_vec(s.pap.sol.penalties.clone()));
    let g_pred = (DMatrix::identity(m, m) + &s_flex * &e_pap)
        .try_inverse()
        .ok_or_else(|| Error::Numerical("I + S E singular".into()))?
        * DVector::from_vec(g0.clone());
    // Eq. 28 read literally with q_i (the full load vector at index i = 1..m) instead of q̄_i.
    let qbar: Vec<f64> = dofs.iter().map(|&d| p.q[d]).collect();
    let limits: Vec<f64> = p.constraints.iter().map(|c| c.limit).collect();
    let eq28_with = |qv: &[f64]| -> Vec<f64> {
        (0..m)
            .map(|i| {
                let ku: f64 = (0..m).map(|k| kbar[(i, k)] * limits[k]).sum();
                let kdl: f64 = (0..m).map(|k| kbar[(i, k)] * DELTA).sum();
                ((ku - qv[i]).abs() - kdl) / DELTA
            })
            .collect()
    };
    let eps_qbar = eq28_with(&qbar);
    let eps_q_literal = eq28_with(&p.q[..m]);
    Ok(Overstiffening {
        kbar,
        s_flex,
        s_inv,
        diff_eigs,
        g0,
        gap_ratio,
        g_pred: g_pred.iter().copied().collect(),
        qbar,
        eps_qbar,
        eps_q_literal,
    })
}

fn unilateral(s: &Solves) -> Result<Unilateral> {
    let p_up = paper::problem_with_kind(ConstraintKind::Upper);
    let lag_up = strategy::solve(&p_up, Method::lagrange())?;
    let pap_up = strategy::solve(&p_up, Method::paper(DELTA))?;
    let con_up = strategy::solve(&p_up, Method::condensed(DELTA))?;
    let active_up = match &lag_up.system {
        strategy::SystemKind::SaddlePoint { active } => active.iter().map(|c| c + 1).collect(),
        strategy::SystemKind::Penalized => vec![],
    };
    Ok(Unilateral {
        lag_forces: s.lag.sol.forces.clone(),
        lag_up,
        pap_up,
        con_up,
        active_up,
    })
}

fn cond_drop(p: &Problem, s: &Solves) -> Result<CondDrop> {
    let sig = |e: &[f64]| conditioning::cond2(&strategy::penalized_matrix(p, e));
    Ok(CondDrop {
        cond_drop: s.cond_k / s.pap.cond2,
        sig_k: conditioning::cond2(&p.k)?,
        sig_pap: sig(&s.pap.sol.penalties)?,
        sig_con: sig(&s.con.sol.penalties)?,
    })
}

/// Computes the checks (a)–(g) for the beam `p` and its solves.
pub fn compute(p: &Problem, s: &Solves) -> Result<Checks> {
    let sec = beam::Section::rectangle(paper::E, 1.0, 1.0);
    let l_el = paper::LENGTH / paper::N_ELEMENTS as f64;
    let ea = sec.e * sec.a;
    let eq36: Vec<f64> = EQ36_U.iter().map(|s| printed::value(s)).collect();
    let eq36_gaps = p.gaps(&eq36);
    let ke = beam::element_stiffness(sec, l_el);
    let ke_beam_length = beam::element_stiffness(sec, paper::LENGTH);
    Ok(Checks {
        ea,
        tip_axial: paper::LOAD[6] * paper::LENGTH / ea,
        eq36,
        eq36_gaps,
        l_el,
        k35_elem: ke[2][4],      // θ1–w2 coupling (1-based (3,5))
        k35_eq31: p.k.get(2, 4), // Eq. 31 row 3, column 5: −10.5
        ea_over_l_10: ke[0][0],
        ea_over_l_30: ke_beam_length[0][0],
        k_maxdiff: k_maxdiff(p),
        units: units(p, s)?,
        stiff: overstiffening(p, s)?,
        uni: unilateral(s)?,
        drop: cond_drop(p, s)?,
    })
}

fn rows_of(a: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| a[(i, j)]).collect())
        .collect()
}

impl Checks {
    /// The `checks` object of the record.
    pub fn to_json(&self, s: &Solves) -> Value {
        let (u, st, un, dr) = (&self.units, &self.stiff, &self.uni, &self.drop);
        let eq37: Vec<f64> = EQ37_GAPS.iter().map(|g| printed::value(g)).collect();
        json!({
            "a_tip_axial": {
                "EA": self.ea, "formula": "-50 * 30 / EA", "value": self.tip_axial,
                "ours_u0_7": s.u0[6], "paper_printed": printed::value(EQ33_U0[6]),
            },
            "b_eq37_from_eq36": {
                "eq36_printed": self.eq36, "gaps_from_printed_eq36": self.eq36_gaps,
                "ours": s.pap.sol.gaps, "paper_eq37_printed": eq37,
            },
            "c_eq30_layout": {
                "element_length": self.l_el,
                "element_k35_standard": self.k35_elem,
                "eq31_K_3_5": self.k35_eq31,
                "eq30_printed_k35": "+6EJ/l^2",
                "EA_over_l_with_l_30": self.ea_over_l_30,
                "EA_over_l_with_l_10": self.ea_over_l_10,
            },
            "d_units": {
                "E_text_N_per_mm2": u.e_si, "E_eq31": paper::E,
                "K_SI_over_K_eq31": u.k_ratio,
                "log10_det_K_SI": u.log10_det_k_si, "log10_det_K_eq31": s.log10_det_k,
                "cond_K_SI": u.cond_k_si, "cond_K_eq31": s.cond_k,
                "max_abs_u0_difference_with_q_in_N": u.u_si_diff,
                "eps_SI_over_eps_eq35": u.eps_si_ratio,
            },
            "e_overstiffening": {
                "Kbar": rows_of(&st.kbar), "S": rows_of(&st.s_flex), "S_inv": rows_of(&st.s_inv),
                "eig_Kbar_minus_S_inv": st.diff_eigs,
                "g0": st.g0, "gaps_over_delta_eq28": st.gap_ratio,
                "gaps_predicted_by_(I+SE)^-1 g0": st.g_pred,
                "eps_eq28_with_qbar": st.eps_qbar, "eps_eq28_with_literal_q_i": st.eps_q_literal,
                "eps_condensed": s.con.sol.penalties,
            },
            "f_unilateral": {
                "bilateral_lagrange_forces": un.lag_forces,
                "upper_obstacles_lagrange_active_constraints_1based": un.active_up,
                "upper_obstacles_lagrange_u": un.lag_up.u,
                "upper_obstacles_lagrange_gaps": un.lag_up.gaps,
                "upper_obstacles_paper_gaps": un.pap_up.gaps,
                "upper_obstacles_paper_penalties": un.pap_up.penalties,
                "upper_obstacles_condensed_gaps": un.con_up.gaps,
                "upper_obstacles_condensed_penalties": un.con_up.penalties,
            },
            "g_cond_drop": {
                "cond_K_over_cond_K_plus_eps": dr.cond_drop, "decades": dr.cond_drop.log10(),
                "sigma_K": [dr.sig_k.sigma_min, dr.sig_k.sigma_max],
                "sigma_K_plus_eps_eq28": [dr.sig_pap.sigma_min, dr.sig_pap.sigma_max],
                "sigma_K_plus_eps_condensed": [dr.sig_con.sigma_min, dr.sig_con.sigma_max],
            },
            "i_equal_accuracy": {
                "uniform_eps_for_max_pen_delta": s.eps_tuned, "cond": s.tuned.cond2,
                "max_pen": s.tuned.sol.max_penetration,
                "condensed_cond": s.con.cond2,
                "eq28_max_pen": s.pen_pap, "eq28_cond": s.pap.cond2,
                "uniform_eps_for_eq28_max_pen": s.eps_at_pap,
                "uniform_cond_at_eq28_max_pen": s.uni_at_pap.cond2,
                "condensed_cond_at_eq28_max_pen": s.con_at_pap.cond2,
                "condensed_eps_at_eq28_max_pen": s.con_at_pap.sol.penalties,
            },
        })
    }
}
