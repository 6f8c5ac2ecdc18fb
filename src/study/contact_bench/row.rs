//! What the benchmark records: one row per (case, method, knob, mesh), the pressure profiles
//! of the finest meshes and each mesh's conditioning floor.

use serde::{Deserialize, Serialize};

/// One (case, method, knob, mesh).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BenchRow {
    /// The case ([`super::analytic::Case::name`]: `hertz-plane`, `flat-punch`,
    /// `patch-two-body-nts-1`, …).
    pub case: String,
    /// How the contact rows are discretized: `nodal` (one row per contact node), or
    /// `nts-1`, `nts-2` and `mortar` for two bodies.
    #[serde(default = "nodal")]
    pub discretization: String,
    /// Inclination θ of the rigid plane, degrees (0: level).
    #[serde(default)]
    pub theta: f64,
    /// Two bodies: elements across the upper (slave) face over the lower (master) face's.
    #[serde(default)]
    pub mesh_ratio: Option<f64>,
    /// Two bodies: the upper block's Young's modulus.
    #[serde(default)]
    pub young2: Option<f64>,
    /// Two bodies: the upper block's Poisson's ratio.
    #[serde(default)]
    pub poisson2: Option<f64>,
    /// `hertz-two-body`: the second body's (the cylinder's) radius.
    #[serde(default)]
    pub radius2: Option<f64>,
    /// Method name.
    pub method: String,
    /// Knob name (`eps`, `factor`, `delta`, `tol`, `adaptive-tol`, or empty).
    pub knob: String,
    /// Knob value (absolute: ε per unit contact length/area in force/length³, f, δ or
    /// tolerance in length); None without a knob.
    pub knob_value: Option<f64>,
    /// Knob value relative to its scale (ε/(E*/a), f, δ/`length_scale`); None without a knob.
    pub knob_rel: Option<f64>,
    /// Element size at the contact.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub h: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// Total load P (per unit thickness in plane strain).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub load: f64,
    /// Lift of the base at which this rule carries P.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub lift: f64,
    /// Indenter radius R (∞ for the flat punch: written as 0).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub radius: f64,
    /// Young's modulus.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub young: f64,
    /// Poisson's ratio.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub poisson: f64,
    /// Exact contact half-width a.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub a_exact: f64,
    /// Contact half-width from the nodal pressures.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub a_num: f64,
    /// Exact peak pressure.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub p0_exact: f64,
    /// Pressure at the axis node.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub p0_num: f64,
    /// Relative L2 pressure error against the analytic pressure.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub p_err_rel: f64,
    /// Pressure distance from Lagrange on the same mesh (relative to ‖p_exact‖).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub err_penalty: f64,
    /// Lagrange's pressure error against the analytic pressure on this mesh — Hertz: on the
    /// reference block ([`super::domain`]), the finite block's bias removed; the flat punch: on its
    /// block (exact there).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub err_discretization: f64,
    /// What the finite block adds ([`super::domain`]): the distance of Lagrange's pressure on the
    /// benchmark's block from the reference block's, relative to ‖p_exact‖ (0 for the flat
    /// punch).
    #[serde(default, deserialize_with = "crate::provenance::null_as_nan")]
    pub err_domain: f64,
    /// Max penetration.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub max_penetration: f64,
    /// Relative spread (max − min)/mean of the pressures over the contact nodes (the flat
    /// punch's measure; NaN where no node carries pressure).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub p_spread: f64,
    /// cond₂ of the final system matrix.
    pub cond2_system: Option<f64>,
    /// Relative accuracy asked of cond₂.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub cond_tol: f64,
    /// cond₂'s bracket is proven ([`crate::conditioning::CondReport::bounds_proven`]).
    #[serde(default)]
    pub cond2_bounds_proven: Option<bool>,
    /// cond₂ is proven within the accuracy contract `max(1e-12, 4·ε_mach·cond₂)`
    /// ([`crate::conditioning::CondReport::within_contract`]); false where the bracket is
    /// only as narrow as `cond_tol` asked (1e-6 by default), which is wider.
    #[serde(default)]
    pub cond2_within_contract: Option<bool>,
    /// cond₂ of the Jacobi-scaled final system, to `cond_tol` ([`crate::metrics::solver`];
    /// empty in rows written by older versions).
    #[serde(default)]
    pub cond2_jacobi: Option<f64>,
    /// CG iterations with Jacobi from 0 to ‖r‖ ≤ 1e-8‖b‖ (penalties; a residual test, not an
    /// accuracy).
    #[serde(default)]
    pub pcg_iters_jacobi: Option<usize>,
    /// CG iterations with IC(0), the same test (penalties).
    #[serde(default)]
    pub pcg_iters_ic0: Option<usize>,
    /// Both CG runs reached τ within 10·N iterations.
    #[serde(default)]
    pub pcg_converged: Option<bool>,
    /// MINRES iterations (lagrange).
    #[serde(default)]
    pub minres_iters: Option<usize>,
    /// CG iterations with Jacobi from 0 to ‖u_k − u*‖∞ ≤ 1e-6‖u*‖∞ (u* the refined direct
    /// solution; penalties): the count that compares rules at equal accuracy.
    #[serde(default)]
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_jacobi_to_err_converged: Option<bool>,
    /// CG iterations with IC(0) to the same error of u (penalties).
    #[serde(default)]
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_ic0_to_err_converged: Option<bool>,
    /// MINRES iterations to the same error of u (lagrange).
    #[serde(default)]
    pub minres_iters_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub minres_iters_to_err_converged: Option<bool>,
    /// CG iterations with scalar smoothed-aggregation AMG (B = ones) to the same error of u
    /// (penalties).
    #[serde(default)]
    pub pcg_iters_amg_scalar_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_amg_scalar_to_err_converged: Option<bool>,
    /// CG iterations with nodal AMG (the model's rigid-body modes, block size 2) to the same
    /// error of u (penalties).
    #[serde(default)]
    pub pcg_iters_amg_nodal_to_err: Option<usize>,
    /// Whether that run reached the error target.
    #[serde(default)]
    pub pcg_iters_amg_nodal_to_err_converged: Option<bool>,
    /// Relative error of the plain direct solve's u against its double-double refinement.
    #[serde(default)]
    pub forward_err_u: Option<f64>,
    /// The same for the contact forces.
    #[serde(default)]
    pub forward_err_force: Option<f64>,
    /// The solver's own convergence flag (of the last solve of the force control).
    pub converged: bool,
    /// Solves the force control took.
    pub force_solves: usize,
    /// The rule's own outer iterations in the last solve (`Stats::iterations`: Uzawa
    /// updates, active-set or Newton steps).
    #[serde(default)]
    pub iterations: usize,
    /// `barrier` rows: its stiffness κ at the first Newton solve (the rule's hidden second
    /// knob, [`crate::strategy::barrier::KappaReport`]); empty for other rules.
    #[serde(default)]
    pub kappa_initial: Option<f64>,
    /// `barrier` rows: κ of the returned solve.
    #[serde(default)]
    pub kappa_final: Option<f64>,
    /// `barrier` rows: times κ was doubled.
    #[serde(default)]
    pub kappa_increases: Option<usize>,
    /// `barrier` rows: the rule that chose κ ([`crate::strategy::barrier::KappaRule`]: `ipc`, the
    /// default here, the scene having its surface; `balanced` or `fixed` in the κ study).
    #[serde(default)]
    pub kappa_rule: Option<String>,
    /// (total force − P)/P of the reported solution (in magnitude at most the rule's
    /// `Strategy::force_tol`: 1e-10, `optimal` 1e-6; more only where the rule's force
    /// jumps with the lift and the bracket collapsed at the jump).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub force_mismatch: f64,
    /// Wall time of the force-controlled solve, all its solves (s; cond₂ not included).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub seconds: f64,
    /// Error message where the rule refused the scene (empty if it solved).
    pub error: String,
}

