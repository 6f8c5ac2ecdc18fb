//! The record of forming runs: the JSON document ([`SavedRuns`]) and the step tables (CSV).

use crate::error::{Error, Result};
use crate::forming::config::{ContactRule, FormingConfig};
use crate::forming::solver::{RunResult, Snapshot, StepRecord};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One run as saved in the JSON document.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SavedRun {
    /// Contact rule.
    pub rule: ContactRule,
    /// Penalty ε (classical only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub eps: Option<f64>,
    /// Allowed penetration δ (in; adaptive rules only).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub delta: Option<f64>,
    /// Largest penetration over the run, `max_steps max_c p_c·Δt` (in): what δ bounds
    /// ([`super::largest_penetration`]).
    #[serde(default)]
    pub largest_penetration: f64,
    /// Per-step telemetry.
    pub steps: Vec<StepRecord>,
    /// Sheet snapshots.
    pub snapshots: Vec<Snapshot>,
    /// Wall time (s).
    pub seconds: f64,
    /// This run stayed inside the model's domain ([`crate::forming::validity`]).
    #[serde(default = "valid_default")]
    pub valid: bool,
    /// Why not (empty when valid).
    #[serde(default)]
    pub invalid_reasons: Vec<String>,
    /// What finding this run's ε cost (`classical-matched` only): the search is an oracle a
    /// user without δ would pay for.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub search: Option<MatchSearch>,
}

/// The cost of [`super::matched_penalty`]'s search: every trial run, the returned one included.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct MatchSearch {
    /// Full forming runs made.
    pub runs: usize,
    /// Matrix factorizations over all their steps.
    pub factorizations: usize,
    /// Their wall time (s).
    pub seconds: f64,
}

impl From<&RunResult> for SavedRun {
    fn from(r: &RunResult) -> Self {
        SavedRun {
            rule: r.rule,
            eps: match r.rule {
                ContactRule::Classical { eps } => Some(eps),
                _ => None,
            },
            delta: r.rule.delta(),
            largest_penetration: super::largest_penetration(&r.steps),
            steps: r.steps.clone(),
            snapshots: r.snapshots.clone(),
            seconds: r.seconds,
            valid: true,
            invalid_reasons: Vec::new(),
            search: None,
        }
    }
}

/// The JSON document of an experiment: provenance, configuration, runs by name.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SavedRuns {
    /// Experiment name.
    pub experiment: String,
    /// Git commit, command line, wall time, …
    pub provenance: serde_json::Value,
    /// The configuration shared by the runs.
    pub config: FormingConfig,
    /// Runs by name (`classical`, `adaptive`, `paper-literal`, `condensed`).
    pub runs: BTreeMap<String, SavedRun>,
    /// Every run stayed inside the model's domain ([`crate::forming::validity`]).
    #[serde(default = "valid_default")]
    pub valid: bool,
    /// Why not (empty when valid).
    #[serde(default)]
    pub invalid_reasons: Vec<String>,
}

fn valid_default() -> bool {
    true
}

