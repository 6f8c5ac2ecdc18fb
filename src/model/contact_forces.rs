//! Contact forces read from equilibrium, for [`super::elasticity::Indentation::pressures`].
//!
//! A solution u of a contact problem with rows D (one per column d_c) satisfies
//! `r = K u − q = −D f` for the rows' forces f (a penalty's `ε_c g_c`, a multiplier; every
//! rule the same). Two readings of f from the residual r:
//! - [`row_forces`]: the least-squares row forces `DᵀD f = −Dᵀ r`, defined where D has full
//!   column rank (independent rows: nodal, one-pass node-to-segment, mortar);
//! - [`nodal_forces`]: the contact force on each row's own node, `f_c = −r_d / a_cd` (d the
//!   row's own DOF, a_cd = ±1 its coefficient there), defined whatever the rows' dependence:
//!   r_d is the node's whole contact force. Where no other row touches d (one-pass
//!   node-to-segment) the two readings agree to rounding; with two passes the node's force
//!   holds its own row's and the other pass's shares, and only the sum is defined.

use crate::system::Problem;

/// The row forces f with `r = −D f` (least squares, `DᵀD f = −Dᵀr`, dense m×m Cholesky; NaN
/// where DᵀD is singular or its pivots spread by more than [`DEPENDENT_ROWS_RATIO`]:
/// dependent rows carry no defined share of the force).
pub(super) fn row_forces(p: &Problem, r: &[f64]) -> Vec<f64> {
    let m = p.m();
    let mut dtd = faer::Mat::<f64>::zeros(m, m);
    let n = p.n();
    let mut col = vec![0.0; n];
    for (j, cj) in p.constraints.iter().enumerate() {
        cj.scatter(&mut col, 1.0);
        for (i, ci) in p.constraints.iter().enumerate() {
            dtd[(i, j)] = ci.value(&col);
        }
        for &(d, _) in &cj.terms {
            col[d] = 0.0;
        }
    }
    let mut rhs = faer::Mat::<f64>::from_fn(m, 1, |c, _| -p.constraints[c].value(r));
    let Ok(llt) = dtd.llt(faer::Side::Lower) else {
        return vec![f64::NAN; m];
    };
    // Each pivot L_ii² lies in [λ_min, λ_max] of DᵀD, so max/min pivot ≤ cond(DᵀD): a ratio
    // above 1/√ε_mach proves the forces would keep fewer than half their digits. Dependent
    // rows (two-pass node-to-segment) give a pivot at the rounding level without a
    // breakdown; their shares are not defined.
    let pivots = (0..m).map(|i| llt.L()[(i, i)].powi(2));
    let (lo, hi) = pivots.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if m > 0 && lo * DEPENDENT_ROWS_RATIO < hi {
        return vec![f64::NAN; m];
    }
    faer::linalg::solvers::Solve::solve_in_place(&llt, rhs.as_mut());
    (0..m).map(|c| rhs[(c, 0)]).collect()
}

/// Rows whose DᵀD has a Cholesky pivot ratio above this (1/√ε_mach) are treated as dependent
/// by [`row_forces`].
pub(super) const DEPENDENT_ROWS_RATIO: f64 = 6.7e7;

/// The contact force on each row's own node in the units of the row's force:
/// `f_c = −r_d / a_cd` with d = `own[c]` and a_cd its coefficient in row c (module doc); NaN
/// for a row whose terms lack d.
pub(super) fn nodal_forces(p: &Problem, own: &[usize], r: &[f64]) -> Vec<f64> {
    p.constraints
        .iter()
        .zip(own)
        .map(|(con, &d)| {
            con.terms
                .iter()
                .find(|t| t.0 == d)
                .map_or(f64::NAN, |&(_, a)| -r[d] / a)
        })
        .collect()
}
