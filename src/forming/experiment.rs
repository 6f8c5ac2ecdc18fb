//! The two experiments of issue 4 as library functions (the binaries only parse flags):
//! the same configuration run with the classical penalty (ε), the paper's Eq. 28–29 (δ) —
//! the "modified approach" of Fig. 7, named `adaptive` — and the exact `condensed` rule (δ).
//! The three runs are independent and run in parallel (rayon).

use super::config::{ContactRule, FormingConfig};
use super::report::{git_commit, SavedRun, SavedRuns};
use super::solver::Simulation;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

/// An experiment: the forming configuration and the two contact knobs.
///
/// TOML: `penalty = 1e7`, `delta = 1e-5`, and a `[forming]` table with any fields of
/// [`FormingConfig`] (missing ones take the experiment's preset).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentConfig {
    /// Classical penalty ε (ton-force·s/in).
    pub penalty: f64,
    /// Allowed penetration δ (in) of the adaptive runs.
    pub delta: f64,
    /// Also run the exact `condensed` rule.
    #[serde(default = "yes")]
    pub condensed: bool,
    /// The forming configuration.
    pub forming: FormingConfig,
}

fn yes() -> bool {
    true
}

impl ExperimentConfig {
    /// ε = 1e7, δ = 1e-5 in (the paper's values) on `forming`.
    pub fn paper_knobs(forming: FormingConfig) -> Self {
        ExperimentConfig {
            penalty: 1e7,
            delta: 1e-5,
            condensed: true,
            forming,
        }
    }

    /// Reads a TOML file; the `[forming]` table is merged over `preset`.
    pub fn from_toml_file(path: &std::path::Path, preset: FormingConfig) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
        let one_line = |e: toml::de::Error| {
            Error::input(format!(
                "{}: {}",
                path.display(),
                e.to_string().replace('\n', " ")
            ))
        };
        let mut value: toml::Table = toml::from_str(&text).map_err(one_line)?;
        // Merge [forming] over the preset.
        let preset_toml = toml::Table::try_from(&preset)
            .map_err(|e| Error::Numerical(format!("cannot encode preset: {e}")))?;
        let mut forming = preset_toml;
        if let Some(v) = value.remove("forming") {
            match v {
                toml::Value::Table(t) => {
                    for (k, v) in t {
                        forming.insert(k, v);
                    }
                }
                _ => {
                    return Err(Error::input(format!(
                        "{}: [forming] must be a table",
                        path.display()
                    )))
                }
            }
        }
        value.insert("forming".into(), toml::Value::Table(forming));
        value.entry("penalty").or_insert(toml::Value::Float(1e7));
        value.entry("delta").or_insert(toml::Value::Float(1e-5));
        let c: ExperimentConfig = value.try_into().map_err(one_line)?;
        c.validate()?;
        Ok(c)
    }

    /// Checks ε, δ and the forming configuration.
    pub fn validate(&self) -> Result<()> {
        ContactRule::Classical { eps: self.penalty }.validate()?;
        ContactRule::Paper { delta: self.delta }.validate()?;
        self.forming.validate()
    }

    /// The runs: `classical`, `adaptive` (Eq. 28–29) and, if enabled, `condensed`.
    pub fn rules(&self) -> Vec<(String, ContactRule)> {
        let mut v = vec![
            (
                "classical".to_string(),
                ContactRule::Classical { eps: self.penalty },
            ),
            (
                "adaptive".to_string(),
                ContactRule::Paper { delta: self.delta },
            ),
        ];
        if self.condensed {
            v.push((
                "condensed".to_string(),
                ContactRule::Condensed { delta: self.delta },
            ));
        }
        v
    }
}

/// Runs every rule of `cfg` (in parallel) and assembles the saved document.
pub fn run(experiment: &str, cfg: &ExperimentConfig, command: &str) -> Result<SavedRuns> {
    cfg.validate()?;
    let t0 = Instant::now();
    let rules = cfg.rules();
    let results: Vec<Result<(String, SavedRun)>> = {
        use rayon::prelude::*;
        rules
            .par_iter()
            .map(|(name, rule)| {
                let r = Simulation::run(&cfg.forming, *rule).map_err(|e| match e {
                    Error::Input(m) => Error::Input(m),
                    e => Error::Numerical(format!("{name} run: {e}")),
                })?;
                Ok((name.clone(), SavedRun::from(&r)))
            })
            .collect()
    };
    let mut runs = BTreeMap::new();
    for r in results {
        let (k, v) = r?;
        runs.insert(k, v);
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu: BTreeMap<String, f64> = runs.iter().map(|(k, v)| (k.clone(), v.seconds)).collect();
    let provenance = serde_json::json!({
        "git_commit": git_commit(),
        "command": command,
        "crate_version": env!("CARGO_PKG_VERSION"),
        "threads": rayon::current_num_threads(),
        "wall_seconds": wall,
        "run_seconds": cpu,
        "units": "inch, ton-force, second",
        "penalty": cfg.penalty,
        "delta": cfg.delta,
    });
    Ok(SavedRuns {
        experiment: experiment.to_string(),
        provenance,
        config: cfg.forming.clone(),
        runs,
    })
}
