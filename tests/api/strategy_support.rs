//! Helpers of the strategy tests (`strategy_*`): each contact strategy's defining property
//! (shared/notes/methods.md), checked on the paper's beam (Eq. 30–34) and on small handmade scenes.
//!
//! Expected values come from closed forms (the 1-DOF spring of Eq. 10–17, a two-spring chain
//! solved by hand), from defining properties (penetration exactly δ, equilibrium, complementarity),
//! from formulas recomputed here independently with nalgebra (Eq. 17, Eq. 28, S = DᵀK⁻¹D), or from
//! numbers printed in methods.md / the paper — never from our own code's output.
//!
//! Tolerances are derived from the problem: a backward-stable solve of an n×n system with 2-norm
//! condition number κ has relative forward error ≲ c·n·ε_mach·κ and relative residual
//! ≲ c·n·ε_mach (Higham, *Accuracy and Stability of Numerical Algorithms*, §7.1 and §9–10); see
//! [`rounding_tol`] and [`residual_tol`].

use crate::common::dense::{dense, inf};
use nalgebra::{DMatrix, DVector};
use penalty_lab::conditioning;
use penalty_lab::model::beam::{paper, Frame, Section};
use penalty_lab::strategy::Method;
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};

/// Safety constant `c` in the rounding bounds below. Wilkinson/Higham bounds for Cholesky and
/// partial-pivoting LU are `γ_{cn}` with small c; 8 covers the extra products (right-hand-side
/// assembly, D E û, the gap subtraction) done around the solve.
pub(crate) const C_ROUND: f64 = 8.0;

/// Forward-error tolerance for a quantity of magnitude `scale` obtained from an n×n solve with
/// condition number `cond`: `c · n · ε_mach · cond · scale`.
pub(crate) fn rounding_tol(cond: f64, n: usize, scale: f64) -> f64 {
    C_ROUND * n as f64 * f64::EPSILON * cond * scale
}

/// Residual (backward-error) tolerance of a backward-stable solve of `A x = b`:
/// `‖A x − b‖∞ ≤ c · n · ε_mach · (‖A‖∞ ‖x‖∞ + ‖b‖∞)` — no condition number involved.
pub(crate) fn residual_tol(a: &DMatrix<f64>, x: &[f64], b: &[f64]) -> f64 {
    C_ROUND * a.nrows() as f64 * f64::EPSILON * (norm_inf_mat(a) * inf(x) + inf(b))
}

/// cond₂ of a stiffness (the library's exact route; cross-checked against SVD elsewhere).
pub(crate) fn cond_of(k: &Stiffness) -> f64 {
    conditioning::cond2(k).expect("cond2").cond2
}

