//! Contact strategies: eight ways to enforce `Dᵀu ⋚ û` on `K u = q`.
//!
//! | name | knob | penalty ε_c (or method) | paper |
//! |---|---|---|---|
//! | [`constant`] | ε | ε_c = ε | Eq. 9 |
//! | [`scaled`] | factor f | ε_c = f · K[d_c, d_c] | — |
//! | [`spring`] | δ | ε_c = (q_d − k(û + sδ)) / (sδ), k = K\[d,d\], s = sign g0_c | Eq. 17 |
//! | [`paper`] | δ | ε_c = (\|K̄û − q̄\|_c − (K̄δ1)_c) / δ, K̄ = DᵀKD | Eq. 26–29 |
//! | [`condensed`] | δ | ε = S⁻¹(g0 − g*) ./ g*, S = DᵀK⁻¹D, \|g*_c\| = δ | (ours) |
//! | [`optimal`] | δ | min cond₂(K + DEDᵀ) s.t. penetration ≤ δ (smoothed spectrum, barrier, multi-start) | (ours) |
//! | [`lagrange`] | — | saddle point `[K D; Dᵀ 0]`, active set | exact |
//! | [`augmented`] | ε, tol | Uzawa: λ ← λ + ε g until max penetration ≤ tol | — |
//!
//! Each strategy is one file that declares everything about itself in a [`Strategy`]
//! (`STRATEGY`: name, summary, legend label, knob, colour, whether it needs K⁻¹, whether it
//! targets δ, its solve) and its [`Method`] constructor; [`registry::BUILT_IN`] lists them,
//! and the CLI, the sweep, the figures and the studies derive from it. A rule from outside
//! the crate joins through [`registry::register`] (`examples/custom_rule.rs`).
//!
//! Every strategy returns a [`Solution`]: u, the penalties, the gaps, warnings and
//! [`Stats`] (iterations, linear solves, factorizations, active-set sizes, `converged`).
//! Unilateral constraints (`upper`/`lower`) are penalized only while violated. The penalty
//! strategies share the drivers of [`active_set`]: a globalized semismooth Newton method for
//! rules with a fixed energy (`constant`, `scaled`, `augmented`'s inner solves), which always
//! reaches the unique minimizer, and a fixed-point iteration with a documented terminating
//! rule for the rules whose ε depends on the active set (`spring`, `paper`).

pub mod active_set;
pub mod augmented;
pub mod barrier;
pub mod box_qp;
pub mod condensed;
pub mod constant;
pub mod eliminated;
pub mod force_control;
pub mod lagrange;
pub mod optimal;
pub mod paper;
pub mod registry;
pub mod scaled;
pub mod spring;

use crate::error::{Error, Result};
use crate::linalg::{FactorKind, Factorization};
use crate::system::{Problem, Stiffness};
use serde::Serialize;
use std::sync::Arc;

pub use registry::{symbol, Glyph, Knob, Look, Strategy};

pub use active_set::{
    clip_negative, fixed_energy, fixed_point, initial_active_set, max_iterations, per_active,
    violated,
};

/// A strategy with its knob values: what [`solve`] runs. Built by the strategy's own
/// constructor (`Method::constant(ε)`, `Method::condensed(δ)`, … — each in the strategy's
/// file), by [`Method::from_name`] (CLI, configuration files), or by [`Method::new`] for a
/// registered rule from outside the crate ([`registry`]).
///
/// Serialized as `{"method": name, <its knobs>}`: `eps` (`constant`), `factor` (`scaled`),
/// `delta` (the δ rules), `eps`, `tol`, `adaptive` (`augmented`), nothing (`lagrange`).
#[derive(Clone, Copy, Debug)]
pub struct Method {
    strategy: &'static Strategy,
    knobs: Knobs,
}

impl PartialEq for Method {
    fn eq(&self, other: &Self) -> bool {
        self.strategy.name == other.strategy.name && self.knobs == other.knobs
    }
}

