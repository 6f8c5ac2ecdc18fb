//! What the final linear system costs a solver: the digits a direct solve loses and the
//! iterations a preconditioned Krylov solver needs.
//!
//! **The final system** `A x = b` is the one whose solution the strategy reports:
//! - penalties: `A = K + D E Dᵀ`, `b = q + D(E û − λ)` with `λ_c = r_c − ε_c g_c` the part of
//!   the contact force that is not `ε_c g_c` (zero for the pure penalties; the multiplier
//!   estimate of `augmented`; the barrier's force offset at its last Newton point), so that
//!   `K u + D r = q` is its solution;
//! - `lagrange`: `A = [K D_A; D_Aᵀ 0]`, `b = [q; û_A]`, `x = [u; r_A]`.
//!
//! **Metrics** (all on that stored A and b):
//! - `cond2_jacobi`: cond₂(S A S), `S = diag(A)^{−1/2}`, by the cond₂ routes of the
//!   accuracy contract (proven brackets). For the saddle point diag(A) vanishes on the
//!   multiplier block; there `S_λc = diag(K)_{d_c}^{1/2}` (Jacobi on u, and on λ the scaling
//!   that keeps each coupling entry exactly 1), i.e. the matrix `[S K S, D_A; D_Aᵀ, 0]`; for a
//!   row with several terms `S_λc = 1/‖S d_c‖_∞` (its largest coupling entry 1);
//! - `pcg_iters_jacobi_to_err`, `pcg_iters_ic0_to_err`: CG from x₀ = 0
//!   ([`crate::linalg::krylov::cg`]) until `‖u_k − u*‖∞ ≤ e·‖u*‖∞` (e = `krylov_err_target`,
//!   default 1e-6; u* the refined reference below), preconditioned by Jacobi and by IC(0) on
//!   A's pattern ([`crate::linalg::precond::Ic0`], with its Manteuffel shift recorded);
//!   penalties only (A is SPD); `pcg_iters_amg_scalar_to_err` the same with scalar
//!   smoothed-aggregation AMG ([`crate::linalg::amg`], B = ones, one V-cycle per
//!   application; `amg_scalar_levels`: unknowns per level), and `pcg_iters_amg_nodal_to_err`
//!   with nodal aggregation on the problem's near-null space (the rigid-body modes a model or
//!   scene gives, its block size; `amg_nodal_levels`). **These are the counts to compare
//!   rules by**: each reaches the same accuracy of u;
//! - `pcg_iters_jacobi`, `pcg_iters_ic0`: the same runs stopped by SciPy's residual test
//!   `‖r‖₂ ≤ τ‖b‖₂` (one run serves both stops: its iterates do not depend on the test), each beside the error of u at its stop (`pcg_err_u_at_stop_*`); the
//!   effective condition number of the preconditioned operator (`pcg_cond_eff_*`) is estimated
//!   from the Lanczos coefficients of the error-based run (an estimate). The residual test is
//!   not an accuracy: with
//!   `b = q + D E û` and û ≠ 0, ‖b‖ grows with ε and the test loosens (a stiffer penalty
//!   "converges" in fewer iterations to a worse u);
//! - `minres_iters_to_err`, `minres_iters` (`lagrange`): MINRES from x₀ = 0 to the same error
//!   of u (the displacement block), and to `‖r‖_{M⁻¹} ≤ τ‖b‖_{M⁻¹}`, with the block-diagonal
//!   SPD preconditioner `M = diag(diag(K), D_Aᵀ diag(K)⁻¹ D_A)` (Jacobi on K, the diagonal
//!   approximation of the Schur complement on the multipliers);
//! - `forward_err_u`, `forward_err_force`: `‖x̂ − x*‖∞/‖x*‖∞` of the plain f64 direct solve x̂
//!   (Cholesky, or LU for the saddle point; not refined) against the reference x* of
//!   [`crate::linalg::refine`] (double-double residuals; its estimated accuracy is
//!   `reference_accuracy`), for u and for the contact forces r (multipliers for `lagrange`);
//! - `backward_err`: the normwise backward error of x̂ (Rigal & Gaches 1967),
//!   `‖b − A x̂‖∞ / (‖A‖∞‖x̂‖∞ + ‖b‖∞)`, residual in double-double;
//! - `eps_cond2`, `eps_cond2_jacobi`: `ε_mach·cond₂` of A and of S A S, the first-order bounds
//!   the forward error is set beside.
//!
//! When to use: to compare penalty rules by what a user pays rather than by raw cond₂ (a
//! diagonal preconditioner removes most of a penalty's effect on cond₂; van der Sluis).