pub(crate) fn norm_inf_mat(a: &DMatrix<f64>) -> f64 {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

pub(crate) fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

pub(crate) fn diff2(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Unconstrained solution u0 = K⁻¹ q by nalgebra's LU.
pub(crate) fn u0_of(p: &Problem) -> Vec<f64> {
    let k = dense(&p.k);
    let x = k
        .lu()
        .solve(&DVector::from_column_slice(&p.q))
        .expect("K nonsingular");
    x.iter().copied().collect()
}

/// `S = DᵀK⁻¹D` (m×m) for the listed constraint indices.
pub(crate) fn flexibility(p: &Problem, idx: &[usize]) -> DMatrix<f64> {
    let kinv = dense(&p.k).try_inverse().expect("K nonsingular");
    DMatrix::from_fn(idx.len(), idx.len(), |i, j| {
        kinv[(
            p.constraints[idx[i]].single_dof().unwrap(),
            p.constraints[idx[j]].single_dof().unwrap(),
        )]
    })
}

/// `K + D E Dᵀ` and `q + D E ℓ` built here from the problem data.
pub(crate) fn penalized_system(
    p: &Problem,
    eps: &[f64],
    limits: &[f64],
) -> (DMatrix<f64>, Vec<f64>) {
    let mut a = dense(&p.k);
    let mut b = p.q.clone();
    for ((c, &e), &l) in p.constraints.iter().zip(eps).zip(limits) {
        a[(c.single_dof().unwrap(), c.single_dof().unwrap())] += e;
        b[c.single_dof().unwrap()] += e * l;
    }
    (a, b)
}

pub(crate) fn matvec(a: &DMatrix<f64>, x: &[f64]) -> Vec<f64> {
    (a * DVector::from_column_slice(x))
        .iter()
        .copied()
        .collect()
}

pub(crate) fn limits(p: &Problem) -> Vec<f64> {
    p.constraints.iter().map(|c| c.limit).collect()
}

/// The paper's beam with per-constraint kinds (DOFs 4, 6, 7; limits 3, −1, 30 of Eq. 34).
pub(crate) fn beam_with_kinds(kinds: [ConstraintKind; 3], sparse: bool) -> Problem {
    let k = paper::frame().assemble(sparse).unwrap();
    let cons = paper::DOFS
        .iter()
        .zip(paper::LIMITS)
        .zip(kinds)
        .map(|((&dof, limit), kind)| Constraint::on_dof(dof, limit, kind))
        .collect();
    Problem::new(k, paper::LOAD.to_vec(), cons).unwrap()
}

/// Node 2 transverse `lower` at −1 (never touched: u0 = 26.7), tip axial bilateral at −1, tip
/// transverse `upper` at 30 (violated by u0 = 51.4).
pub(crate) fn beam_mixed(sparse: bool) -> Problem {
    use ConstraintKind::*;
    beam_with_kinds([Lower, Bilateral, Upper], sparse)
}

/// A 6-element cantilever (L = 60, E = 2100, 1×1.5 section) with a transverse tip load, a
/// moment at node 3 and an axial load; obstacles on three transverse DOFs.
pub(crate) fn cantilever6(sparse: bool) -> Problem {
    let f = Frame::cantilever(6, 60.0, Section::rectangle(2100.0, 1.0, 1.5)).unwrap();
    let k = f.assemble(sparse).unwrap();
    let mut q = vec![0.0; f.n_dofs()];
    q[f.dof(6, 1).unwrap()] = 2.0;
    q[f.dof(3, 2).unwrap()] = -5.0;
    q[f.dof(6, 0).unwrap()] = 10.0;
    let cons = vec![
        Constraint::on_dof(f.dof(2, 1).unwrap(), 1.0, ConstraintKind::Upper),
        Constraint::on_dof(f.dof(4, 1).unwrap(), -3.0, ConstraintKind::Lower),
        Constraint::on_dof(f.dof(6, 1).unwrap(), 20.0, ConstraintKind::Bilateral),
    ];
    Problem::new(k, q, cons).unwrap()
}

/// Ground —k1— u0 —k2— u1, load P at u1, constraint on u1 of the given kind and limit.
pub(crate) fn chain(k1: f64, k2: f64, p: f64, limit: f64, kind: ConstraintKind) -> Problem {
    Problem::new(
        Stiffness::from_rows(&[vec![k1 + k2, -k2], vec![-k2, k2]]).unwrap(),
        vec![0.0, p],
        vec![Constraint::on_dof(1, limit, kind)],
    )
    .unwrap()
}

pub(crate) fn all_scenes() -> Vec<(&'static str, Problem)> {
    use ConstraintKind::*;
    vec![
        ("beam bilateral", paper::problem()),
        ("beam upper", paper::problem_with_kind(Upper)),
        ("beam lower", paper::problem_with_kind(Lower)),
        ("beam mixed", beam_mixed(false)),
        ("cantilever6", cantilever6(false)),
        ("chain upper", chain(3.0, 7.0, 5.0, 0.5, Upper)),
    ]
}

pub(crate) fn penalty_methods(delta: f64) -> Vec<Method> {
    vec![
        Method::constant(1e3),
        Method::scaled(10.0),
        Method::spring(delta),
        Method::paper(delta),
        Method::condensed(delta),
    ]
}

pub(crate) fn all_methods(delta: f64) -> Vec<Method> {
    let mut v = penalty_methods(delta);
    v.push(Method::lagrange());
    v.push(Method::augmented(100.0, 1e-6, false));
    v.push(Method::augmented(100.0, 1e-6, true));
    v
}

/// `|a − b| ≤` half a unit in the `sig`-th significant digit of `b` (printed precision).
pub(crate) fn printed_sig(a: f64, b: f64, sig: i32) -> bool {
    let e = b.abs().log10().floor() as i32;
    (a - b).abs() <= 0.5 * 10f64.powi(e - sig + 1) * (1.0 + 1e-12)
}
