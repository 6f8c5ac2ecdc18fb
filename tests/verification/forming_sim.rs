//! Physics self-checks of the forming solver on the default Woo-like deep draw
//! (forming.md): volume, punch-force equilibrium, step/mesh refinement, penetration vs δ for
//! the exact `condensed` rule and for the paper's literal Eq. 28, and the Fig. 7 comparison.
//!
//! The default runs are computed once per test binary and shared.

use penalty_lab::forming::{ContactRule, FormingConfig, Simulation};
use penalty_lab::study::forming_runs::record::SavedRuns;
use penalty_lab::study::forming_runs::{self, ExperimentConfig};
use std::sync::OnceLock;

const DELTA: f64 = 1e-5;

fn default_runs() -> &'static SavedRuns {
    static RUNS: OnceLock<SavedRuns> = OnceLock::new();
    RUNS.get_or_init(|| {
        let cfg = ExperimentConfig::paper_knobs(FormingConfig::woo_deep_drawing());
        forming_runs::run(
            &penalty_lab::provenance::Provenance::new("deep_drawing"),
            &cfg,
        )
        .expect("default deep draw runs")
    })
}

#[test]
fn volume_is_conserved_to_half_a_percent() {
    for (name, run) in &default_runs().runs {
        let cfg = FormingConfig::woo_deep_drawing();
        let v0 = std::f64::consts::PI * cfg.blank_radius.powi(2) * cfg.thickness;
        let worst = run
            .steps
            .iter()
            .map(|s| (s.volume - v0).abs() / v0)
            .fold(0.0, f64::max);
        assert!(worst < 5e-3, "{name}: volume error {worst:.3e}");
    }
}

#[test]
fn punch_force_equals_the_summed_punch_reactions_from_equilibrium() {
    // Independent path: element internal forces K_mat v (+ drag − loads) at the punch nodes.
    for rule in [
        ContactRule::Condensed { delta: DELTA },
        ContactRule::Classical { eps: 1e7 },
    ] {
        let mut cfg = FormingConfig::woo_deep_drawing();
        cfg.travel = 0.3;
        cfg.steps = 30;
        let mut sim = Simulation::new(&cfg, rule).unwrap();
        let mut fmax = 0.0f64;
        for _ in 0..cfg.steps {
            let rec = sim.step().unwrap();
            let eq = sim.equilibrium_punch_force().unwrap();
            fmax = fmax.max(rec.punch_force.abs());
            // Classical ε = 1e7 leaves cond ~1e9–1e10: allow rounding at that level.
            let tol = 1e-6 * fmax.max(1e-3);
            assert!(
                (rec.punch_force - eq).abs() <= tol,
                "{rule:?} step {}: reported {} vs equilibrium {}",
                rec.step,
                rec.punch_force,
                eq
            );
            assert!(rec.punch_force > 0.0, "step {}: punch must push", rec.step);
        }
    }
}

#[test]
fn halving_the_step_and_doubling_the_elements_change_the_final_punch_force_by_under_5_percent() {
    let rule = ContactRule::Condensed { delta: DELTA };
    let base = FormingConfig::woo_deep_drawing();
    let f = |c: &FormingConfig| {
        Simulation::run(c, rule)
            .unwrap()
            .steps
            .last()
            .unwrap()
            .punch_force
    };
    let f0 = default_runs().runs["condensed"]
        .steps
        .last()
        .unwrap()
        .punch_force;
    let mut half = base.clone();
    half.steps *= 2;
    let mut fine = base.clone();
    fine.elements *= 2;
    let (fh, ff) = rayon::join(|| f(&half), || f(&fine));
    for (what, x) in [("half step", fh), ("double elements", ff)] {
        let rel = (x - f0).abs() / f0;
        assert!(rel < 0.05, "{what}: {x} vs {f0} ({rel:.3})");
    }
}

#[test]
fn condensed_penetration_is_at_most_delta_at_converged_steps() {
    let run = &default_runs().runs["condensed"];
    let converged: Vec<_> = run.steps.iter().filter(|s| s.converged).collect();
    assert!(
        converged.len() * 10 >= run.steps.len() * 8,
        "only {}/{} steps converged",
        converged.len(),
        run.steps.len()
    );
    for s in converged {
        assert!(
            s.max_penetration <= DELTA * (1.0 + 1e-6),
            "step {}: penetration {:.3e} > δ",
            s.step,
            s.max_penetration
        );
        assert!(s.clipped == 0);
    }
}

#[test]
fn literal_eq28_exceeds_delta_on_the_draw_and_says_so() {
    // What is true for the literal Eq. 28 (forming.md warns about it): the penetration is not
    // bounded by δ — at stationary-tool nodes ε comes out ≤ 0 and is clipped (reported per step
    // in `clipped`), and Eq. 28 ignores the coupling of the contact DOFs. Documented in
    // figures/deep_drawing/README.md; if this test starts failing, update that README.
    let run = &default_runs().runs["paper-literal"];
    assert_eq!(run.rule, ContactRule::PaperLiteral { delta: DELTA });
    let worst = run
        .steps
        .iter()
        .map(|s| s.max_penetration)
        .fold(0.0, f64::max);
    let clipped: usize = run.steps.iter().map(|s| s.clipped).sum();
    assert!(worst > 10.0 * DELTA, "max penetration {worst:.3e}");
    assert!(clipped > 0, "Eq. 28 never produced a negative penalty");
}

#[test]
fn fig7_adaptive_conditioning_is_better_than_classical_in_almost_every_step() {
    // The paper: better "in all but one increment". We check ≥ 95 % of the steps (the
    // measured count is reported in figures/deep_drawing/README.md).
    let r = &default_runs().runs;
    for name in ["adaptive", "condensed"] {
        let better = r[name]
            .steps
            .iter()
            .zip(&r["classical"].steps)
            .filter(|(a, c)| a.cond2 < c.cond2)
            .count();
        let n = r["classical"].steps.len();
        assert!(
            better * 100 >= n * 95,
            "{name}: better in {better}/{n} steps"
        );
    }
}