use super::{cond_of_system, finite_or_null, system_matrix};
use crate::conditioning::CondReport;
use crate::dd::Dd;
use crate::error::{Error, Result};
use crate::linalg::amg::{Amg, AmgOptions};
use crate::linalg::krylov::{self, EachSolver, KrylovRun, Preconditioner, Stop};
use crate::linalg::precond::{Ic0, Jacobi};
use crate::linalg::{refine, Factorization};
use crate::strategy::{Solution, SystemKind};
use crate::system::{Problem, Stiffness};
use serde::Serialize;
use std::time::Instant;

/// The default relative residual τ of the Krylov runs.
pub const DEFAULT_TOL: f64 = 1e-8;

/// The default relative error of u the error-based Krylov counts are taken to
/// (`krylov_err_target`, module doc).
pub const DEFAULT_ERR_TARGET: f64 = 1e-6;

/// The default iteration limit of a Krylov run on N unknowns: SciPy's 10·N, at most 10⁵ (a
/// run that has not converged by then would take hours at 10⁶ unknowns).
pub fn default_max_iters(n: usize) -> usize {
    (10 * n.max(1)).min(100_000)
}

/// Options of [`compute`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverOptions {
    /// τ: the residual-based Krylov runs stop at `‖r‖ ≤ τ‖b‖` (module doc).
    pub tol: f64,
    /// e: the error-based Krylov runs stop at `‖u_k − u*‖∞ ≤ e‖u*‖∞` (module doc).
    pub err_target: f64,
    /// Iteration limit of each Krylov run (`None`: [`default_max_iters`]).
    pub max_iters: Option<usize>,
    /// Relative accuracy asked of `cond2_jacobi` (`None`: the accuracy contract).
    pub cond_tol: Option<f64>,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            tol: DEFAULT_TOL,
            err_target: DEFAULT_ERR_TARGET,
            max_iters: None,
            cond_tol: None,
        }
    }
}

impl SolverOptions {
    /// Checks τ, e ∈ (0, 1) and a positive iteration limit.
    pub fn check(&self) -> Result<()> {
        Error::fraction("Krylov tolerance", self.tol)?;
        Error::fraction("Krylov error target", self.err_target)?;
        if self.max_iters == Some(0) {
            return Err(Error::out_of_range("the Krylov iteration limit", 0, "≥ 1"));
        }
        super::MetricSet::check_cond_tol(self.cond_tol)
    }
}

/// One Krylov run as reported.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct IterativeSolve {
    /// Statistics of the run.
    pub run: KrylovRun,
    /// Wall time from the run's start to this stop (s; the pair's two stops share one run).
    pub seconds: f64,
    /// `‖u_k − u*‖∞/‖u*‖∞` at the run's stop (`None` without a converged reference u*).
    pub err_u: Option<f64>,
}

/// A count of a run to the error target where that run reached it (`None` otherwise): what
/// tables, slopes and figures plot of a row's `*_to_err` and `*_to_err_converged`.
pub fn reached(iters: Option<usize>, converged: Option<bool>) -> Option<usize> {
    iters.filter(|_| converged == Some(true))
}

/// The pair of runs of one Krylov solver and preconditioner (module doc): to the fixed error
/// of u, and to the residual test.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct KrylovPair {
    /// Stopped at `‖u_k − u*‖∞ ≤ e‖u*‖∞` (`None` without a converged reference u*).
    pub to_err: Option<IterativeSolve>,
    /// Stopped at the residual test τ.
    pub residual: Option<IterativeSolve>,
}

impl KrylovPair {
    /// Iterations and convergence of the error-based run.
    pub fn to_err(&self) -> Option<KrylovRun> {
        self.to_err.map(|s| s.run)
    }

    /// Iterations of the error-based run where it reached the target ([`reached`]).
    pub fn iters_reached(&self) -> Option<usize> {
        let r = self.to_err();
        reached(r.map(|r| r.iterations), r.map(|r| r.converged))
    }