impl Serialize for Method {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let k = &self.knobs;
        let mut map = s.serialize_map(None)?;
        map.serialize_entry("method", self.strategy.name)?;
        match self.strategy.knob {
            Knob::None => {}
            Knob::Eps => map.serialize_entry("eps", &k.eps)?,
            Knob::Factor => map.serialize_entry("factor", &k.factor)?,
            Knob::Delta => {
                map.serialize_entry("delta", &k.delta)?;
                if k.kappa != barrier::KappaRule::Auto {
                    map.serialize_entry("kappa", &k.kappa)?;
                }
            }
            Knob::EpsTol => {
                map.serialize_entry("eps", &k.eps)?;
                map.serialize_entry("tol", &k.tol)?;
                map.serialize_entry("adaptive", &k.adaptive)?;
            }
        }
        map.end()
    }
}

/// Knob values for [`Method::from_name`] and [`Method::new`]; a strategy reads those its
/// [`Knob`] names and ignores the others.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Knobs {
    /// ε for `constant` and `augmented`.
    pub eps: Option<f64>,
    /// Factor for `scaled`.
    pub factor: Option<f64>,
    /// δ for `spring`, `paper`, `condensed`, `optimal`.
    pub delta: Option<f64>,
    /// Tolerance for `augmented`.
    pub tol: Option<f64>,
    /// Adaptive penalty update for `augmented`.
    pub adaptive: bool,
    /// How `barrier` chooses its stiffness κ ([`barrier::KappaRule`]; `Auto` by default).
    pub kappa: barrier::KappaRule,
}

impl Knobs {
    /// No knob set.
    pub const NONE: Knobs = Knobs {
        eps: None,
        factor: None,
        delta: None,
        tol: None,
        adaptive: false,
        kappa: barrier::KappaRule::Auto,
    };

    /// ε alone ([`Knob::Eps`]).
    pub const fn eps(v: f64) -> Knobs {
        Knobs {
            eps: Some(v),
            ..Knobs::NONE
        }
    }

    /// f alone ([`Knob::Factor`]).
    pub const fn factor(v: f64) -> Knobs {
        Knobs {
            factor: Some(v),
            ..Knobs::NONE
        }
    }

    /// δ alone ([`Knob::Delta`]).
    pub const fn delta(v: f64) -> Knobs {
        Knobs {
            delta: Some(v),
            ..Knobs::NONE
        }
    }

    /// The value `v` of one knob: ε ([`Knob::Eps`]), f ([`Knob::Factor`]), δ ([`Knob::Delta`])
    /// or the tolerance ([`Knob::EpsTol`], whose ε the caller adds); nothing for
    /// [`Knob::None`].
    pub fn single(knob: Knob, v: f64) -> Knobs {
        let mut k = Knobs::NONE;
        match knob {
            Knob::None => {}
            Knob::Eps => k.eps = Some(v),
            Knob::Factor => k.factor = Some(v),
            Knob::Delta => k.delta = Some(v),
            Knob::EpsTol => k.tol = Some(v),
        }
        k
    }
}

/// The knob `what` of method `name`: set, finite and > 0.
fn positive(name: &str, what: &'static str, v: Option<f64>) -> Result<f64> {
    let v = v.ok_or_else(|| Error::MissingKnob {
        method: name.into(),
        knob: what,
    })?;
    Error::positive(what, v)
}

impl Method {
    /// `strategy` with the knob values it declares, validated (missing, ≤ 0 or NaN → error);
    /// the other fields of `knobs` are dropped.
    pub fn new(strategy: &'static Strategy, knobs: Knobs) -> Result<Self> {
        let n = strategy.name;
        let k = match strategy.knob {
            Knob::None => Knobs::NONE,
            Knob::Eps => Knobs::eps(positive(n, symbol::EPS, knobs.eps)?),
            Knob::Factor => Knobs::factor(positive(n, symbol::FACTOR, knobs.factor)?),
            Knob::Delta => Knobs {
                kappa: knobs.kappa.validated()?,
                ..Knobs::delta(positive(n, symbol::DELTA, knobs.delta)?)
            },
            Knob::EpsTol => Knobs {
                eps: Some(positive(n, symbol::EPS, knobs.eps)?),
                tol: Some(positive(n, symbol::TOL, knobs.tol)?),
                adaptive: knobs.adaptive,
                ..Knobs::NONE
            },
        };
        Ok(Method { strategy, knobs: k })
    }

    /// Builds a method from its name ([`registry::names`]) and knobs, validating them.
    pub fn from_name(name: &str, k: Knobs) -> Result<Self> {
        Method::new(registry::lookup(name)?, k)
    }