/// The nodal pressures of one solve (kept for the finest mesh of each case).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Profile {
    /// Case.
    pub case: String,
    /// Rule ([`super::rule_of`]).
    pub rule: String,
    /// Knob name (as in the rows).
    pub knob: String,
    /// Relative knob value.
    pub knob_rel: Option<f64>,
    /// Element size at the contact.
    pub h: f64,
    /// Node abscissae.
    pub x: Vec<f64>,
    /// Pressures.
    pub p: Vec<f64>,
}

/// The conditioning floor of one mesh: no penalties on its contact DOFs give a system matrix
/// better conditioned than `cond2_floor` ([`crate::strategy::optimal::cond2_lower_bound`]:
/// `λ_max(K)/λ_min(K_FF)`, F the DOFs without a contact constraint, from proven brackets).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Floor {
    /// Case.
    pub case: String,
    /// Element size at the contact.
    pub h: f64,
    /// Free DOFs.
    pub n_dofs: usize,
    /// The certified lower bound of cond₂(K + DEDᵀ) over every E ≥ 0 (NaN where the rows are
    /// dependent: two-pass node-to-segment).
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub cond2_floor: f64,
}

impl BenchRow {
    /// Whether the rule's force-controlled solve succeeded (it found a lift; the row may still
    /// carry an error of its metrics).
    pub fn solved(&self) -> bool {
        !self.lift.is_nan()
    }

    /// The solver-cost columns ([`crate::metrics::solver::Summary`]).
    pub fn set_solver_columns(&mut self, c: crate::metrics::solver::Summary) {
        self.cond2_jacobi = c.cond2_jacobi;
        self.pcg_iters_jacobi = c.pcg_iters_jacobi;
        self.pcg_iters_ic0 = c.pcg_iters_ic0;
        self.pcg_converged = c.pcg_converged;
        self.minres_iters = c.minres_iters;
        self.pcg_iters_jacobi_to_err = c.pcg_iters_jacobi_to_err;
        self.pcg_iters_jacobi_to_err_converged = c.pcg_iters_jacobi_to_err_converged;
        self.pcg_iters_ic0_to_err = c.pcg_iters_ic0_to_err;
        self.pcg_iters_ic0_to_err_converged = c.pcg_iters_ic0_to_err_converged;
        self.minres_iters_to_err = c.minres_iters_to_err;
        self.minres_iters_to_err_converged = c.minres_iters_to_err_converged;
        self.pcg_iters_amg_scalar_to_err = c.pcg_iters_amg_scalar_to_err;
        self.pcg_iters_amg_scalar_to_err_converged = c.pcg_iters_amg_scalar_to_err_converged;
        self.pcg_iters_amg_nodal_to_err = c.pcg_iters_amg_nodal_to_err;
        self.pcg_iters_amg_nodal_to_err_converged = c.pcg_iters_amg_nodal_to_err_converged;
        self.forward_err_u = c.forward_err_u;
        self.forward_err_force = c.forward_err_force;
    }
}

/// The `discretization` of rows written before the column existed.
fn nodal() -> String {
    "nodal".into()
}