    /// Iterations and convergence of the residual-based run.
    pub fn residual(&self) -> Option<KrylovRun> {
        self.residual.map(|s| s.run)
    }

    /// The error of u where the residual-based run stopped.
    pub fn err_u_at_stop(&self) -> Option<f64> {
        self.residual.and_then(|s| s.err_u)
    }

    /// The effective condition number of the preconditioned operator (an estimate from the
    /// run's Lanczos coefficients) of the longer of the two runs: the error-based one where
    /// it ran (a residual run on a stiff penalty may stop after one step and see nothing).
    pub fn effective_cond(&self) -> Option<f64> {
        self.to_err()
            .or(self.residual())
            .and_then(|r| r.effective_cond())
    }
}

/// The solver-cost metrics of one final system (module doc); `None` where a metric does not
/// apply or could not be computed (the reason in `unavailable`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SolverMetrics {
    /// τ of the residual-based Krylov runs.
    pub tol: f64,
    /// e of the error-based Krylov runs.
    pub err_target: f64,
    /// cond₂(S A S).
    pub cond2_jacobi: Option<CondReport>,
    /// CG with Jacobi (penalties).
    pub pcg_jacobi: KrylovPair,
    /// CG with IC(0) (penalties).
    pub pcg_ic0: KrylovPair,
    /// CG with scalar smoothed-aggregation AMG, B = ones (penalties).
    pub pcg_amg_scalar: KrylovPair,
    /// Levels of that AMG hierarchy (unknowns per level, finest first).
    pub amg_scalar_sizes: Vec<usize>,
    /// CG with nodal smoothed-aggregation AMG on the problem's near-null space (penalties,
    /// where the model or scene gives B).
    pub pcg_amg_nodal: KrylovPair,
    /// Levels of the nodal hierarchy (unknowns per level, finest first).
    pub amg_nodal_sizes: Vec<usize>,
    /// IC(0)'s diagonal shift α (`A + α·diag(A)` factored; 0: none needed).
    pub ic0_shift: Option<f64>,
    /// MINRES with the block-diagonal preconditioner (`lagrange`).
    pub minres: KrylovPair,
    /// Relative ∞-norm error of the direct solve's u.
    pub forward_err_u: Option<f64>,
    /// Relative ∞-norm error of the direct solve's contact forces.
    pub forward_err_force: Option<f64>,
    /// Normwise backward error of the direct solve.
    pub backward_err: Option<f64>,
    /// Estimated relative accuracy of the reference solution.
    pub reference_accuracy: Option<f64>,
    /// Refinement steps of the reference.
    pub refinement_steps: Option<usize>,
    /// Wall time of the direct solve: a fresh factorization and one solve (s).
    pub seconds_direct: Option<f64>,
    /// Metrics not computed, with the reason.
    pub unavailable: Vec<String>,
    /// x̂: the plain direct solve the forward and backward errors measure (empty when it
    /// failed; not serialized).
    #[serde(skip)]
    pub x_direct: Vec<f64>,
}

/// The columns a table of rows keeps of [`SolverMetrics`] (`contact_bench`, `sweep
/// --metrics solver`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Summary {
    /// cond₂ of S A S.
    pub cond2_jacobi: Option<f64>,
    /// Jacobi-CG iterations to the error target.
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the target.
    pub pcg_iters_jacobi_to_err_converged: Option<bool>,
    /// IC(0)-CG iterations to the error target.
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// Whether that run reached the target.
    pub pcg_iters_ic0_to_err_converged: Option<bool>,
    /// MINRES iterations to the error target.
    pub minres_iters_to_err: Option<usize>,
    /// Whether that run reached the target.
    pub minres_iters_to_err_converged: Option<bool>,
    /// Scalar smoothed-aggregation AMG-CG iterations to the error target (penalties).
    pub pcg_iters_amg_scalar_to_err: Option<usize>,
    /// Whether that run reached the target.
    pub pcg_iters_amg_scalar_to_err_converged: Option<bool>,
    /// Nodal AMG-CG iterations to the error target (penalties, where the scene gives a
    /// near-null space).
    pub pcg_iters_amg_nodal_to_err: Option<usize>,
    /// Whether that run reached the target.
    pub pcg_iters_amg_nodal_to_err_converged: Option<bool>,
    /// Jacobi-CG iterations to the residual test.
    pub pcg_iters_jacobi: Option<usize>,
    /// IC(0)-CG iterations to the residual test.
    pub pcg_iters_ic0: Option<usize>,
    /// Both CG runs reached τ.
    pub pcg_converged: Option<bool>,
    /// MINRES iterations to the residual test.
    pub minres_iters: Option<usize>,
    /// Forward error of u.
    pub forward_err_u: Option<f64>,
    /// Forward error of the contact forces.
    pub forward_err_force: Option<f64>,
}

