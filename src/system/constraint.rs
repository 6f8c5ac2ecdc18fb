//! Contact constraints: the rows `d_cᵀ` of Dᵀ with their limits and kinds, and their checks.

use super::Stiffness;
use crate::error::{ConstraintProblem, Error, Result};
use serde::{Deserialize, Serialize};

/// Kind of a contact constraint (binding names: `bilateral`, `upper`, `lower`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ConstraintKind {
    /// `u[d] = û` — always penalized (the paper's beam example).
    Bilateral,
    /// `u[d] ≤ û` — obstacle on the + side; penalized only while violated.
    Upper,
    /// `u[d] ≥ û` — obstacle on the − side; penalized only while violated.
    Lower,
}

impl ConstraintKind {
    /// The kind named `name` as scene files and the Python module write it: `"bilateral"`,
    /// `"upper"` or `"lower"`.
    pub fn from_name(name: &str) -> Option<ConstraintKind> {
        match name {
            "bilateral" => Some(ConstraintKind::Bilateral),
            "upper" => Some(ConstraintKind::Upper),
            "lower" => Some(ConstraintKind::Lower),
            _ => None,
        }
    }

    /// Penetration for the signed gap `g = u[d] − û`.
    pub fn penetration(self, g: f64) -> f64 {
        match self {
            ConstraintKind::Bilateral => g.abs(),
            ConstraintKind::Upper => g.max(0.0),
            ConstraintKind::Lower => (-g).max(0.0),
        }
    }

    /// The signed distance to the obstacle for the signed gap `g = u[d] − û`: `−g` for
    /// `upper`, `g` for `lower`, `−|g|` for bilateral; negative where the row penetrates
    /// (then it is `−penetration`).
    pub fn clearance(self, g: f64) -> f64 {
        match self {
            ConstraintKind::Bilateral => -g.abs(),
            ConstraintKind::Upper => -g,
            ConstraintKind::Lower => g,
        }
    }
}

/// One contact restriction: a row `d_cᵀ` of Dᵀ (its nonzero terms) and an entry `û_c` of û.
///
/// `g_c = d_cᵀu − û_c = Σ_(j, a) a·u[j] − û_c` over the row's terms `(j, a)` (DOF, coefficient).
/// A one-term row with coefficient 1 is the single-DOF constraint `u[d] ⋚ û` of a Boolean
/// (selection) D, where `D E Dᵀ` is diagonal; a row with several terms is a normal on an
/// inclined or curved surface, a node-to-segment or a mortar row, and `D E Dᵀ` couples its
/// DOFs. Build one with [`Constraint::on_dof`] or [`Constraint::row`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Constraint {
    /// The row's terms `(DOF, coefficient)`: 0-based DOF indices, each DOF at most once.
    pub terms: Vec<(usize, f64)>,
    /// Limit `û_c` (units of `d_cᵀu`).
    pub limit: f64,
    /// Bilateral, upper or lower.
    pub kind: ConstraintKind,
}

impl Constraint {
    /// The single-DOF constraint `u[dof] ⋚ limit` (one term, coefficient 1).
    pub fn on_dof(dof: usize, limit: f64, kind: ConstraintKind) -> Self {
        Constraint {
            terms: vec![(dof, 1.0)],
            limit,
            kind,
        }
    }

    /// The constraint `Σ a·u[j] ⋚ limit` over `terms` `(j, a)` (checked by [`Problem::new`](super::Problem::new)).
    /// Terms whose coefficient is exactly zero (either sign) are dropped: they are not part of
    /// the row, so `[[d, 1], [e, 0]]` is the single-DOF row on d, with its routes.
    pub fn row(mut terms: Vec<(usize, f64)>, limit: f64, kind: ConstraintKind) -> Self {
        terms.retain(|t| t.1 != 0.0);
        Constraint { terms, limit, kind }
    }

    /// The DOF of a single-DOF constraint (one term with coefficient exactly 1), else `None`.
    pub fn single_dof(&self) -> Option<usize> {
        match self.terms.as_slice() {
            [(d, a)] if *a == 1.0 => Some(*d),
            _ => None,
        }
    }

    /// The first term's DOF (the DOF of a single-DOF constraint).
    pub fn lead_dof(&self) -> usize {
        self.terms.first().map_or(0, |t| t.0)
    }

    /// How a message names the row: `DOF d` for a single DOF, else `DOFs d1, d2, …`.
    pub fn label(&self) -> String {
        match self.single_dof() {
            Some(d) => format!("DOF {d}"),
            None => {
                let dofs: Vec<String> = self.terms.iter().map(|t| t.0.to_string()).collect();
                format!("DOFs {}", dofs.join(", "))
            }
        }
    }

