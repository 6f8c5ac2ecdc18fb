//! The default `adaptive` run (Eq. 28 on the contact rows' residual) must converge
//! and agree with the exact references, every rule must be mesh- and step-converged, and the
//! residual reading must reduce to the literal Eq. 28 where the two coincide.
//!
//! Release-mode numeric tests: the default draw (four runs, ≈ 1 s) plus, per refinement, the
//! four rules at 100 elements or 200 steps (≈ 2 s each on two cores).

use penalty_lab::forming::FormingConfig;
use penalty_lab::strategy::paper;
use penalty_lab::study::forming_runs::record::SavedRuns;
use penalty_lab::study::forming_runs::{self, ExperimentConfig};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use std::sync::OnceLock;

const DELTA: f64 = 1e-5;

fn draw(elements: usize, steps: usize) -> SavedRuns {
    let mut f = FormingConfig::woo_deep_drawing();
    f.elements = elements;
    f.steps = steps;
    let cfg = ExperimentConfig::paper_knobs(f);
    forming_runs::run(
        &penalty_lab::provenance::Provenance::new("deep_drawing"),
        &cfg,
    )
    .expect("the draw runs")
}

fn default_draw() -> &'static SavedRuns {
    static RUNS: OnceLock<SavedRuns> = OnceLock::new();
    RUNS.get_or_init(|| draw(50, 100))
}

fn final_force(doc: &SavedRuns, run: &str) -> f64 {
    doc.runs[run].steps.last().unwrap().punch_force
}

#[test]
fn default_adaptive_run_meets_the_convergence_targets() {
    let doc = default_draw();
    assert!(doc.valid, "{:?}", doc.invalid_reasons);
    let a = &doc.runs["adaptive"];
    let n = a.steps.len();
    let converged = a.steps.iter().filter(|s| s.converged).count();
    assert!(
        converged * 100 >= 95 * n,
        "Picard converged in {converged}/{n}"
    );
    let fa = final_force(doc, "adaptive");
    for reference in ["classical", "condensed"] {
        let f = final_force(doc, reference);
        assert!(
            (fa - f).abs() <= 0.02 * f.abs(),
            "final force {fa} vs {reference} {f}"
        );
    }
    let pen = a
        .steps
        .iter()
        .map(|s| s.max_penetration)
        .fold(0.0, f64::max);
    assert!(pen <= 3.0 * DELTA, "max penetration {pen:.3e} > 3δ");
    let cl = &doc.runs["classical"].steps;
    let mut ratios: Vec<f64> = cl
        .iter()
        .zip(&a.steps)
        .map(|(c, s)| c.cond2 / s.cond2)
        .collect();
    let better = ratios.iter().filter(|&&r| r > 1.0).count();
    assert!(
        better * 100 >= 95 * n,
        "better than classical in {better}/{n}"
    );
    ratios.sort_by(f64::total_cmp);
    let median = ratios[n / 2];
    assert!(median >= 100.0, "median cond ratio {median:.1}");
}

#[test]
fn the_fig7_extras_are_consistent_per_step() {
    // K alone has no contact term: adding the positive semidefinite penalty and friction
    // terms can only raise |det| (log10 ratio > 0); and every run's system is better
    // conditioned than K alone, whose rigid z mode only the drag holds (the paper's "system
    // without any contact conditions").
    for (name, run) in &default_draw().runs {
        for s in &run.steps {
            assert!(s.log10_det_ratio > 0.0, "{name} step {}", s.step);
            assert!(s.cond2 < s.cond2_k, "{name} step {}", s.step);
            assert!(s.cond2_equilibrated.is_finite() && s.cond2_equilibrated >= 1.0);
        }
    }
}

fn assert_refinement_changes_every_rule_by_under_3_percent(fine: &SavedRuns, what: &str) {
    let base = default_draw();
    assert_eq!(fine.runs.len(), base.runs.len());
    for name in base.runs.keys() {
        let (f0, f1) = (final_force(base, name), final_force(fine, name));
        let rel = (f1 - f0).abs() / f0.abs();
        assert!(rel < 0.03, "{name}, {what}: {f0} → {f1} ({rel:.4})");
    }
    // The adaptive run keeps its targets on the refined discretization too.
    assert!(fine.valid, "{what}: {:?}", fine.invalid_reasons);
    let a = &fine.runs["adaptive"].steps;
    let converged = a.iter().filter(|s| s.converged).count();
    assert!(
        converged * 100 >= 95 * a.len(),
        "{what}: {converged}/{}",
        a.len()
    );
    let pen = a.iter().map(|s| s.max_penetration).fold(0.0, f64::max);
    assert!(pen <= 3.0 * DELTA, "{what}: max penetration {pen:.3e}");
}

#[test]
fn doubling_the_elements_changes_every_rules_final_force_by_under_3_percent() {
    assert_refinement_changes_every_rule_by_under_3_percent(&draw(100, 100), "50 → 100 elements");
}

#[test]
fn halving_the_step_changes_every_rules_final_force_by_under_3_percent() {
    assert_refinement_changes_every_rule_by_under_3_percent(&draw(50, 200), "100 → 200 steps");
}

/// A 3-DOF chain with two constrained DOFs (K SPD, coupled).
fn chain() -> Problem {
    let k = Stiffness::from_rows(&[
        vec![4.0, -1.0, 0.0],
        vec![-1.0, 3.0, -1.0],
        vec![0.0, -1.0, 2.0],
    ])
    .unwrap();
    let c = |dof, limit| Constraint::on_dof(dof, limit, ConstraintKind::Bilateral);
    Problem::new(k, vec![1.0, -2.0, 5.0], vec![c(0, 0.5), c(2, -1.0)]).unwrap()
}

#[test]
fn eq28_at_a_zero_reference_is_the_literal_eq28_and_differs_elsewhere() {
    let p = chain();
    let all = [true, true];
    let lit = paper::eq28(&p, &all, 0.1);
    let at0 = paper::eq28_at(&p, &all, 0.1, &[0.0; 3]);
    for (a, b) in lit.iter().zip(&at0) {
        assert!(
            (a - b).abs() <= 1e-12 * a.abs().max(1.0),
            "{lit:?} vs {at0:?}"
        );
    }
    // A free DOF moving couples into both rows: (K ũ − q) changes by K[:,1] u_1.
    let at = paper::eq28_at(&p, &all, 0.1, &[9.0, 5.0, 9.0]);
    assert!((at[0] - lit[0]).abs() > 1.0 && (at[1] - lit[1]).abs() > 1.0);
}

#[test]
fn the_residual_rule_with_corrector_targets_delta_on_a_coupled_problem() {
    let p = chain();
    let delta = 1e-3;
    let sol = paper::solve_residual(&p, delta, &[0.0; 3], 1e-6, 200).unwrap();
    assert!(sol.stats.converged, "{:?}", sol.warnings);
    for (c, g) in sol.gaps.iter().enumerate() {
        assert!(
            (g.abs() - delta).abs() <= 1e-6 * delta,
            "constraint {c}: |g| = {:.6e}",
            g.abs()
        );
        assert!(sol.penalties[c] > 0.0);
    }
}