impl SolverMetrics {
    /// The [`Summary`] columns.
    pub fn summary(&self) -> Summary {
        let (j, i) = (self.pcg_jacobi.residual(), self.pcg_ic0.residual());
        let to_err = [
            &self.pcg_jacobi,
            &self.pcg_ic0,
            &self.minres,
            &self.pcg_amg_scalar,
            &self.pcg_amg_nodal,
        ]
        .map(|p| p.to_err());
        Summary {
            cond2_jacobi: self.cond2_jacobi.map(|r| r.cond2),
            pcg_iters_jacobi_to_err: to_err[0].map(|r| r.iterations),
            pcg_iters_jacobi_to_err_converged: to_err[0].map(|r| r.converged),
            pcg_iters_ic0_to_err: to_err[1].map(|r| r.iterations),
            pcg_iters_ic0_to_err_converged: to_err[1].map(|r| r.converged),
            minres_iters_to_err: to_err[2].map(|r| r.iterations),
            minres_iters_to_err_converged: to_err[2].map(|r| r.converged),
            pcg_iters_amg_scalar_to_err: to_err[3].map(|r| r.iterations),
            pcg_iters_amg_scalar_to_err_converged: to_err[3].map(|r| r.converged),
            pcg_iters_amg_nodal_to_err: to_err[4].map(|r| r.iterations),
            pcg_iters_amg_nodal_to_err_converged: to_err[4].map(|r| r.converged),
            pcg_iters_jacobi: j.map(|r| r.iterations),
            pcg_iters_ic0: i.map(|r| r.iterations),
            pcg_converged: j.zip(i).map(|(a, b)| a.converged && b.converged),
            minres_iters: self.minres.residual().map(|r| r.iterations),
            forward_err_u: self.forward_err_u,
            forward_err_force: self.forward_err_force,
        }
    }
}

/// The final linear system of a solution (module doc).
#[derive(Clone, Debug)]
pub struct FinalSystem {
    /// A.
    pub a: Stiffness,
    /// b.
    pub b: Vec<f64>,
    /// λ_c of the module doc per constraint (penalties; empty for `lagrange`).
    pub offsets: Vec<f64>,
}

/// The final system `A x = b` of `sol` (module doc).
pub fn final_system(problem: &Problem, sol: &Solution) -> FinalSystem {
    let a = system_matrix(problem, sol);
    match &sol.system {
        SystemKind::Penalized => {
            let mut b = problem.q.clone();
            let mut offsets = vec![0.0; problem.m()];
            for (c, con) in problem.constraints.iter().enumerate() {
                let (e, r, g) = (sol.penalties[c], sol.forces[c], sol.gaps[c]);
                offsets[c] = r - e * g;
                if e != 0.0 || offsets[c] != 0.0 {
                    con.scatter(&mut b, e * con.limit - offsets[c]);
                }
            }
            FinalSystem { a, b, offsets }
        }
        SystemKind::SaddlePoint { active } => {
            let mut b = problem.q.clone();
            b.extend(active.iter().map(|&c| problem.constraints[c].limit));
            FinalSystem {
                a,
                b,
                offsets: Vec::new(),
            }
        }
    }
}