    /// A method from a strategy's own constructor: `knobs` hold what its [`Knob`] declares
    /// (not validated, as a literal would not be).
    pub(crate) const fn of(strategy: &'static Strategy, knobs: Knobs) -> Self {
        Method { strategy, knobs }
    }

    /// The strategy.
    pub fn strategy(&self) -> &'static Strategy {
        self.strategy
    }

    /// The knob values (those the strategy's [`Knob`] declares are set).
    pub fn knobs(&self) -> &Knobs {
        &self.knobs
    }

    /// Whether this is a run of `strategy`.
    pub fn is(&self, strategy: &Strategy) -> bool {
        self.strategy.name == strategy.name
    }

    /// The method's name.
    pub fn name(&self) -> &'static str {
        self.strategy.name
    }

    /// δ if the method has one.
    pub fn delta(&self) -> Option<f64> {
        self.knobs.delta
    }

    /// The method's penalty rule as named in messages: `spring (Eq. 17)`, `paper (Eq. 28)`,
    /// otherwise the method name.
    pub fn rule_label(&self) -> &'static str {
        self.strategy.rule_label()
    }

    /// The knob value `v` the strategy declared; [`Error::MissingKnob`] naming the method and
    /// the knob's symbol `what` ([`registry::symbol`]) for a method built without it.
    pub fn value(&self, v: Option<f64>, what: &'static str) -> Result<f64> {
        v.ok_or_else(|| Error::MissingKnob {
            method: self.name().into(),
            knob: what,
        })
    }

    /// Its δ; an error naming the method where it has none.
    pub fn need_delta(&self) -> Result<f64> {
        self.value(self.knobs.delta, symbol::DELTA)
    }
}

/// Solver statistics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Stats {
    /// Outer iterations (active-set or Uzawa).
    pub iterations: usize,
    /// Right-hand sides solved (a block solve with m columns counts m).
    pub linear_solves: usize,
    /// Matrix factorizations.
    pub factorizations: usize,
    /// Number of active (penalized / multiplier) constraints after each iteration.
    pub active_set_sizes: Vec<usize>,
    /// Active constraints whose rule gave a negative penalty at the final iterate (Eq. 17,
    /// Eq. 28), set to 0 and warned about: their penetration is not controlled.
    pub clipped: usize,
    /// The strategy's iteration reached its own solution: the minimizer of the penalized
    /// energy (fixed-energy rules), a consistent active set (set-dependent rules, Lagrange),
    /// the box QP's optimum (condensed), the tolerance (augmented). `false` comes with a
    /// warning that says which terminating rule was applied.
    pub converged: bool,
    /// `condensed`: how many times rounding put a penetration above δ and the targets were
    /// moved inward and the box problem re-solved from its final state (0 almost always).
    pub refinements: usize,
    /// Conjugate-gradient iterations (each: one product with the matrix and one solve with an
    /// earlier factor as preconditioner) spent instead of refactorizing when an active-set
    /// iteration changed few constraints (elimination route; see
    /// [`eliminated`]).
    pub cg_iterations: usize,
    /// `optimal`: the optimality report (KKT residual, starts agreeing, certified lower
    /// bound); absent for the other methods.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal: Option<optimal::OptimalReport>,
    /// `barrier`: its stiffness κ — a second knob the rule sets itself (initial, final,
    /// increases, and the bounds it was clamped to); absent for the other methods.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barrier: Option<barrier::KappaReport>,
}

/// The final system matrix of a solve (for metrics).
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SystemKind {
    /// `K + D E Dᵀ` with E = diag(penalties).
    Penalized,
    /// `[K D_A; D_Aᵀ 0]` with the listed active constraint indices.
    SaddlePoint {
        /// Constraint indices in the saddle-point system.
        active: Vec<usize>,
    },
}

