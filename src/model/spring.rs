//! The 1-DOF spring of Fig. 1: `Π = ½ k u² − q u + ½ ε (û − u)²` (Eq. 10).
//!
//! Stationarity gives `(k + ε) u = q + ε û` (Eq. 12), `u = (q + ε û)/(k + ε)` (Eq. 13), and the
//! penalty that yields penetration exactly δ (`û − u = δ`, Eq. 15) is
//! `ε = (k(û − δ) − q)/δ` (Eq. 17).

use crate::error::Result;
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};

/// Eq. 13: displacement of the penalized spring.
pub fn displacement(k: f64, q: f64, u_hat: f64, eps: f64) -> f64 {
    (q + eps * u_hat) / (k + eps)
}

/// Eq. 17: the penalty giving penetration exactly δ (`û − u = δ`).
pub fn eq17_penalty(k: f64, q: f64, u_hat: f64, delta: f64) -> f64 {
    (k * (u_hat - delta) - q) / delta
}

/// The spring as a 1×1 contact problem: stiffness k, load q, obstacle `u ≥ û` (`lower`) or a
/// bilateral tie.
pub fn problem(k: f64, q: f64, u_hat: f64, kind: ConstraintKind) -> Result<Problem> {
    Problem::new(
        Stiffness::from_rows(&[vec![k]])?,
        vec![q],
        vec![Constraint::on_dof(0, u_hat, kind)],
    )
}