    /// `d_cᵀu` (for a single-DOF constraint exactly `u[d]`).
    pub fn value(&self, u: &[f64]) -> f64 {
        self.apply(|j| u[j])
    }

    /// `Σ a·x(j)` over the row's terms `(j, a)` (for a single-DOF constraint exactly `x(d)`):
    /// `d_cᵀx` for a vector given entry by entry, e.g. a column of W = K⁻¹D.
    pub fn apply(&self, x: impl Fn(usize) -> f64) -> f64 {
        if let Some(d) = self.single_dof() {
            return x(d);
        }
        self.terms.iter().map(|&(j, a)| a * x(j)).sum()
    }

    /// Moves u so that `d_cᵀu = target`: `u[d] = target` for a single-DOF constraint, else
    /// the orthogonal projection `u += d_c (target − d_cᵀu)/‖d_c‖²`.
    pub fn set_value(&self, u: &mut [f64], target: f64) {
        if let Some(d) = self.single_dof() {
            u[d] = target;
            return;
        }
        let step = (target - self.value(u)) / self.norm2();
        self.scatter(u, step);
    }

    /// The signed gap `g_c = d_cᵀu − û_c`.
    pub fn gap(&self, u: &[f64]) -> f64 {
        self.value(u) - self.limit
    }

    /// `x += v·d_c` (for a single-DOF constraint exactly `x[d] += v`).
    pub fn scatter(&self, x: &mut [f64], v: f64) {
        for &(j, a) in &self.terms {
            x[j] += a * v;
        }
    }

    /// `k_c = d_cᵀ K d_c / ‖d_c‖⁴` (for a single-DOF constraint exactly `K[d, d]`): the
    /// penalty ε at which the penalty's stiffness along the row, `ε‖d_c‖²`, equals K's,
    /// `d_cᵀKd_c/‖d_c‖²`. The penalty rules' stiffness scale, in the units of ε; for a unit
    /// row (a normal) it is `d_cᵀKd_c`.
    pub fn stiffness(&self, k: &Stiffness) -> f64 {
        if let Some(d) = self.single_dof() {
            return k.diag(d);
        }
        let mut s = 0.0;
        for &(i, a) in &self.terms {
            for &(j, b) in &self.terms {
                s += a * b * k.get(i, j);
            }
        }
        let n2 = self.norm2();
        // (s/‖d‖²)/‖d‖², not s/‖d‖⁴: ‖d‖⁴ overflows for ‖d‖ above ~1e77.
        (s / n2) / n2
    }

    /// `‖d_c‖²` (exactly 1 for a single-DOF constraint).
    pub fn norm2(&self) -> f64 {
        if self.single_dof().is_some() {
            return 1.0;
        }
        self.terms.iter().map(|t| t.1 * t.1).sum()
    }

    /// The entries `(i, j, e·a_i·a_j)` of `e·d_c d_cᵀ` (for a single-DOF constraint exactly
    /// `(d, d, e)`).
    pub fn outer(&self, e: f64) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.terms
            .iter()
            .flat_map(move |&(i, a)| self.terms.iter().map(move |&(j, b)| (i, j, e * (a * b))))
    }
}

/// The checks of [`Problem::new`] on the constraints of an N-DOF problem (also run before a
/// scene is written).
pub(crate) fn check_constraints(constraints: &[Constraint], n: usize) -> Result<()> {
    let mut single = vec![false; n];
    let mut in_row = vec![usize::MAX; n];
    for (c, con) in constraints.iter().enumerate() {
        if con.terms.is_empty() {
            return Err(Error::Constraint {
                index: c,
                problem: ConstraintProblem::NoTerms,
            });
        }
        for &(dof, a) in &con.terms {
            if dof >= n {
                return Err(Error::DofOutOfRange {
                    context: format!("constraint {c}"),
                    dof,
                    n,
                });
            }
            if !a.is_finite() {
                return Err(Error::Constraint {
                    index: c,
                    problem: ConstraintProblem::NonFiniteCoefficient { dof },
                });
            }
            if std::mem::replace(&mut in_row[dof], c) == c {
                return Err(Error::Constraint {
                    index: c,
                    problem: ConstraintProblem::RepeatedDof { dof },
                });
            }
        }
        if con.terms.iter().all(|t| t.1 == 0.0) {
            return Err(Error::Constraint {
                index: c,
                problem: ConstraintProblem::AllZero,
            });
        }
        if !con.limit.is_finite() {
            return Err(Error::Constraint {
                index: c,
                problem: ConstraintProblem::NonFiniteLimit,
            });
        }
        if let [(dof, _)] = con.terms[..] {
            if std::mem::replace(&mut single[dof], true) {
                return Err(Error::Constraint {
                    index: c,
                    problem: ConstraintProblem::ConstrainedTwice { dof },
                });
            }
        }
    }
    Ok(())
}