/// Contact forces of a solution x of the final system, in double-double: penalties
/// `ε_c (x_{d_c} − û_c) + λ_c`, multipliers `x_{N+j}` for `lagrange` (0 where inactive).
fn forces_of(problem: &Problem, sol: &Solution, fs: &FinalSystem, x: &[Dd]) -> Vec<Dd> {
    let n = problem.n();
    match &sol.system {
        SystemKind::Penalized => problem
            .constraints
            .iter()
            .enumerate()
            .map(|(c, con)| {
                let v = match con.single_dof() {
                    Some(d) => x[d],
                    None => con
                        .terms
                        .iter()
                        .fold(Dd::ZERO, |s, &(d, a)| s + Dd::from_f64(a) * x[d]),
                };
                let g = v - Dd::from_f64(con.limit);
                Dd::from_f64(sol.penalties[c]) * g + Dd::from_f64(fs.offsets[c])
            })
            .collect(),
        SystemKind::SaddlePoint { active } => {
            let mut f = vec![Dd::ZERO; problem.m()];
            for (j, &c) in active.iter().enumerate() {
                f[c] = x[n + j];
            }
            f
        }
    }
}

/// `ε_mach·cond₂` of a report, when finite.
pub fn eps_cond(c: Option<&CondReport>) -> Option<f64> {
    c.map(|c| c.cond2 * f64::EPSILON).filter(|v| v.is_finite())
}

/// Computes the solver-cost metrics of `sol`'s final system (module doc).
pub fn compute(problem: &Problem, sol: &Solution, opts: SolverOptions) -> Result<SolverMetrics> {
    compute_for(problem, sol, &final_system(problem, sol), opts)
}

/// [`compute`] on the final system `fs` already formed ([`final_system`] of `problem` and
/// `sol`; `solve --write-system` writes the same one). `cond2_jacobi` runs beside the direct
/// solve and the Krylov runs, and the Krylov runs beside one another (rayon): each is
/// sequential inside, so every value is the same for any number of threads; only the
/// `seconds` of a run are wall times taken while the others run.
pub fn compute_for(
    problem: &Problem,
    sol: &Solution,
    fs: &FinalSystem,
    opts: SolverOptions,
) -> Result<SolverMetrics> {
    opts.check()?;
    let mut out = SolverMetrics {
        tol: opts.tol,
        err_target: opts.err_target,
        ..SolverMetrics::default()
    };
    let mut unavailable = Vec::new();
    let (cond, solves) = rayon::join(
        || cond_jacobi(problem, sol, &fs.a, opts.cond_tol, &mut unavailable),
        || direct_and_krylov(problem, sol, fs, &opts, &mut out),
    );
    out.cond2_jacobi = cond?;
    solves?;
    // The reasons in the order the metrics are listed: cond2_jacobi's first.
    unavailable.append(&mut out.unavailable);
    out.unavailable = unavailable;
    Ok(out)
}

/// The direct solve's errors (its reference u* first: the error-based counts stop on it),
/// then every Krylov run of the system's kind, side by side.
fn direct_and_krylov(
    problem: &Problem,
    sol: &Solution,
    fs: &FinalSystem,
    opts: &SolverOptions,
    out: &mut SolverMetrics,
) -> Result<()> {
    let symmetric = fs.a.is_symmetric();
    let u_star = direct_errors(problem, sol, fs, symmetric, out)?;
    if !symmetric {
        out.unavailable.push(
            "Krylov iterations not computed: the system matrix is not symmetric bit for bit \
             (CG and MINRES need a symmetric A)"
                .into(),
        );
        return Ok(());
    }
    if u_star.is_none() {
        out.unavailable.push(
            "error-based Krylov counts not computed: no converged reference u* (see the \
             forward errors)"
                .into(),
        );
    }
    let sparse = fs.a.to_sparse();
    let a = sparse.as_ref();
    let max_iters = opts.max_iters.unwrap_or(default_max_iters(fs.b.len()));
    let pair = |solver: EachSolver, m: &dyn Preconditioner| {
        paired_runs(solver, a, m, &fs.b, opts, max_iters, u_star.as_deref())
    };
    let mut report = |name: &str, e: Error| {
        out.unavailable
            .push(format!("{name}: {}", e.bare_message()));
    };
    match &sol.system {
        SystemKind::Penalized => {
            let amg = |o: &AmgOptions| {
                Amg::new(a, o).map(|m| (m.sizes.clone(), pair(krylov::cg_each, &m)))
            };
            // Without a near-null space the nodal count does not apply (null, not a warning).
            let nodal = problem.near_null.as_ref().map(AmgOptions::nodal);
            let ((jacobi, ic0), (scalar, nodal)) = rayon::join(
                || {
                    rayon::join(
                        || Jacobi::new(a).map(|m| pair(krylov::cg_each, &m)),
                        || Ic0::new(a).map(|m| (m.shift, pair(krylov::cg_each, &m))),
                    )
                },
                || rayon::join(|| amg(&AmgOptions::default()), || nodal.as_ref().map(amg)),
            );
            match jacobi {
                Ok(run) => out.pcg_jacobi = run,
                Err(e) => report("pcg (Jacobi)", e),
            }
            match ic0 {
                Ok((shift, run)) => {
                    out.ic0_shift = Some(shift);
                    out.pcg_ic0 = run;
                }
                Err(e) => report("pcg (IC(0))", e),
            }
            match scalar {
                Ok(run) => (out.amg_scalar_sizes, out.pcg_amg_scalar) = run,
                Err(e) => report("pcg (AMG, scalar)", e),
            }
            match nodal {
                Some(Ok(run)) => (out.amg_nodal_sizes, out.pcg_amg_nodal) = run,
                Some(Err(e)) => report("pcg (AMG, nodal)", e),
                None => {}
            }
        }
        SystemKind::SaddlePoint { active } => match saddle_preconditioner(problem, active) {
            Ok(m) => out.minres = pair(krylov::minres_each, &m),
            Err(e) => report("minres", e),
        },
    }
    Ok(())
}