/// Result of a strategy.
#[derive(Clone, Debug, Serialize)]
pub struct Solution {
    /// The method and knob used.
    pub method: Method,
    /// Solution u (N).
    pub u: Vec<f64>,
    /// ε_c per constraint (0 where unpenalized; 0 for `lagrange`).
    pub penalties: Vec<f64>,
    /// Signed gaps g_c = u\[d_c\] − û_c.
    pub gaps: Vec<f64>,
    /// Contact forces r_c (K u = q − D r): `ε_c g_c` for penalties, multipliers otherwise.
    pub forces: Vec<f64>,
    /// max_c penetration.
    pub max_penetration: f64,
    /// The final system matrix kind.
    pub system: SystemKind,
    /// Statistics.
    pub stats: Stats,
    /// Human-readable warnings (assumption failures, non-convergence).
    pub warnings: Vec<String>,
    /// The sparse Cholesky factor of the final penalized system `K + D E Dᵀ`, where the
    /// solve's last factorization is of exactly that matrix (`penalties` bit for bit) and
    /// N ≤ [`crate::conditioning::sparse::RITZ_VECTOR_MAX_N`]: the system's cond₂ solves with
    /// it instead of factorizing the matrix again. Not serialized.
    #[serde(skip)]
    pub factor: Option<Arc<Factorization>>,
    /// The final penalized system `K + D E Dᵀ` that `factor` factors, as the solve assembled
    /// it ([`penalized_matrix`] of `penalties`), where it is symmetric bit for bit (K is, and
    /// every penalized constraint is single-DOF, so `D E Dᵀ` is diagonal): kept with the
    /// factor, so that the metrics neither assemble it nor check its symmetry again. Not
    /// serialized.
    #[serde(skip)]
    pub matrix: Option<Arc<Stiffness>>,
}

/// Solves `problem` with `method`.
pub fn solve(problem: &Problem, method: Method) -> Result<Solution> {
    solve_prepared(problem, method, None)
}

/// Solves `problem` with `method`, reusing K's factorization and u0 from `prepared` (a sweep
/// prepares each scene once). [`Stats`] are the same as without `prepared`: the prepared
/// factorization and u0 solve are counted when the method uses them. A contact set in
/// `prepared` ([`Prepared::with_contact_set`]) changes where the fixed-energy rules start,
/// and so their iteration counts, not their solution.
pub fn solve_prepared(
    problem: &Problem,
    method: Method,
    prepared: Option<&Prepared>,
) -> Result<Solution> {
    let ctx = match prepared {
        Some(p) => Context::from_prepared(problem, p),
        None => Context::new(problem),
    };
    // K's property: checked once per Prepared (a sweep solves many rules on one K).
    let not_spd = match prepared {
        Some(p) => p.not_spd.clone(),
        None => not_spd_warning(problem, None),
    };
    let mut sol = (method.strategy.solve)(ctx, &method)?;
    sol.warnings.extend(not_spd);
    Ok(sol)
}

/// The warning for a symmetric K that is not positive definite, where that shows without
/// extra work: a diagonal entry ≤ 0, or a prepared factorization of K that is not Cholesky.
/// Every strategy here assumes the energy ½uᵀKu − qᵀu (+ penalty terms) is convex; without
/// it the "solution" is only a stationary point. `metrics` says the same when cond₂(K) finds
/// K indefinite ([`NOT_SPD_WARNING`]).
fn not_spd_warning(problem: &Problem, prepared: Option<&Prepared>) -> Option<String> {
    let k = &problem.k;
    if !prepared.map_or_else(|| k.is_symmetric(), |p| p.symmetric) {
        return asymmetry_warning(k);
    }
    let bad_diagonal = (0..k.n()).find(|&i| k.diag(i) <= 0.0 || k.diag(i).is_nan());
    let lu = prepared.is_some_and(|p| {
        matches!(
            p.k_factor().kind(),
            crate::linalg::FactorKind::DenseLu | crate::linalg::FactorKind::SparseLu
        )
    });
    match bad_diagonal {
        Some(i) => Some(format!(
            "{NOT_SPD_WARNING} (K[{i},{i}] = {:e} ≤ 0)",
            k.diag(i)
        )),
        None => lu.then(|| format!("{NOT_SPD_WARNING} (its Cholesky factorization failed)")),
    }
}

/// The warning for a K that is not symmetric bit for bit, naming the asymmetry: the energy
/// ½uᵀKu − qᵀu the strategies minimize sees only K's symmetric part, so u (the solution of the
/// stored system, by LU) is a stationary point of no energy; cond₂ is certified through the
/// symmetric part (a rounding-level asymmetry) or by the SVD.
fn asymmetry_warning(k: &crate::system::Stiffness) -> Option<String> {
    use crate::system::Symmetry;
    match k.symmetry() {
        Symmetry::Exact => None,
        Symmetry::Near(a) => Some(format!(
            "{NOT_SYMMETRIC_WARNING}, by rounding only ({}): u solves the stored matrix (LU, \
             not Cholesky); cond₂ is certified through its symmetric part, the bracket widened \
             for the skew part",
            a.describe()
        )),
        Symmetry::Unsymmetric(a) => Some(format!(
            "{NOT_SYMMETRIC_WARNING} ({}): the energy ½uᵀKu − qᵀu the strategies assume sees only \
             its symmetric part, so u (the solution of the stored system, by LU) minimizes no \
             energy; cond₂ is the SVD's",
            a.describe()
        )),
    }
}

