//! The README's solver-cost verdict against SciPy and PyAMG on scenes penalty-lab never
//! generated: `tests/data/verdict/reference.json`, made by `scripts/verdict_reference.py`
//! from its own scenes (`tests/data/verdict/scenes/`: a plane-strain Q4 body, 1 764 DOFs,
//! pressed onto a rigid flat — one-DOF rows — and onto planes inclined at 20° and 40° —
//! two-term rows sin θ·u_x + cos θ·u_y ≥ −g₀ —, and a Q1 membrane, 1 363 DOFs, one-DOF rows).
//! The script solves each penalized contact problem with its own active-set iteration, refines
//! u* with exact residuals and counts SciPy's `cg` from x₀ = 0 to ‖u_k − u*‖∞ ≤ 1e-6‖u*‖∞ with
//! Jacobi, IC(0), and PyAMG's smoothed aggregation (scalar, B = ones; nodal, BSR 2×2 with the
//! rigid-body modes), for `constant` at ε = 10^k·k_scale (k_scale = mean diag K) and for
//! `paper` and `condensed` at the penetration of `constant` at k = 2 and 4 (on K + D E Dᵀ with
//! the penalties of penalty-lab's run, stored in the file as input).
//!
//! Here penalty-lab's library runs the same scenes with the same methods and knobs and
//! - its counts agree with the reference's: Jacobi and IC(0) within ±2 or 5 %, AMG within 1.5×,
//!   and the same verdict on reaching the target;
//! - its counts alone give the reference's verdict per coupling, in the README's bounds.
//!
//! The ladder's last rung, k = 10, is in the reference but not compared here: at
//! ε = 10¹⁰·k_scale the runs are at the mercy of rounding on both sides. On body-incline-40
//! penalty-lab's final system penalizes 10 rows and the reference's 9 (row 19 ends at a gap of
//! 1.3e-14: not the same system), and there PyAMG's scalar AMG takes 206 iterations where ours
//! misses the target; SciPy's IC(0)-CG breaks down (NaN) on body-incline-20 where ours takes
//! 47; PyAMG's nodal AMG misses on body-flat where ours takes 7 (the other k = 10 counts agree:
//! Jacobi 1 523 against our 1 517 on body-incline-40, both miss on body-incline-20). The README
//! says as much ("flat until ε = 10¹⁰·k_scale"; there preconditioners miss on some scenes), and
//! runs that miss the target cost 10·N iterations (≈ 7 s a scene).

use penalty_lab::metrics::solver::{self, SolverOptions, Summary};
use penalty_lab::scene::read_scene_preferred;
use penalty_lab::strategy::{self, registry, Knobs, Method};
use serde::Deserialize;
use std::collections::HashMap;

#[derive(Deserialize)]
struct Reference {
    err_target: f64,
    scenes: Vec<SceneRef>,
}

#[derive(Deserialize)]
struct SceneRef {
    name: String,
    scene: String,
    coupling: String,
    eps_ladder: Vec<Run>,
    rules: Vec<Rules>,
}

#[derive(Deserialize)]
struct Rules {
    delta: f64,
    runs: Vec<Run>,
}

#[derive(Deserialize, Clone)]
struct Run {
    k: Option<i32>,
    method: String,
    args: Vec<String>,
    active: usize,
    matched: Option<bool>,
    penalties: Option<Vec<f64>>,
    ic0_shift: f64,
    jacobi_to_err: usize,
    jacobi_to_err_converged: bool,
    ic0_to_err: usize,
    ic0_to_err_converged: bool,
    amg_scalar_to_err: usize,
    amg_scalar_to_err_converged: bool,
    amg_nodal_to_err: Option<usize>,
    amg_nodal_to_err_converged: Option<bool>,
}

/// The preconditioners in the order of [`Counts`].
const PRECONDS: [&str; 4] = ["Jacobi", "IC(0)", "scalar AMG", "nodal AMG"];

/// Iterations to the error target and whether it was reached, per preconditioner (`None`:
/// not run, the scene has no near-null space).
type Counts = [Option<(usize, bool)>; 4];

impl Run {
    fn counts(&self) -> Counts {
        [
            Some((self.jacobi_to_err, self.jacobi_to_err_converged)),
            Some((self.ic0_to_err, self.ic0_to_err_converged)),
            Some((self.amg_scalar_to_err, self.amg_scalar_to_err_converged)),
            self.amg_nodal_to_err.zip(self.amg_nodal_to_err_converged),
        ]
    }

