//! The stress studies: ε sweeps against the reference and every strategy at extreme knobs.

use super::*;
use crate::conditioning;
use crate::error::Result;
use crate::generate::Family;
use crate::metrics::{self, MetricSet};
use crate::strategy::{self, Knob, Method, Solution, SystemKind};
use crate::system::{ConstraintKind, Problem, Stiffness};
use serde::Serialize;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A named problem for the stress studies.
#[derive(Clone, Debug)]
pub struct StressScene {
    /// Name (e.g. `paper-beam`, `spectrum-0001`).
    pub name: String,
    /// Family (`paper`, `beam`, `membrane`, `spectrum`).
    pub family: String,
    /// The problem.
    pub problem: Problem,
}

/// Outcome of one guarded strategy run.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    /// `Ok` with finite outputs.
    Ok,
    /// A clean `Err` (message).
    Error {
        /// The error message.
        message: String,
    },
    /// `Ok` but some output (u, penalties, gaps, forces, max penetration) is NaN/Inf.
    NonFinite {
        /// Which field.
        field: String,
    },
    /// The strategy panicked (message).
    Panic {
        /// The panic payload.
        message: String,
    },
}

impl Outcome {
    /// `ok`, `error`, `non_finite` or `panic`.
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Ok => "ok",
            Outcome::Error { .. } => "error",
            Outcome::NonFinite { .. } => "non_finite",
            Outcome::Panic { .. } => "panic",
        }
    }
    /// The message (empty for `ok`).
    pub fn message(&self) -> String {
        match self {
            Outcome::Ok => String::new(),
            Outcome::Error { message } | Outcome::Panic { message } => message.clone(),
            Outcome::NonFinite { field } => format!("{field} contains NaN/Inf"),
        }
    }
}

/// The first non-finite output field of a solution, if any.
pub fn non_finite_field(sol: &Solution) -> Option<&'static str> {
    let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
    if bad(&sol.u) {
        Some("u")
    } else if bad(&sol.penalties) {
        Some("penalties")
    } else if bad(&sol.gaps) {
        Some("gaps")
    } else if bad(&sol.forces) {
        Some("forces")
    } else if !sol.max_penetration.is_finite() {
        Some("max_penetration")
    } else {
        None
    }
}

/// Runs a strategy, turning a panic into [`Outcome::Panic`] and non-finite output into
/// [`Outcome::NonFinite`].
pub fn guarded_solve(problem: &Problem, method: Method) -> (Outcome, Option<Solution>) {
    match catch_unwind(AssertUnwindSafe(|| strategy::solve(problem, method))) {
        Ok(Ok(sol)) => match non_finite_field(&sol) {
            Some(f) => (
                Outcome::NonFinite {
                    field: f.to_string(),
                },
                Some(sol),
            ),
            None => (Outcome::Ok, Some(sol)),
        },
        Ok(Err(e)) => (
            Outcome::Error {
                message: e.to_string(),
            },
            None,
        ),
        Err(p) => (
            Outcome::Panic {
                message: p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "unknown panic payload".into()),
            },
            None,
        ),
    }
}

/// Forward errors of the five [`SolveOptions::variants`] (`None` where the solve errored).
#[derive(Clone, Debug, Default, Serialize, serde::Deserialize)]
pub struct VariantErrors {
    /// One factorization, one solve.
    pub plain: Option<f64>,
    /// Refinement with an f64 residual.
    pub refined_working: Option<f64>,
    /// Refinement with a double-double residual.
    pub refined_extended: Option<f64>,
    /// Power-of-two equilibration.
    pub equilibrated: Option<f64>,
    /// Equilibration and refinement with a double-double residual.
    pub equilibrated_refined_extended: Option<f64>,
}