/// The start of the warning for a K that is not symmetric bit for bit.
pub const NOT_SYMMETRIC_WARNING: &str = "K is not symmetric";

/// The start of the warning for a symmetric K that is not positive definite.
pub const NOT_SPD_WARNING: &str = "K is symmetric but not positive definite: the energy the \
     strategies minimize is not convex, so u is a stationary point, not a minimizer, and \
     penetrations and penalties have no energy meaning";

/// K's factorization and the unconstrained solution u0 = K⁻¹q, computed once per problem and
/// shared by every strategy run on it; W = K⁻¹D, computed by the first rule that needs it
/// (`condensed`'s S = DᵀW) and shared from then on; optionally the exact contact set
/// ([`Prepared::with_contact_set`]).
#[derive(Clone)]
pub struct Prepared {
    k_factor: Arc<Factorization>,
    u0: Arc<Vec<f64>>,
    symmetric: bool,
    contact_set: Option<Arc<Vec<bool>>>,
    constraint_columns: ConstraintColumns,
    /// [`not_spd_warning`] of K with this factorization.
    not_spd: Option<String>,
}

/// W = K⁻¹D (N×m), filled once and shared by the clones that hold it.
type ConstraintColumns = Arc<std::sync::OnceLock<Arc<faer::Mat<f64>>>>;

impl Prepared {
    /// Factorizes K and solves for u0. Errors if K is singular.
    pub fn new(problem: &Problem) -> Result<Self> {
        let mut ctx = Context::new(problem);
        ctx.u0()?;
        let mut p = Prepared {
            k_factor: ctx.k_factor.expect("computed by u0"),
            u0: ctx.u0.expect("computed"),
            symmetric: ctx.symmetric,
            contact_set: None,
            constraint_columns: ConstraintColumns::default(),
            not_spd: None,
        };
        p.not_spd = not_spd_warning(problem, Some(&p));
        Ok(p)
    }

    /// The same, with the exact contact set `set[c]` (constraint c active in the `lagrange`
    /// solution, [`Solution::contact_set`]) as the start of the rules whose answer does not
    /// depend on where they start: the fixed-energy rules (`constant`, `scaled`; their Newton
    /// iteration starts from `H_A⁻¹ b_A` on that set instead of from u0,
    /// [`active_set::fixed_energy`]) and `condensed` on its elimination route (that set at
    /// its bounds). Both problems have one solution, so the start changes only the iterations
    /// it takes (on the membranes, where the contact boundary moves one ring of nodes per
    /// iteration from u0, 6–7 solves become 1–3); `Stats` count the rule's own work, not the
    /// lagrange solve that found the set. A set of the wrong length is ignored.
    pub fn with_contact_set(mut self, set: Vec<bool>) -> Self {
        self.contact_set = Some(Arc::new(set));
        self
    }

    /// u0 = K⁻¹q.
    pub fn u0(&self) -> &[f64] {
        &self.u0
    }

    /// K's factorization.
    pub fn k_factor(&self) -> &Factorization {
        &self.k_factor
    }
}

/// Shared state: K's factorization (lazy) and the unconstrained solution u0 = K⁻¹q.
pub struct Context<'a> {
    /// The problem.
    pub problem: &'a Problem,
    /// K is symmetric (selects Cholesky and the eigenvalue cond route).
    pub symmetric: bool,
    k_factor: Option<Arc<Factorization>>,
    u0: Option<Arc<Vec<f64>>>,
    /// The exact contact set, where a [`Prepared`] carried one: where the fixed-energy rules
    /// start.
    contact_set: Option<Arc<Vec<bool>>>,
    /// Last penalized factorization and the penalties it was built with (reused when the
    /// penalties repeat, e.g. Uzawa updates at fixed ε), with the matrix it factors where
    /// [`Context::finish`] may hand that on ([`Solution::matrix`]).
    last: Option<(Vec<f64>, Factorization, Option<Stiffness>)>,
    /// W = K⁻¹D, shared with the [`Prepared`] this context came from.
    constraint_columns: ConstraintColumns,
    /// Work done by a [`Prepared`] that is charged to this solve the first time it is used,
    /// so that statistics do not depend on whether K was prepared in advance:
    /// (factorization of K not yet counted, u0 solve not yet counted).
    uncharged: (bool, bool),
    /// Statistics accumulated so far.
    pub stats: Stats,
}