/// The pair of runs (module doc) from one run of `solver`: its iterates do not depend on the
/// stopping test, so the run to the residual test τ and the run to the error of u (where u*
/// is known) are the same run stopped at two places. Each stop keeps its count, its
/// convergence, its spectrum estimate, the seconds from the start to it and the error of u
/// there.
fn paired_runs(
    solver: EachSolver,
    a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    m: &dyn Preconditioner,
    b: &[f64],
    opts: &SolverOptions,
    max_iters: usize,
    u_star: Option<&[f64]>,
) -> KrylovPair {
    let mut stops = vec![Stop::Residual(opts.tol)];
    if let Some(u) = u_star {
        stops.push(Stop::ErrorOfU {
            reference: u,
            target: opts.err_target,
        });
    }
    let t = Instant::now();
    let mut out = KrylovPair::default();
    solver(a, m, b, &stops, max_iters, &mut |i, x, run| {
        let solve = IterativeSolve {
            run,
            seconds: t.elapsed().as_secs_f64(),
            err_u: u_star.map(|u| krylov::relative_error_of_u(x, u)),
        };
        match i {
            0 => out.residual = Some(solve),
            _ => out.to_err = Some(solve),
        }
    });
    out
}

/// `M⁻¹` of the MINRES preconditioner (module doc): `1/K_ii` on u, and on λ_c the inverse of
/// `d_cᵀ diag(K)⁻¹ d_c = Σ_j a_j²/K_jj` (for a single-DOF row exactly `K_dd`).
fn saddle_preconditioner(problem: &Problem, active: &[usize]) -> Result<Jacobi> {
    let n = problem.n();
    let k = &problem.k;
    let mut inv: Vec<f64> = (0..n).map(|i| 1.0 / k.diag(i)).collect();
    inv.extend(active.iter().map(|&c| {
        let con = &problem.constraints[c];
        match con.single_dof() {
            Some(d) => k.diag(d),
            None => {
                1.0 / con
                    .terms
                    .iter()
                    .map(|&(j, a)| a * a / k.diag(j))
                    .sum::<f64>()
            }
        }
    }));
    Jacobi::from_inverse_diagonal(inv)
}

