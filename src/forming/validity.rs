//! Validity guards: does a finished run stay inside the domain of its model?
//!
//! The model (flat blank on a die flat under a holder, explicit geometry update, Picard per
//! step) stops describing the process when:
//! * the blank rim leaves the die flat (**drawn off the holder**: the holder loads and the
//!   flange friction act only there) or passes the die opening (**drawn through the die**);
//! * a node ends **through a tool** by more than half the thickness (geometric penetration);
//! * the sheet volume drifts by more than [`MAX_VOLUME_DRIFT`] (incompressibility is violated
//!   by the explicit update, forming.md asks for well under 1 %);
//! * a step's punch travel exceeds [`MAX_STEP_FRACTION`] of an initial element length (the
//!   contact candidates and the explicit update assume small steps);
//! * Picard stopped at its cap in more than [`MAX_UNCONVERGED_FRACTION`] of the steps.
//!
//! [`check_config`] and [`check`] return the reasons (empty = valid). The experiment binaries exit with status 3
//! on a non-empty list unless `--allow-invalid` is given; then the outputs carry
//! `"valid": false` and the reasons.

use super::config::FormingConfig;
use super::solver::StepRecord;

/// Largest relative volume drift `|V − V₀|/V₀` of a valid run.
pub const MAX_VOLUME_DRIFT: f64 = 0.01;
/// Largest punch travel per step, as a fraction of the initial element length.
pub const MAX_STEP_FRACTION: f64 = 0.5;
/// Largest fraction of steps whose Picard iteration stopped at the cap.
pub const MAX_UNCONVERGED_FRACTION: f64 = 0.05;
/// Largest geometric penetration of a node into a tool, as a fraction of the thickness.
pub const MAX_GEOMETRIC_PENETRATION: f64 = 0.5;

/// `x ≤ limit`, false for NaN (a NaN value is never within a limit).
fn at_most(x: f64, limit: f64) -> bool {
    x.partial_cmp(&limit).is_some_and(|o| o.is_le())
}

/// The reasons why a configuration is outside the model's domain before it runs: a step
/// longer than [`MAX_STEP_FRACTION`] of an initial element.
pub fn check_config(cfg: &FormingConfig) -> Vec<String> {
    let h = cfg.blank_radius / cfg.elements as f64;
    let step = cfg.travel / cfg.steps as f64;
    if step > MAX_STEP_FRACTION * h {
        vec![format!(
            "a step of {step:.3e} in punch travel is longer than {MAX_STEP_FRACTION} of an \
             element ({h:.3e} in)"
        )]
    } else {
        Vec::new()
    }
}

/// The reasons why the run `name` (configuration `cfg`, telemetry `steps`) left the model's
/// domain; empty if it did not. Each reason is one short sentence naming the run, the
/// quantity, its value and the limit.
pub fn check(name: &str, cfg: &FormingConfig, steps: &[StepRecord]) -> Vec<String> {
    let mut out = Vec::new();
    let unconverged = steps.iter().filter(|s| !s.converged).count();
    if unconverged as f64 > MAX_UNCONVERGED_FRACTION * steps.len() as f64 {
        out.push(format!(
            "{name}: Picard unconverged in {unconverged}/{} steps (limit {:.0} %)",
            steps.len(),
            100.0 * MAX_UNCONVERGED_FRACTION
        ));
    }
    let v0 = std::f64::consts::PI * cfg.blank_radius.powi(2) * cfg.thickness;
    if let Some(s) = steps
        .iter()
        .find(|s| !at_most((s.volume - v0).abs(), MAX_VOLUME_DRIFT * v0))
    {
        out.push(format!(
            "{name}: volume drift {:.2} % at step {} (limit {:.0} %)",
            100.0 * (s.volume - v0) / v0,
            s.step,
            100.0 * MAX_VOLUME_DRIFT
        ));
    }
    if !cfg.clamped_rim {
        let flat = cfg.die.opening_radius + cfg.die.profile_radius;
        if let Some(s) = steps.iter().find(|s| !at_most(flat, s.rim_r)) {
            let what = if s.rim_r < cfg.die.opening_radius {
                "drawn through the die"
            } else {
                "drawn off the holder"
            };
            out.push(format!(
                "{name}: blank {what} at step {} (rim radius {:.4} in < die flat from {flat:.4} \
                 in)",
                s.step, s.rim_r
            ));
        }
    }
    let pen_limit = MAX_GEOMETRIC_PENETRATION * cfg.thickness;
    if let Some(s) = steps
        .iter()
        .find(|s| !at_most(s.geometric_penetration, pen_limit))
    {
        out.push(format!(
            "{name}: a node went through a tool at step {} (geometric penetration {:.3e} in > \
             {pen_limit:.3e} in)",
            s.step, s.geometric_penetration
        ));
    }
    if let Some(s) = steps.iter().find(|s| !s.punch_force.is_finite()) {
        out.push(format!("{name}: non-finite punch force at step {}", s.step));
    }
    out
}