impl<'a> Context<'a> {
    /// A new context.
    pub fn new(problem: &'a Problem) -> Self {
        Context {
            problem,
            symmetric: problem.k.is_symmetric(),
            k_factor: None,
            u0: None,
            contact_set: None,
            last: None,
            constraint_columns: ConstraintColumns::default(),
            uncharged: (false, false),
            stats: Stats::default(),
        }
    }

    /// A context that starts from a [`Prepared`] K factorization and u0.
    pub fn from_prepared(problem: &'a Problem, p: &Prepared) -> Self {
        Context {
            problem,
            symmetric: p.symmetric,
            k_factor: Some(p.k_factor.clone()),
            u0: Some(p.u0.clone()),
            contact_set: p.contact_set.clone(),
            last: None,
            constraint_columns: p.constraint_columns.clone(),
            uncharged: (true, true),
            stats: Stats::default(),
        }
    }

    /// W = K⁻¹D (N×m: column c is K⁻¹d_c), computed once per [`Prepared`] and shared by
    /// every solve from it (the δ values of a sweep scene); its m solves are counted in every
    /// call's statistics all the same, so they do not depend on the sharing. Errors if K is
    /// singular.
    pub fn constraint_columns(&mut self) -> Result<Arc<faer::Mat<f64>>> {
        let cell = self.constraint_columns.clone();
        let rows: Vec<&[(usize, f64)]> = self
            .problem
            .constraints
            .iter()
            .map(|c| c.terms.as_slice())
            .collect();
        let factor = self.k_factor()?;
        let w = cell.get_or_init(|| Arc::new(factor.solve_sparse_columns(&rows)));
        self.stats.linear_solves += rows.len();
        Ok(w.clone())
    }

    /// Factorization of K (computed once). Errors if K is singular.
    pub fn k_factor(&mut self) -> Result<&Factorization> {
        if std::mem::take(&mut self.uncharged.0) {
            self.stats.factorizations += 1;
        }
        if self.k_factor.is_none() {
            let f = Factorization::new(&self.problem.k, self.symmetric).map_err(|e| match e {
                Error::Singular(m) => Error::singular(format!(
                    "K is singular ({m}); this method needs K⁻¹ (use constant, scaled or lagrange)"
                )),
                e => e,
            })?;
            self.stats.factorizations += 1;
            self.k_factor = Some(Arc::new(f));
        }
        Ok(self.k_factor.as_ref().expect("just set"))
    }

    /// Unconstrained solution u0 = K⁻¹ q (computed once).
    pub fn u0(&mut self) -> Result<&[f64]> {
        if std::mem::take(&mut self.uncharged.1) {
            self.stats.linear_solves += 1;
            if std::mem::take(&mut self.uncharged.0) {
                self.stats.factorizations += 1;
            }
        }
        if self.u0.is_none() {
            let q = self.problem.q.clone();
            let u0 = self.k_factor()?.solve(&q);
            self.stats.linear_solves += 1;
            self.u0 = Some(Arc::new(u0));
        }
        Ok(self.u0.as_deref().map(|v| v.as_slice()).expect("just set"))
    }

    /// The exact contact set carried by a [`Prepared`] ([`Prepared::with_contact_set`]), if it
    /// has one entry per constraint and is not empty (an empty contact set says no more than
    /// u0, which the rules then start from, without solving with K again).
    pub fn contact_set(&self) -> Option<Vec<bool>> {
        self.contact_set
            .as_deref()
            .filter(|s| s.len() == self.problem.m() && s.contains(&true))
            .cloned()
    }

    /// Unconstrained gaps g0 = Dᵀu0 − û.
    pub fn g0(&mut self) -> Result<Vec<f64>> {
        let u0 = self.u0()?.to_vec();
        Ok(self.problem.gaps(&u0))
    }