/// cond₂ of the Jacobi-scaled system (module doc).
fn cond_jacobi(
    problem: &Problem,
    sol: &Solution,
    a: &Stiffness,
    tol: Option<f64>,
    unavailable: &mut Vec<String>,
) -> Result<Option<CondReport>> {
    let n = problem.n();
    let diag: Vec<f64> = (0..a.n()).map(|i| a.diag(i)).collect();
    if let Some(i) = diag[..n].iter().position(|&d| !(d > 0.0 && d.is_finite())) {
        unavailable.push(format!(
            "cond2_jacobi not computed: diagonal entry {i} of the system matrix is {}",
            diag[i]
        ));
        return Ok(None);
    }
    let s: Vec<f64> = diag[..n].iter().map(|d| 1.0 / d.sqrt()).collect();
    match &sol.system {
        SystemKind::Penalized => {
            let scaled = a.scaled(&s);
            let reuse = crate::conditioning::Reuse {
                tol,
                ..Default::default()
            };
            cond_of_system(problem, &sol.system, &scaled, reuse, unavailable)
        }
        SystemKind::SaddlePoint { active } => {
            let scaled_k = problem.k.scaled(&s);
            // Single-DOF rows keep their entry 1; a coupled row becomes S d_c / ‖S d_c‖_∞.
            let rows = problem.constraints.iter().map(|c| {
                if c.single_dof().is_some() {
                    return c.clone();
                }
                let top = c
                    .terms
                    .iter()
                    .fold(0.0f64, |t, &(d, a)| t.max((a * s[d]).abs()));
                let terms = c.terms.iter().map(|&(d, a)| (d, a * s[d] / top)).collect();
                crate::system::Constraint::row(terms, c.limit, c.kind)
            });
            let p = match Problem::new(scaled_k, problem.q.clone(), rows.collect()) {
                Ok(p) => p,
                Err(e) => {
                    unavailable.push(format!("cond2_jacobi not computed: {}", e.bare_message()));
                    return Ok(None);
                }
            };
            let sys = crate::strategy::lagrange::saddle_matrix(&p, active);
            let reuse = crate::conditioning::Reuse {
                tol,
                ..Default::default()
            };
            cond_of_system(&p, &sol.system, &sys, reuse, unavailable)
        }
    }
}

/// The direct solve's forward and backward errors against the refined reference; returns the
/// reference's u block u* (rounded to f64) where the refinement converged.
fn direct_errors(
    problem: &Problem,
    sol: &Solution,
    fs: &FinalSystem,
    symmetric: bool,
    out: &mut SolverMetrics,
) -> Result<Option<Vec<f64>>> {
    // A fresh factorization even where the solve kept its own (`Solution::factor`), so that
    // `seconds_direct` is a whole direct solve (factorization and one solve) for every rule.
    let t = Instant::now();
    let factor = match Factorization::new(&fs.a, symmetric) {
        Ok(f) => f,
        Err(e) => {
            out.unavailable.push(format!(
                "forward/backward errors not computed: {}",
                e.bare_message()
            ));
            return Ok(None);
        }
    };
    let x = factor.solve(&fs.b);
    out.seconds_direct = Some(t.elapsed().as_secs_f64());
    let xd: Vec<Dd> = x.iter().map(|&v| Dd::from_f64(v)).collect();
    let r = refine::residual_dd(&fs.a, &xd, &fs.b);
    let rn = refine::inf_norm(r.iter().map(|v| v.to_f64()));
    let den = fs.a.inf_norm() * refine::inf_norm(x.iter().copied())
        + refine::inf_norm(fs.b.iter().copied());
    out.backward_err = Some(if den > 0.0 { rn / den } else { rn });
    let reference = refine::refine(&fs.a, &fs.b, &factor, &x);
    out.x_direct = x;
    out.refinement_steps = Some(reference.steps);
    out.reference_accuracy = Some(reference.accuracy);
    if !reference.converged {
        out.unavailable.push(format!(
            "forward errors not computed: the reference did not converge (estimated accuracy {:.1e} after {} refinement steps; cond₂ too large for f64 corrections)",
            reference.accuracy, reference.steps
        ));
        return Ok(None);
    }
    let n = problem.n();
    out.forward_err_u = Some(refine::relative_error_dd(
        &out.x_direct[..n],
        &reference.x[..n],
    ));
    let f_hat: Vec<f64> = forces_of(problem, sol, fs, &xd)
        .iter()
        .map(|v| v.to_f64())
        .collect();
    let f_ref = forces_of(problem, sol, fs, &reference.x);
    out.forward_err_force = Some(refine::relative_error_dd(&f_hat, &f_ref));
    Ok(Some(reference.x[..n].iter().map(|v| v.to_f64()).collect()))
}