    fn label(&self) -> String {
        format!("{} {}", self.method, self.args.join(" "))
    }
}

fn summary_counts(s: &Summary) -> Counts {
    [
        s.pcg_iters_jacobi_to_err
            .zip(s.pcg_iters_jacobi_to_err_converged),
        s.pcg_iters_ic0_to_err.zip(s.pcg_iters_ic0_to_err_converged),
        s.pcg_iters_amg_scalar_to_err
            .zip(s.pcg_iters_amg_scalar_to_err_converged),
        s.pcg_iters_amg_nodal_to_err
            .zip(s.pcg_iters_amg_nodal_to_err_converged),
    ]
}

fn reference() -> Reference {
    let dir = super::cond_reference::data_dir("verdict");
    let text = std::fs::read_to_string(dir.join("reference.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The README's bounds (its "What a rule costs a solver" paragraph and
/// `figures/solver_cost/README.md`, "The answer" and "The ε map"), each the widest spread it
/// reports, so that a scene it never saw is held to what it claims and no tighter.
mod bound {
    /// One-DOF rows, flat in ε: the widest one-DOF ε-map spread, the beam's Jacobi-CG 67–75
    /// (1.12×), rounded up.
    pub const ONE_DOF_FLAT: f64 = 1.15;
    /// One-DOF rows, across matched rules: Jacobi 1.08×, IC(0) 1.14×, scalar AMG 1.33×; nodal
    /// AMG 1.13× (3-D).
    pub const ONE_DOF_RULES: [f64; 4] = [1.08, 1.14, 1.33, 1.13];
    /// Two-term rows, flat in ε below 10¹⁰·k_scale for IC(0) and nodal AMG: their ε-map spreads
    /// 19–22 (1.16×) and 6–7 (1.17×).
    pub const TWO_TERM_FLAT: f64 = 1.17;
    /// Two-term rows: the smallest growth the README reports for Jacobi-CG over the ε map,
    /// 2.4× (incline-45), and for scalar-AMG-CG, 29 → 63 = 2.2× (incline-45); over eight
    /// decades here (k = 0 … 8), not ten.
    pub const TWO_TERM_GROWTH: [f64; 2] = [2.4, 2.2];
    /// Two-term rows, across matched rules: IC(0) within 1.09×, nodal AMG within 1.17×.
    pub const TWO_TERM_RULES_FLAT: [f64; 2] = [1.09, 1.17];
}

fn ratio(counts: &[usize]) -> f64 {
    let max = *counts.iter().max().unwrap() as f64;
    let min = *counts.iter().min().unwrap() as f64;
    max / min.max(1.0)
}

/// The reached counts of preconditioner `p` over `runs` (all must have reached the target).
fn reached(runs: &[&Counts], p: usize, what: &str) -> Vec<usize> {
    runs.iter()
        .map(|c| {
            let (n, ok) = c[p].unwrap_or_else(|| panic!("{what}: no {} count", PRECONDS[p]));
            assert!(ok, "{what}: {} did not reach the target", PRECONDS[p]);
            n
        })
        .collect()
}

/// The README's verdict for one scene, from one source's counts (`ladder`: `constant` at
/// k = 0 … 8; `rules`: per δ, the matched runs of the three rules). Returns the failures.
fn verdict_failures(
    source: &str,
    scene: &str,
    coupling: &str,
    ladder: &[&Counts],
    rules: &[Vec<&Counts>],
) -> Vec<String> {
    let mut fail = Vec::new();
    let has_nodal = ladder[0][3].is_some();
    let preconds = if has_nodal { 4 } else { 3 };
    let mut check = |ok: bool, msg: String| {
        if !ok {
            fail.push(format!("{source} {scene}: {msg}"));
        }
    };
    for (p, name) in PRECONDS.iter().enumerate().take(preconds) {
        let lad = ratio(&reached(ladder, p, scene));
        let rule_ratios: Vec<f64> = rules.iter().map(|r| ratio(&reached(r, p, scene))).collect();
        let worst_rule = rule_ratios.iter().cloned().fold(1.0, f64::max);
        match (coupling, p) {
            ("one-dof", _) => {
                check(
                    lad <= bound::ONE_DOF_FLAT,
                    format!("{name} over ε {lad:.3}× (one-DOF: flat)"),
                );
                check(
                    worst_rule <= bound::ONE_DOF_RULES[p],
                    format!("{name} across rules {worst_rule:.3}×"),
                );
            }
            ("two-term", 0 | 2) => {
                let g = bound::TWO_TERM_GROWTH[p / 2];
                check(
                    lad >= g,
                    format!("{name} grows only {lad:.3}× over ε (two-term: ≥ {g})"),
                );
            }
            ("two-term", _) => {
                check(
                    lad <= bound::TWO_TERM_FLAT,
                    format!("{name} over ε {lad:.3}× (two-term: flat)"),
                );
                let b = bound::TWO_TERM_RULES_FLAT[p / 2];
                check(
                    worst_rule <= b,
                    format!("{name} across rules {worst_rule:.3}× (≤ {b})"),
                );
            }
            _ => panic!("unknown coupling {coupling}"),
        }
    }
    fail
}

/// The reference's own counts give the README's verdict on every scene (no penalty-lab
/// number involved); and on the two-term scenes `paper`, at equal penetration, needs the
/// most Jacobi- and scalar-AMG-CG iterations of the three rules, as the README says of the
/// stiff rule.
#[test]
fn scipy_and_pyamg_counts_give_the_readmes_verdict() {
    let r = reference();
    assert_eq!(r.scenes.len(), 4);
    let mut fail = Vec::new();
    for s in &r.scenes {
        let ladder: Vec<Counts> = s
            .eps_ladder
            .iter()
            .filter(|run| run.k.unwrap() <= 8)
            .map(Run::counts)
            .collect();
        let rules: Vec<Vec<Counts>> = s
            .rules
            .iter()
            .map(|g| {
                g.runs
                    .iter()
                    .filter(|run| run.matched == Some(true))
                    .map(Run::counts)
                    .collect()
            })
            .collect();
        let ladder_refs: Vec<&Counts> = ladder.iter().collect();
        let rule_refs: Vec<Vec<&Counts>> = rules.iter().map(|g| g.iter().collect()).collect();
        for g in &rule_refs {
            assert_eq!(g.len(), 3, "{}: every rule matched", s.name);
        }
        fail.extend(verdict_failures(
            "SciPy/PyAMG",
            &s.name,
            &s.coupling,
            &ladder_refs,
            &rule_refs,
        ));
        if s.coupling == "two-term" {
            for g in &s.rules {
                for p in [0, 2] {
                    let most = g
                        .runs
                        .iter()
                        .max_by_key(|run| run.counts()[p].unwrap().0)
                        .unwrap();
                    assert_eq!(
                        most.method, "paper",
                        "{} δ {}: {}",
                        s.name, g.delta, PRECONDS[p]
                    );
                }
            }
        }
    }
    assert!(fail.is_empty(), "{}", fail.join("\n"));
}

/// Iteration counts to a fixed error agree within ±2 or 5 % (Jacobi, IC(0)): the same
/// algorithm in a different summation order, whose CG iterates drift apart by rounding — the
/// tolerance of `tests/verification/solver_cost.rs`. The largest gap measured here is
/// ours 503 against SciPy's 480 (4.8 %, `condensed` at δ = 2.5e-7 on body-incline-40): long
/// Jacobi-CG runs on two-term rows are the most rounding-sensitive counts.
fn iterations_agree(ours: usize, theirs: usize) -> bool {
    (ours as f64 - theirs as f64).abs() <= 2.0f64.max(0.05 * theirs as f64)
}

/// AMG counts within 1.5×: the same algorithm (PyAMG's smoothed aggregation, its defaults),
/// but the prolongation smoother's ω comes from a spectral-radius estimate (PyAMG's starts
/// from a random vector) and aggregation ties may break differently; as in `solver_cost.rs`.
fn amg_agrees(ours: usize, theirs: usize) -> bool {
    let (a, b) = (ours as f64, theirs as f64);
    a <= 1.5 * b.max(1.0) && b <= 1.5 * a.max(1.0)
}

fn knobs(args: &[String]) -> Knobs {
    let v: f64 = args[1].parse().unwrap();
    match args[0].as_str() {
        "--eps" => Knobs::eps(v),
        "--delta" => Knobs::delta(v),
        other => panic!("unexpected flag {other}"),
    }
}

/// Solves `scene_name`'s runs with penalty-lab (`constant` at k = 0 … 8, `paper` and
/// `condensed` at both δ), compares every count with the reference's and checks that its own
/// counts give the verdict.
fn check_scene(scene_name: &str) {
    let r = reference();
    let s = r.scenes.iter().find(|s| s.name == scene_name).unwrap();
    let dir = super::cond_reference::data_dir("verdict");
    let scene = read_scene_preferred(&dir.join(&s.scene)).unwrap();
    let p = &scene.problem;
    let opts = SolverOptions {
        err_target: r.err_target,
        // Only the counts are compared: cond₂(S A S), also computed, to 10 %.
        cond_tol: Some(0.1),
        ..SolverOptions::default()
    };
    let mut fail = Vec::new();
    let mut ours: HashMap<String, Counts> = HashMap::new();
    let runs = s
        .eps_ladder
        .iter()
        .filter(|run| run.k.unwrap() <= 8)
        .chain(s.rules.iter().flat_map(|g| &g.runs))
        .filter(|run| run.k.is_none() || run.k.unwrap() <= 8);
    for run in runs {
        let label = run.label();
        if ours.contains_key(&label) {
            continue;
        }
        let method = Method::new(registry::lookup(&run.method).unwrap(), knobs(&run.args)).unwrap();
        let sol = strategy::solve(p, method).unwrap();
        let what = format!("{scene_name} {label}");
        assert!(sol.stats.converged, "{what}: not converged");
        // The system is the reference's: the same penalties (δ rules; stored from
        // `solve --json` when the reference was made) and the same violated rows.
        if let Some(pen) = &run.penalties {
            for (c, (a, b)) in sol.penalties.iter().zip(pen).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-9 * b.abs(),
                    "{what}: penalty {c} is {a}, the reference's system has {b}"
                );
            }
        }
        let violated = sol.gaps.iter().filter(|&&g| g < 0.0).count();
        assert_eq!(violated, run.active, "{what}: violated rows");
        let m = solver::compute(p, &sol, opts).unwrap();
        assert_eq!(m.ic0_shift, Some(run.ic0_shift), "{what}: IC(0) shift");
        let counts = summary_counts(&m.summary());
        eprintln!(
            "{what}: penalty-lab {counts:?}, reference {:?}",
            run.counts()
        );
        for (i, (o, t)) in counts.iter().zip(run.counts()).enumerate() {
            let ok = match (o, t) {
                (Some((a, ra)), Some((b, rb))) => {
                    let close = if i < 2 {
                        iterations_agree(*a, b)
                    } else {
                        amg_agrees(*a, b)
                    };
                    *ra == rb && (close || !rb)
                }
                (None, None) => true,
                _ => false,
            };
            if !ok {
                fail.push(format!(
                    "{what}: {} {o:?} against the reference's {t:?}",
                    PRECONDS[i]
                ));
            }
        }
        ours.insert(label, counts);
    }
    let ladder: Vec<&Counts> = s
        .eps_ladder
        .iter()
        .filter(|run| run.k.unwrap() <= 8)
        .map(|run| &ours[&run.label()])
        .collect();
    // The rules compared where the reference found them matched (penetration within 5 % of δ).
    let rules: Vec<Vec<&Counts>> = s
        .rules
        .iter()
        .map(|g| {
            g.runs
                .iter()
                .filter(|run| run.matched == Some(true))
                .map(|run| &ours[&run.label()])
                .collect()
        })
        .collect();
    fail.extend(verdict_failures(
        "penalty-lab",
        scene_name,
        &s.coupling,
        &ladder,
        &rules,
    ));
    assert!(fail.is_empty(), "{}", fail.join("\n"));
}

#[test]
fn verdict_one_dof_body_on_a_flat() {
    check_scene("body-flat");
}

#[test]
fn verdict_one_dof_q1_membrane() {
    check_scene("membrane-q1");
}

#[test]
fn verdict_two_term_body_on_a_20_degree_incline() {
    check_scene("body-incline-20");
}

#[test]
fn verdict_two_term_body_on_a_40_degree_incline() {
    check_scene("body-incline-40");
}