impl VariantErrors {
    fn set(&mut self, name: &str, v: Option<f64>) {
        match name {
            "plain" => self.plain = v,
            "refined_working" => self.refined_working = v,
            "refined_extended" => self.refined_extended = v,
            "equilibrated" => self.equilibrated = v,
            _ => self.equilibrated_refined_extended = v,
        }
    }
    /// `(name, value)` pairs in the order of [`SolveOptions::variants`].
    pub fn pairs(&self) -> [(&'static str, Option<f64>); 5] {
        [
            ("plain", self.plain),
            ("refined_working", self.refined_working),
            ("refined_extended", self.refined_extended),
            ("equilibrated", self.equilibrated),
            (
                "equilibrated_refined_extended",
                self.equilibrated_refined_extended,
            ),
        ]
    }
}

/// One point of [`eps_study`].
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct EpsRow {
    /// Scene name.
    pub scene: String,
    /// Scene family.
    pub family: String,
    /// N.
    pub n: usize,
    /// Penalized constraints (the exact solution's active set).
    pub m_active: usize,
    /// Uniform penalty ε.
    pub eps: f64,
    /// cond₂ of `K + ε D_A D_Aᵀ` by [`PenalizedSystem::cond2_extended`] (accurate beyond
    /// 1/ε_mach); `None` if it could not be computed.
    pub cond2: Option<f64>,
    /// cond₂ of the f64-assembled matrix by [`conditioning::cond2`] (the harness's exact route,
    /// all in f64: reliable while cond₂ ≲ 1e15, noise beyond).
    pub cond2_f64: Option<f64>,
    /// cond₂ · ε_mach: the classical forward-error bound.
    pub cond_eps_mach: Option<f64>,
    /// cond₂ of the equilibrated matrix `S A S` ([`Stiffness::equilibration`]): it bounds Cholesky's
    /// forward error in the S⁻¹-weighted norm (van der Sluis; Demmel 1989), and is far below
    /// cond₂ when the ill-conditioning is a matter of diagonal scale, as with a few huge
    /// penalties. Against the plain 2-norm error it is an empirical predictor only (see the
    /// `forward_error_vs_scaled_cond` figure).
    pub cond2_scaled: Option<f64>,
    /// `cond₂ · ε_mach` exceeds [`metrics::DIGITS_LOST_THRESHOLD`], the threshold of
    /// [`metrics::precision_warnings`].
    pub precision_warning: bool,
    /// [`Reference::correction`] (a-posteriori error estimate of u*).
    pub reference_correction: Option<f64>,
    /// Forward errors `‖x − u*‖/‖u*‖` per solve variant.
    pub forward: VariantErrors,
    /// Messages of variants that errored (`variant: message`).
    pub variant_errors: Vec<String>,
    /// Refinement steps taken by `refined_extended`.
    pub steps_extended: Option<usize>,
    /// Model error of the penalty: `‖u* − u_lagrange‖/‖u_lagrange‖` (`None` when lagrange
    /// refuses the scene). u_lagrange is itself an f64 solve, accurate to about
    /// cond₂(saddle)·ε_mach, which is where this error levels off at large ε.
    pub penalty_error: Option<f64>,
    /// Total error of the plain f64 solve: `‖x_plain − u_lagrange‖/‖u_lagrange‖`.
    pub total_error_plain: Option<f64>,
    /// Total error of the best variant (`equilibrated_refined_extended`) against lagrange.
    pub total_error_refined: Option<f64>,
    /// The `constant` strategy at this ε: outcome name.
    pub strategy_status: String,
    /// The `constant` strategy's message (error/panic), empty if ok.
    pub strategy_message: String,
    /// The `constant` strategy's max penetration.
    pub strategy_max_penetration: Option<f64>,
    /// The `constant` strategy's warnings plus the precision warnings of its system.
    pub strategy_warnings: usize,
}

/// Configuration of the stress studies.
#[derive(Clone, Debug, Serialize)]
pub struct StressConfig {
    /// ε grid for `constant` and [`eps_study`] (absolute values).
    pub eps: Vec<f64>,
    /// Factors for `scaled`.
    pub factors: Vec<f64>,
    /// δ relative to the displacement scale max_c |u0\[d_c\]| (spring, paper, condensed).
    pub deltas_rel: Vec<f64>,
    /// Augmented: ε relative to max_c K\[d_c,d_c\].
    pub augmented_eps_rel: Vec<f64>,
    /// Augmented: tolerance relative to the displacement scale.
    pub augmented_tol_rel: Vec<f64>,
    /// Maximum refinement steps.
    pub max_steps: usize,
}

impl Default for StressConfig {
    fn default() -> Self {
        StressConfig {
            eps: (0..=46)
                .map(|k| 10f64.powf(-3.0 + 0.5 * k as f64))
                .collect(),
            factors: vec![1e-12, 1e-6, 1.0, 1e4, 1e8, 1e12, 1e16, 1e20],
            deltas_rel: vec![1e-18, 1e-14, 1e-10, 1e-6, 1e-3, 0.1, 1.0, 1e3, 1e8],
            augmented_eps_rel: vec![1e-9, 1.0, 1e9],
            augmented_tol_rel: vec![1e-15, 1e-6],
            max_steps: 10,
        }
    }
}

/// The exact contact solution (`lagrange`) and the constraints active in it.
pub fn exact_contact(problem: &Problem) -> Result<(Vec<f64>, Vec<bool>)> {
    let sol = strategy::solve(problem, Method::lagrange())?;
    let mut active = vec![false; problem.m()];
    if let SystemKind::SaddlePoint { active: a } = &sol.system {
        for &c in a {
            active[c] = true;
        }
    }
    Ok((sol.u, active))
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Cond₂ of a matrix, `None` if not computable or infinite.
fn cond_of(a: &Stiffness) -> Option<f64> {
    conditioning::cond2(a).ok().and_then(|c| finite(c.cond2))
}

/// Uniform-ε study on one scene: for each ε, the penalized system `K + ε D_A D_Aᵀ` over the
/// constraints active in the exact contact solution (all of them for bilateral scenes) is
/// solved by every [`SolveOptions::variants`] and compared with the double-double reference
/// and with lagrange; the `constant` strategy is run at the same ε.
pub fn eps_study(scene: &StressScene, cfg: &StressConfig) -> Result<Vec<EpsRow>> {
    let p = &scene.problem;
    // Lagrange may refuse a near-singular K: then every constraint is penalized and the
    // errors against the exact contact solution are left empty.
    let (u_lag, active) = match exact_contact(p) {
        Ok((u, a)) => (Some(u), a),
        Err(_) => (None, vec![true; p.m()]),
    };
    let mut rows = Vec::with_capacity(cfg.eps.len());
    for &eps in &cfg.eps {
        let pen: Vec<f64> = active.iter().map(|&a| if a { eps } else { 0.0 }).collect();
        let sys = PenalizedSystem::new(p, &pen)?;
        let a = sys.matrix();
        let cond2_f64 = cond_of(&a);
        let cond2_scaled = cond_of(&a.scaled(&a.equilibration()));
        let cond2 = sys.cond2_extended().ok();
        let reference = sys.reference().ok();
        let mut forward = VariantErrors::default();
        let mut variant_errors = Vec::new();
        let mut steps_extended = None;
        let mut x_plain = None;
        let mut x_best = None;
        for (name, opts) in SolveOptions::variants(cfg.max_steps) {
            match solve(&sys, opts) {
                Ok(r) => {
                    let err = reference
                        .as_ref()
                        .map(|rf| metrics::relative_error(&r.x, &rf.u))
                        .and_then(finite);
                    forward.set(name, err);
                    if name == "refined_extended" {
                        steps_extended = Some(r.steps);
                    }
                    if name == "plain" {
                        x_plain = Some(r.x);
                    } else if name == "equilibrated_refined_extended" {
                        x_best = Some(r.x);
                    }
                }
                Err(e) => variant_errors.push(format!("{name}: {e}")),
            }
        }
        let (outcome, sol) = guarded_solve(p, Method::constant(eps));
        let strategy_warnings = sol.as_ref().map_or(0, |s| {
            let m = metrics::compute_with_k(
                p,
                s,
                MetricSet {
                    cond: true,
                    det: false,
                    cond_tol: None,
                },
                None,
                None,
                None,
            )
            .unwrap_or_default();
            s.warnings.len() + metrics::precision_warnings(&m).len()
        });
        let precision_warning = match cond2 {
            Some(c) => c * f64::EPSILON > metrics::DIGITS_LOST_THRESHOLD,
            None => true,
        };
        rows.push(EpsRow {
            scene: scene.name.clone(),
            family: scene.family.clone(),
            n: p.n(),
            m_active: active.iter().filter(|&&a| a).count(),
            eps,
            cond2,
            cond2_f64,
            cond_eps_mach: cond2.map(|c| c * f64::EPSILON),
            cond2_scaled,
            precision_warning,
            reference_correction: reference.as_ref().map(|r| r.correction).and_then(finite),
            forward,
            variant_errors,
            steps_extended,
            penalty_error: match (&reference, &u_lag) {
                (Some(r), Some(ul)) => finite(metrics::relative_error(&r.u, ul)),
                _ => None,
            },
            total_error_plain: match (&x_plain, &u_lag) {
                (Some(x), Some(ul)) => finite(metrics::relative_error(x, ul)),
                _ => None,
            },
            total_error_refined: match (&x_best, &u_lag) {
                (Some(x), Some(ul)) => finite(metrics::relative_error(x, ul)),
                _ => None,
            },
            strategy_status: outcome.name().into(),
            strategy_message: outcome.message(),
            strategy_max_penetration: sol.as_ref().map(|s| s.max_penetration).and_then(finite),
            strategy_warnings,
        });
    }
    Ok(rows)
}

/// One strategy run of [`strategy_study`].
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct StrategyRow {
    /// Scene name.
    pub scene: String,
    /// Scene family.
    pub family: String,
    /// N.
    pub n: usize,
    /// m.
    pub m: usize,
    /// Method name.
    pub method: String,
    /// The knob's name (`eps`, `factor`, `delta`, `eps,tol`, `-`).
    pub knob: String,
    /// The knob's value (ε, factor or δ; ε for augmented).
    pub value: f64,
    /// Second knob (augmented tolerance), else `None`.
    pub value2: Option<f64>,
    /// Adaptive augmented.
    pub adaptive: bool,
    /// `ok`, `error`, `non_finite`, `panic`.
    pub status: String,
    /// Error / panic message.
    pub message: String,
    /// Max penetration.
    pub max_penetration: Option<f64>,
    /// Largest penalty used.
    pub max_penalty: Option<f64>,
    /// Exact cond₂ of the final system matrix.
    pub cond2_system: Option<f64>,
    /// cond₂ · ε_mach > [`metrics::DIGITS_LOST_THRESHOLD`].
    pub precision_expected: bool,
    /// The solution's warnings plus [`metrics::precision_warnings`].
    pub warnings: Vec<String>,
    /// `‖u − u*‖/‖u*‖` against the double-double solution of its own penalized system
    /// (penalty strategies except `augmented`, whose final limits are shifted).
    pub forward_error: Option<f64>,
    /// `‖u − u_lagrange‖/‖u_lagrange‖`.
    pub error_vs_lagrange: Option<f64>,
}

/// The jobs of [`strategy_study`] on a scene of displacement scale `scale` whose largest
/// constraint stiffness is `kmax`, through the one expansion of knob grids
/// ([`KnobGrid::points`]), in the rows' order: `constant` at every ε, `scaled` at every
/// factor, `spring`, `paper` and `condensed` at each relative δ in turn, `augmented` at each
/// relative ε and tolerance (fixed, then adaptive update), `lagrange`. Each job: the method,
/// the knob's name in the rows (`eps,tol` for augmented, `-` for lagrange) and its values
/// (augmented: ε and the tolerance).
fn strategy_jobs(
    cfg: &StressConfig,
    scale: f64,
    kmax: f64,
) -> Vec<(Method, &'static str, f64, Option<f64>)> {
    use crate::strategy::{augmented, condensed, constant, lagrange, paper, scaled, spring};
    use crate::study::grid::{Augmented, KnobGrid, Level};
    let absolute = |v: &[f64]| v.iter().map(|&x| Level::absolute(x)).collect();
    let mut grids = vec![
        (
            KnobGrid {
                eps: absolute(&cfg.eps),
                ..KnobGrid::default()
            },
            vec![&constant::STRATEGY],
        ),
        (
            KnobGrid {
                factors: absolute(&cfg.factors),
                ..KnobGrid::default()
            },
            vec![&scaled::STRATEGY],
        ),
    ];
    for &r in &cfg.deltas_rel {
        let grid = KnobGrid {
            deltas: vec![Level::relative(r, scale)],
            ..KnobGrid::default()
        };
        grids.push((
            grid,
            vec![&spring::STRATEGY, &paper::STRATEGY, &condensed::STRATEGY],
        ));
    }
    for &er in &cfg.augmented_eps_rel {
        for &tr in &cfg.augmented_tol_rel {
            let grid = KnobGrid {
                tols: vec![Level::relative(tr, scale)],
                augmented: [false, true]
                    .map(|adaptive| Augmented {
                        eps: er * kmax,
                        adaptive,
                        name: "eps,tol",
                    })
                    .to_vec(),
                ..KnobGrid::default()
            };
            grids.push((grid, vec![&augmented::STRATEGY]));
        }
    }
    let exact = KnobGrid {
        exact: Some(Level::absolute(0.0)),
        ..KnobGrid::default()
    };
    grids.push((exact, vec![&lagrange::STRATEGY]));
    grids
        .iter()
        .flat_map(|(grid, strategies)| grid.points(strategies))
        .map(|p| {
            let k = p.method.knobs();
            match p.method.strategy().knob {
                Knob::EpsTol => (p.method, p.knob, k.eps.unwrap_or(f64::NAN), k.tol),
                Knob::None => (p.method, "-", 0.0, None),
                _ => (p.method, p.knob, p.level.value, None),
            }
        })
        .collect()
}

/// Every strategy at the knobs of `cfg` (extremes included) on one scene, guarded.
pub fn strategy_study(scene: &StressScene, cfg: &StressConfig) -> Result<Vec<StrategyRow>> {
    let p = &scene.problem;
    let u_lag = exact_contact(p).ok().map(|(u, _)| u);
    let scale = strategy::Prepared::new(p)
        .map(|pr| p.displacement_scale(pr.u0()))
        .unwrap_or(1.0);
    let kmax = p
        .constraints
        .iter()
        .map(|c| c.stiffness(&p.k).abs())
        .fold(0.0f64, f64::max);
    let kmax = if kmax > 0.0 { kmax } else { 1.0 };
    let jobs = strategy_jobs(cfg, scale, kmax);
    let mut rows = Vec::with_capacity(jobs.len());
    for (method, knob, value, value2) in jobs {
        let (outcome, sol) = guarded_solve(p, method);
        let mut warnings = Vec::new();
        let mut cond2_system = None;
        let mut forward_error = None;
        if let Some(s) = &sol {
            warnings.extend(s.warnings.iter().cloned());
            if let Ok(m) = metrics::compute_with_k(
                p,
                s,
                MetricSet {
                    cond: true,
                    det: false,
                    cond_tol: None,
                },
                None,
                None,
                None,
            ) {
                cond2_system = m.cond2_system.map(|c| c.cond2).and_then(finite);
                warnings.extend(metrics::precision_warnings(&m));
            }
            let penalty_method = !method.is(&strategy::lagrange::STRATEGY)
                && !method.is(&strategy::augmented::STRATEGY);
            if penalty_method && outcome.name() == "ok" {
                forward_error = PenalizedSystem::new(p, &s.penalties)
                    .and_then(|sys| sys.reference())
                    .ok()
                    .map(|r| metrics::relative_error(&s.u, &r.u))
                    .and_then(finite);
            }
        }
        let precision_expected =
            cond2_system.is_some_and(|c| c * f64::EPSILON > metrics::DIGITS_LOST_THRESHOLD);
        rows.push(StrategyRow {
            scene: scene.name.clone(),
            family: scene.family.clone(),
            n: p.n(),
            m: p.m(),
            method: method.name().into(),
            knob: knob.into(),
            value,
            value2,
            adaptive: method.knobs().adaptive,
            status: outcome.name().into(),
            message: outcome.message(),
            max_penetration: sol.as_ref().map(|s| s.max_penetration).and_then(finite),
            max_penalty: sol
                .as_ref()
                .map(|s| s.penalties.iter().fold(0.0f64, |a, v| a.max(*v)))
                .and_then(finite),
            cond2_system,
            precision_expected,
            warnings,
            forward_error,
            error_vs_lagrange: match (&sol, &u_lag) {
                (Some(s), Some(ul)) => finite(metrics::relative_error(&s.u, ul)),
                _ => None,
            },
        });
    }
    Ok(rows)
}

/// The stress scenes: the paper's beam (bilateral, and with `upper` obstacles), then `count`
/// generated scenes per family with sizes small enough for the dense double-double reference
/// (beams of 3–12 elements, a 10×10 membrane, spectrum matrices of N = 8–40 with eigenvalue
/// spreads 10¹⁰–10¹⁶).
pub fn stress_scenes(seed: u64, count: usize, families: &[Family]) -> Result<Vec<StressScene>> {
    use crate::generate::{generate, GeneratorConfig};
    let mut out = vec![
        StressScene {
            name: "paper-beam".into(),
            family: "paper".into(),
            problem: crate::model::beam::paper::problem(),
        },
        StressScene {
            name: "paper-beam-upper".into(),
            family: "paper".into(),
            problem: crate::model::beam::paper::problem_with_kind(ConstraintKind::Upper),
        },
    ];
    let cfg = GeneratorConfig {
        beam_elements: (3, 12),
        membrane_side: (10, 10),
        spectrum_n: (8, 40),
        spectrum_log10_spread: (10.0, 16.0),
        elastic_h: (0.1, 0.25),
    };
    for &family in families {
        for i in 0..count {
            let g = generate(family, i, seed, &cfg)?;
            out.push(StressScene {
                name: g.name,
                family: family.name().into(),
                problem: g.problem,
            });
        }
    }
    Ok(out)
}