    /// Solves the penalized system `(K + D E Dᵀ) u = q + D E û`.
    pub fn solve_penalized(&mut self, eps: &[f64]) -> Result<Vec<f64>> {
        let limits: Vec<f64> = self.problem.constraints.iter().map(|c| c.limit).collect();
        self.solve_penalized_with(eps, &limits)
    }

    /// Solves `(K + D E Dᵀ) u = q + D E ℓ` for given limits ℓ (shifted limits of the
    /// augmented Lagrangian).
    pub fn solve_penalized_with(&mut self, eps: &[f64], limits: &[f64]) -> Result<Vec<f64>> {
        let p = self.problem;
        let reuse = matches!(&self.last, Some((e, _, _)) if e.as_slice() == eps);
        if !reuse {
            self.last = None; // one penalized factor in memory at a time
            let a = penalized_matrix(p, eps);
            // K's symbolic analysis serves where K + D E Dᵀ kept K's pattern (a Boolean D, or
            // coupled rows inside it); the coupled rows' fill needs an analysis of its own.
            let sym = self
                .k_factor
                .as_ref()
                .and_then(|f| f.symbolic())
                .filter(|_| a.same_pattern(&p.k));
            let f = Factorization::with_symbolic(&a, self.symmetric, sym).map_err(|e| match e {
                Error::Singular(m) => Error::singular(format!("K + D E Dᵀ is singular ({m})")),
                e => e,
            })?;
            self.stats.factorizations += 1;
            // K exactly symmetric (`self.symmetric`) and D E Dᵀ diagonal: A is too.
            let diagonal =
                (p.constraints.iter().zip(eps)).all(|(c, &e)| e == 0.0 || c.single_dof().is_some());
            let keep = (handed_on(&f) && self.symmetric && diagonal).then_some(a);
            self.last = Some((eps.to_vec(), f, keep));
        }
        let f = &self.last.as_ref().expect("just set").1;
        let mut rhs = p.q.clone();
        for ((c, &e), &l) in p.constraints.iter().zip(eps).zip(limits) {
            c.scatter(&mut rhs, e * l);
        }
        self.stats.linear_solves += 1;
        Ok(f.solve(&rhs))
    }

    /// Drops the last penalized factorization (frees its memory before other large work).
    pub fn release_penalized(&mut self) {
        self.last = None;
    }

    /// Assembles a [`Solution`] from u and the penalties.
    pub fn finish(
        self,
        method: Method,
        u: Vec<f64>,
        penalties: Vec<f64>,
        forces: Option<Vec<f64>>,
        system: SystemKind,
        warnings: Vec<String>,
    ) -> Solution {
        let gaps = self.problem.gaps(&u);
        let forces =
            forces.unwrap_or_else(|| penalties.iter().zip(&gaps).map(|(e, g)| e * g).collect());
        let max_penetration = self.problem.max_penetration(&u);
        let (factor, matrix) = match self.last {
            Some((eps, f, a)) if eps == penalties && handed_on(&f) => {
                (Some(Arc::new(f)), a.map(Arc::new))
            }
            _ => (None, None),
        };
        Solution {
            method,
            u,
            penalties,
            gaps,
            forces,
            max_penetration,
            system,
            stats: self.stats,
            warnings,
            factor,
            matrix,
        }
    }
}

/// Whether a penalized factorization is handed on to the solution ([`Solution::factor`]):
/// a sparse Cholesky factor of at most [`crate::conditioning::sparse::RITZ_VECTOR_MAX_N`]
/// unknowns.
fn handed_on(f: &Factorization) -> bool {
    f.kind() == FactorKind::SparseCholesky
        && f.n() <= crate::conditioning::sparse::RITZ_VECTOR_MAX_N
}

impl Solution {
    /// The contact set of a saddle-point (`lagrange`) solution: `set[c]` iff constraint c is in
    /// its final system; None for the other systems.
    pub fn contact_set(&self) -> Option<Vec<bool>> {
        match &self.system {
            SystemKind::SaddlePoint { active } => {
                let mut set = vec![false; self.penalties.len()];
                for &c in active {
                    *set.get_mut(c)? = true;
                }
                Some(set)
            }
            SystemKind::Penalized => None,
        }
    }
}

/// The penalized matrix `K + D E Dᵀ` of a solution ([`Problem::penalized_k`]).
pub fn penalized_matrix(problem: &Problem, penalties: &[f64]) -> Stiffness {
    problem.penalized_k(penalties)
}