/// Writes one run's step table as CSV; a run outside the model's domain (`invalid` = its
/// reasons, non-empty) gets a first comment line `# valid: false; <reasons>`.
pub fn write_steps_csv(path: &Path, steps: &[StepRecord], invalid: &[String]) -> Result<()> {
    let mut file = std::fs::File::create(path).map_err(|e| Error::io(path.display(), e))?;
    if !invalid.is_empty() {
        use std::io::Write;
        writeln!(file, "# valid: false; {}", invalid.join("; "))
            .map_err(|e| Error::io(path.display(), e))?;
    }
    let mut w = csv::Writer::from_writer(file);
    w.write_record([
        "step",
        "punch_travel",
        "punch_force",
        "cond2",
        "log10_det",
        "cond2_k",
        "log10_det_ratio",
        "cond2_equilibrated",
        "cond2_k_equilibrated",
        "cond2_bounds_proven",
        "cond2_within_contract",
        "cond2_jacobi",
        "pcg_iters_jacobi",
        "pcg_converged_jacobi",
        "pcg_iters_ic0",
        "pcg_converged_ic0",
        "pcg_iters_jacobi_to_err",
        "pcg_iters_jacobi_to_err_converged",
        "pcg_iters_ic0_to_err",
        "pcg_iters_ic0_to_err_converged",
        "pcg_err_u_at_stop_jacobi",
        "pcg_err_u_at_stop_ic0",
        "forward_err_u",
        "max_penetration",
        "geometric_penetration",
        "volume",
        "rim_r",
        "iterations",
        "converged",
        "picard_change",
        "contact_nodes",
        "candidates",
        "clipped",
        "min_penalty",
        "max_penalty",
        "mu_ratio",
        "drag_force",
        "factorizations",
    ])
    .map_err(|e| Error::io(path.display(), e))?;
    for s in steps {
        w.write_record([
            s.step.to_string(),
            s.punch_travel.to_string(),
            s.punch_force.to_string(),
            s.cond2.to_string(),
            s.log10_det.to_string(),
            s.cond2_k.to_string(),
            s.log10_det_ratio.to_string(),
            s.cond2_equilibrated.to_string(),
            s.cond2_k_equilibrated.to_string(),
            s.cond2_bounds_proven.to_string(),
            s.cond2_within_contract.to_string(),
            s.cond2_jacobi.to_string(),
            opt(s.pcg_iters_jacobi),
            opt(s.pcg_converged_jacobi),
            opt(s.pcg_iters_ic0),
            opt(s.pcg_converged_ic0),
            opt(s.pcg_iters_jacobi_to_err),
            opt(s.pcg_iters_jacobi_to_err_converged),
            opt(s.pcg_iters_ic0_to_err),
            opt(s.pcg_iters_ic0_to_err_converged),
            opt(s.pcg_err_u_at_stop_jacobi),
            opt(s.pcg_err_u_at_stop_ic0),
            s.forward_err_u.to_string(),
            s.max_penetration.to_string(),
            s.geometric_penetration.to_string(),
            s.volume.to_string(),
            s.rim_r.to_string(),
            s.iterations.to_string(),
            s.converged.to_string(),
            s.picard_change.to_string(),
            s.contact_nodes.to_string(),
            s.candidates.to_string(),
            s.clipped.to_string(),
            s.min_penalty.to_string(),
            s.max_penalty.to_string(),
            s.mu_ratio.to_string(),
            s.drag_force.to_string(),
            s.factorizations.to_string(),
        ])
        .map_err(|e| Error::io(path.display(), e))?;
    }
    w.flush().map_err(|e| Error::io(path.display(), e))
}

/// An optional value as a CSV cell (empty for `None`).
fn opt<T: ToString>(v: Option<T>) -> String {
    v.map_or(String::new(), |x| x.to_string())
}

/// Writes `DIR/<stem>.json` and `DIR/steps_<run>.csv` for every run; returns the JSON path.
pub fn save(dir: &Path, stem: &str, doc: &SavedRuns) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir.display(), e))?;
    let json = dir.join(format!("{stem}.json"));
    let text = serde_json::to_string_pretty(doc)
        .map_err(|e| Error::Numerical(format!("cannot serialize results: {e}")))?;
    std::fs::write(&json, text).map_err(|e| Error::io(json.display(), e))?;
    for (name, run) in &doc.runs {
        let mut reasons = doc.invalid_reasons.clone();
        reasons.extend(
            run.invalid_reasons
                .iter()
                .filter(|r| !reasons.contains(r))
                .cloned()
                .collect::<Vec<_>>(),
        );
        write_steps_csv(&dir.join(format!("steps_{name}.csv")), &run.steps, &reasons)?;
    }
    Ok(json)
}

/// Reads a document written by [`save`].
pub fn load(json: &Path) -> Result<SavedRuns> {
    crate::provenance::read_json(json)
}