impl SolverMetrics {
    /// The flat fields under which `solve --json` (and every study that records these
    /// metrics) reports them; `null` where not computed. `eps_cond2` needs the system's
    /// cond₂, computed elsewhere (`cond2_system`).
    pub fn json_fields(
        &self,
        cond2_system: Option<&CondReport>,
    ) -> serde_json::Map<String, serde_json::Value> {
        use serde_json::json;
        let j = self.cond2_jacobi.as_ref();
        let (pj, pi, mr) = (
            self.pcg_jacobi.residual(),
            self.pcg_ic0.residual(),
            self.minres.residual(),
        );
        let both = match (pj, pi) {
            (Some(a), Some(b)) => Some(a.converged && b.converged),
            _ => None,
        };
        let mut fields = json!({
            "cond2_jacobi": finite_or_null(j.map(|c| c.cond2)),
            "cond2_jacobi_lo": finite_or_null(j.map(|c| c.cond2_lo)),
            "cond2_jacobi_hi": finite_or_null(j.map(|c| c.cond2_hi)),
            "cond_route_jacobi": j.map(|c| c.route.name()),
            "eps_cond2": finite_or_null(eps_cond(cond2_system)),
            "eps_cond2_jacobi": finite_or_null(eps_cond(j)),
            "krylov_tol": self.tol,
            "krylov_err_target": self.err_target,
            "pcg_iters_jacobi": pj.map(|r| r.iterations),
            "pcg_converged_jacobi": pj.map(|r| r.converged),
            "pcg_cond_eff_jacobi": finite_or_null(self.pcg_jacobi.effective_cond()),
            "pcg_seconds_jacobi": self.pcg_jacobi.residual.map(|s| s.seconds),
            "pcg_iters_ic0": pi.map(|r| r.iterations),
            "pcg_converged_ic0": pi.map(|r| r.converged),
            "pcg_cond_eff_ic0": finite_or_null(self.pcg_ic0.effective_cond()),
            "pcg_seconds_ic0": self.pcg_ic0.residual.map(|s| s.seconds),
            "ic0_shift": self.ic0_shift,
            "pcg_converged": both,
            "minres_iters": mr.map(|r| r.iterations),
            "minres_converged": mr.map(|r| r.converged),
            "minres_seconds": self.minres.residual.map(|s| s.seconds),
            "forward_err_u": finite_or_null(self.forward_err_u),
            "forward_err_force": finite_or_null(self.forward_err_force),
            "backward_err": finite_or_null(self.backward_err),
            "reference_accuracy": finite_or_null(self.reference_accuracy),
            "refinement_steps": self.refinement_steps,
            "seconds_direct": self.seconds_direct,
        });
        let map = fields.as_object_mut().expect("a JSON object literal");
        // The error-based counts, and the error of u at each residual stop.
        for (name, stop_name, p) in [
            (
                "pcg_iters_jacobi_to_err",
                "pcg_err_u_at_stop_jacobi",
                &self.pcg_jacobi,
            ),
            (
                "pcg_iters_ic0_to_err",
                "pcg_err_u_at_stop_ic0",
                &self.pcg_ic0,
            ),
            (
                "pcg_iters_amg_scalar_to_err",
                "pcg_err_u_at_stop_amg_scalar",
                &self.pcg_amg_scalar,
            ),
            (
                "pcg_iters_amg_nodal_to_err",
                "pcg_err_u_at_stop_amg_nodal",
                &self.pcg_amg_nodal,
            ),
            ("minres_iters_to_err", "minres_err_u_at_stop", &self.minres),
        ] {
            let run = p.to_err();
            map.insert(name.into(), json!(run.map(|r| r.iterations)));
            map.insert(format!("{name}_converged"), json!(run.map(|r| r.converged)));
            map.insert(
                format!("{name}_seconds"),
                json!(p.to_err.map(|s| s.seconds)),
            );
            // The error of u where the error-based run stopped (≤ the target iff converged).
            map.insert(
                format!("{name}_err_u"),
                finite_or_null(p.to_err.and_then(|s| s.err_u)),
            );
            map.insert(stop_name.into(), finite_or_null(p.err_u_at_stop()));
        }
        map.insert(
            "pcg_iters_amg_scalar".into(),
            json!(self.pcg_amg_scalar.residual().map(|r| r.iterations)),
        );
        map.insert("amg_scalar_levels".into(), json!(self.amg_scalar_sizes));
        map.insert(
            "pcg_iters_amg_nodal".into(),
            json!(self.pcg_amg_nodal.residual().map(|r| r.iterations)),
        );
        map.insert("amg_nodal_levels".into(), json!(self.amg_nodal_sizes));
        std::mem::take(map)
    }
}
