//! The two forming experiments as library functions (the binaries only parse flags):
//! the same configuration run with the classical penalty (ε), the paper's Eq. 28–29 (δ) —
//! the "modified approach" of Fig. 7, named `adaptive` — and the exact `condensed` rule (δ).
//! The three runs are independent and run in parallel (rayon).

pub mod cli;
pub mod figures;
pub mod record;
pub mod report;

pub use cli::{Experiment, Forming, FormingExperiment, EXIT_STATUSES};
pub use report::{comparisons, summary_table, Comparison};

use crate::error::{Error, Result};
use crate::forming::config::{ContactRule, FormingConfig};
use crate::forming::solver::{RunResult, Simulation, StepRecord};
use crate::provenance::{toml_key_line, Provenance};
use record::{SavedRun, SavedRuns};
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
    /// Also run the literal reading of Eq. 28 (`paper-literal`).
    #[serde(default = "yes")]
    pub paper_literal: bool,
    /// Also run `classical-matched`: the constant ε whose largest penetration over the run
    /// lies in [δ/2, δ] ([`matched_penalty`]), so that the δ-rules are also compared with a
    /// classical penalty of the same accuracy.
    #[serde(default = "yes")]
    pub classical_matched: bool,
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
            paper_literal: true,
            classical_matched: true,
            forming,
        }
    }

    /// Reads a TOML file; the `[forming]` table is merged over `preset`. Not yet validated:
    /// the command line's flags override it first ([`ExperimentConfig::apply`] validates
    /// the result), so a flag can correct a value of the file. With the file's text, to place
    /// those errors in it.
    pub fn from_toml_file(path: &std::path::Path, preset: FormingConfig) -> Result<(Self, String)> {
        let (file, text): (toml::Table, String) = crate::provenance::read_toml_with_text(path)?;
        let preset_toml = toml::Table::try_from(&preset)
            .map_err(|e| Error::Numerical(format!("cannot encode preset: {e}")))?;
        let merged = Self::merged(&file, &preset_toml)
            .ok_or_else(|| Error::bad_file(path.display(), "[forming] must be a table"))?;
        let config = merged.try_into().map_err(|e: toml::de::Error| {
            // The typed conversion has no spans: the line of the first key of the file whose
            // value alone makes it fail.
            match Self::culprit(&file, &preset_toml)
                .and_then(|(table, key)| toml_key_line(&text, table.as_deref(), &key))
            {
                Some(line) => Error::parse(path.display(), line, e.message().replace('\n', " ")),
                None => Error::toml(path.display(), None, &e),
            }
        })?;
        Ok((config, text))
    }

    /// The file's table with its `[forming]` merged over the preset's and the default ε and
    /// δ where it has none; None where `forming` is not a table.
    fn merged(file: &toml::Table, preset: &toml::Table) -> Option<toml::Table> {
        let mut value = file.clone();
        let mut forming = preset.clone();
        if let Some(v) = value.remove("forming") {
            forming.extend(v.as_table()?.clone());
        }
        value.insert("forming".into(), toml::Value::Table(forming));
        value.entry("penalty").or_insert(toml::Value::Float(1e7));
        value.entry("delta").or_insert(toml::Value::Float(1e-5));
        Some(value)
    }

    /// The first key of the file (`(Some("forming"), key)` inside `[forming]`) without which
    /// the merged table converts.
    fn culprit(file: &toml::Table, preset: &toml::Table) -> Option<(Option<String>, String)> {
        let converts = |t: toml::Table| {
            Self::merged(&t, preset).is_some_and(|m| m.try_into::<ExperimentConfig>().is_ok())
        };
        // `[forming]`'s keys first, then the top level's.
        let forming = file.get("forming").and_then(|v| v.as_table());
        let in_forming = forming
            .into_iter()
            .flat_map(|t| t.keys())
            .map(|k| (true, k));
        let top = file.keys().filter(|k| *k != "forming").map(|k| (false, k));
        in_forming
            .chain(top)
            .find(|&(inner, k)| {
                let mut t = file.clone();
                let table = if inner {
                    t.get_mut("forming").and_then(|v| v.as_table_mut())
                } else {
                    Some(&mut t)
                };
                if let Some(table) = table {
                    table.remove(k);
                }
                converts(t)
            })
            .map(|(inner, k)| (inner.then(|| "forming".to_string()), k.clone()))
    }

    /// Checks ε, δ and the forming configuration.
    pub fn validate(&self) -> Result<()> {
        ContactRule::Classical { eps: self.penalty }.validate()?;
        ContactRule::Condensed { delta: self.delta }.validate()?;
        self.forming.validate()
    }

    /// The runs of fixed knobs: `classical`, `adaptive` (Eq. 28–29 on the current residual,
    /// [`ContactRule::PaperResidual`]) and, if enabled, `paper-literal`
    /// ([`ContactRule::PaperLiteral`]) and `condensed`. `classical-matched`, whose ε is
    /// searched for, is run by [`run_with`] after them.
    pub fn rules(&self) -> Vec<(String, ContactRule)> {
        let mut v = vec![
            (
                "classical".to_string(),
                ContactRule::Classical { eps: self.penalty },
            ),
            (
                "adaptive".to_string(),
                ContactRule::PaperResidual { delta: self.delta },
            ),
        ];
        if self.paper_literal {
            v.push((
                "paper-literal".to_string(),
                ContactRule::PaperLiteral { delta: self.delta },
            ));
        }
        if self.condensed {
            let rule = ContactRule::Condensed { delta: self.delta };
            v.push((rule.name().to_string(), rule));
        }
        v
    }
}

/// Command-line overrides shared by the experiment binaries (`None` = keep).
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    /// Number of elements.
    pub elements: Option<usize>,
    /// Number of steps.
    pub steps: Option<usize>,
    /// Punch travel (in); the snapshots move to 25/50/75/100 % of it.
    pub travel: Option<f64>,
    /// Friction coefficient.
    pub friction: Option<f64>,
    /// Classical penalty ε.
    pub penalty: Option<f64>,
    /// Allowed penetration δ (in).
    pub delta: Option<f64>,
}

impl ExperimentConfig {
    /// Applies the overrides and validates the result.
    pub fn apply(mut self, o: &Overrides) -> Result<Self> {
        if let Some(v) = o.elements {
            self.forming.elements = v;
        }
        if let Some(v) = o.steps {
            self.forming.steps = v;
        }
        if let Some(v) = o.travel {
            self.forming.travel = v;
            self.forming.snapshots = [0.25, 0.5, 0.75, 1.0].iter().map(|f| f * v).collect();
        }
        if let Some(v) = o.friction {
            self.forming.friction = v;
        }
        if let Some(v) = o.penalty {
            self.penalty = v;
        }
        if let Some(v) = o.delta {
            self.delta = v;
        }
        self.validate()?;
        Ok(self)
    }
}

/// The name of the classical run matched to δ.
pub const CLASSICAL_MATCHED: &str = "classical-matched";

/// Most trial runs of [`matched_penalty`]'s search.
pub const MATCH_TRIALS: usize = 12;

/// The largest penetration of a run, `max_steps max_c p_c·Δt` (in): what δ bounds.
pub fn largest_penetration(steps: &[StepRecord]) -> f64 {
    steps
        .iter()
        .map(|s| s.max_penetration)
        .filter(|p| p.is_finite())
        .fold(0.0, f64::max)
}

/// What [`matched_penalty`] found.
pub struct Matched {
    /// The constant ε.
    pub eps: f64,
    /// Its run.
    pub run: RunResult,
    /// The run's numerical failure, if it had one.
    pub failure: Option<Error>,
    /// Why no trial landed in [δ/2, δ] (the nearest one is returned), if none did.
    pub unmatched: Option<String>,
    /// What the search cost (every trial run, this one included).
    pub search: record::MatchSearch,
}

/// The constant ε of `classical-matched` and its run: a classical penalty whose largest
/// penetration over the run lies in [δ/2, δ].
///
/// The search starts from the `classical` run (ε₀, largest penetration p₀) and aims at
/// 0.75 δ, the middle of the interval: a penalty carries the contact force as ε·g, so the
/// penetration goes as 1/ε and the first step is `ε₁ = ε₀·p₀/(0.75 δ)`; later steps are
/// secant steps in log ε – log p (slope clamped to [−3, −1/3]), at most [`MATCH_TRIALS`] runs.
/// If none lands in [δ/2, δ] the trial nearest 0.75 δ (in log p) is returned with the reason
/// (the run is then marked invalid).
pub fn matched_penalty(cfg: &ExperimentConfig, classical: &RunResult) -> Result<Matched> {
    let (lo, hi, target) = (0.5 * cfg.delta, cfg.delta, 0.75 * cfg.delta);
    let mut trials: Vec<(f64, f64)> = Vec::new();
    let mut eps = cfg.penalty;
    let mut pen = largest_penetration(&classical.steps);
    let mut best: Option<(f64, RunResult, Option<Error>, f64)> = None;
    let mut cost = record::MatchSearch {
        runs: 0,
        factorizations: 0,
        seconds: 0.0,
    };
    for _ in 0..MATCH_TRIALS {
        if !(pen > 0.0 && pen.is_finite()) {
            break;
        }
        trials.push((eps.ln(), pen.ln()));
        let slope = match trials[..] {
            [.., (e0, p0), (e1, p1)] if e1 != e0 => ((p1 - p0) / (e1 - e0)).clamp(-3.0, -1.0 / 3.0),
            _ => -1.0,
        };
        eps = (eps.ln() + (target.ln() - pen.ln()) / slope).exp();
        let (run, failure) =
            Simulation::run_until_failure(&cfg.forming, ContactRule::Classical { eps })?;
        cost.runs += 1;
        cost.factorizations += run.steps.iter().map(|s| s.factorizations).sum::<usize>();
        cost.seconds += run.seconds;
        pen = largest_penetration(&run.steps);
        let miss = (pen.ln() - target.ln()).abs();
        let done = failure.is_none() && run.steps.len() == cfg.forming.steps;
        if done && (lo..=hi).contains(&pen) {
            return Ok(Matched {
                eps,
                run,
                failure,
                unmatched: None,
                search: cost,
            });
        }
        if done && best.as_ref().is_none_or(|b| miss < b.3) {
            best = Some((eps, run, failure, miss));
        }
    }
    match best {
        Some((eps, run, failure, _)) => {
            let p = largest_penetration(&run.steps);
            let why = format!(
                "{CLASSICAL_MATCHED}: no ε in {MATCH_TRIALS} trials put the largest penetration in \
                 [δ/2, δ] = [{lo:e}, {hi:e}] in; nearest ε = {eps:e} gives {p:e} in"
            );
            Ok(Matched {
                eps,
                run,
                failure,
                unmatched: Some(why),
                search: cost,
            })
        }
        None => Err(Error::Numerical(format!(
            "{CLASSICAL_MATCHED}: no complete classical run in the ε search (from ε = {:e})",
            cfg.penalty
        ))),
    }
}

/// Runs every rule of `cfg` (in parallel) and assembles the saved document, with the
/// validity guards ([`crate::forming::validity`]) applied per run and to the document (every run but
/// the diagnostic `paper-literal` one, see [`diagnostic_only`]). A run that fails numerically keeps the steps
/// it did: the failure is one of the document's invalid reasons if the configuration or the
/// steps done already left the model's domain (or the caller allows invalid runs,
/// `keep_failed`), and an error (exit status 2) otherwise.
/// The document records `provenance` (its experiment names the document).
pub fn run(provenance: &Provenance, cfg: &ExperimentConfig) -> Result<SavedRuns> {
    run_with(provenance, cfg, false)
}

/// Is a run of this rule a diagnostic only (its validity is reported per run and does not
/// decide the document's)? The literal reading of Eq. 28 is kept to show how it fails:
/// its Picard loop stalls in most steps of the draw by design of the comparison.
pub fn diagnostic_only(rule: &ContactRule) -> bool {
    matches!(rule, ContactRule::PaperLiteral { .. })
}

/// [`run`], keeping the runs that failed numerically as invalid when `keep_failed`.
pub fn run_with(
    provenance: &Provenance,
    cfg: &ExperimentConfig,
    keep_failed: bool,
) -> Result<SavedRuns> {
    let experiment = provenance.experiment.as_str();
    cfg.validate()?;
    let t0 = Instant::now();
    let rules = cfg.rules();
    let mut classical = None;
    let mut results: Vec<Result<(String, SavedRun, Option<Error>)>> = {
        use rayon::prelude::*;
        let done: Vec<Result<(String, RunResult, Option<Error>)>> = rules
            .par_iter()
            .map(|(name, rule)| {
                let (r, failure) = Simulation::run_until_failure(&cfg.forming, *rule)?;
                Ok((name.clone(), r, failure))
            })
            .collect();
        done.into_iter()
            .map(|r| {
                r.map(|(name, run, failure)| {
                    let saved = SavedRun::from(&run);
                    if matches!(run.rule, ContactRule::Classical { .. }) {
                        classical = Some(run);
                    }
                    (name, saved, failure)
                })
            })
            .collect()
    };
    let mut unmatched = None;
    if let (true, Some(c)) = (cfg.classical_matched, &classical) {
        let m = matched_penalty(cfg, c)?;
        unmatched = m.unmatched;
        let mut saved = SavedRun::from(&m.run);
        saved.search = Some(m.search);
        results.push(Ok((CLASSICAL_MATCHED.to_string(), saved, m.failure)));
    }
    let mut runs = BTreeMap::new();
    let mut reasons = crate::forming::validity::check_config(&cfg.forming);
    let mut failures = Vec::new();
    for r in results {
        let (name, mut run, failure) = r?;
        let mut own = crate::forming::validity::check(&name, &cfg.forming, &run.steps);
        if name == CLASSICAL_MATCHED {
            own.extend(unmatched.take());
        }
        if let Some(e) = failure {
            let step = run.steps.len() + 1;
            let e = Error::Numerical(format!("{name} run, step {step}: {e}"));
            own.push(e.to_string());
            if !diagnostic_only(&run.rule) {
                failures.push(e);
            }
        }
        if !diagnostic_only(&run.rule) {
            reasons.extend(own.iter().cloned());
        }
        run.valid = own.is_empty();
        run.invalid_reasons = own;
        runs.insert(name, run);
    }
    // Numerical failures are already among the reasons (per run); they decide between an
    // invalid document and a failed run.
    reasons.retain(|r| !r.starts_with("numerical failure"));
    if let Some(first) = failures.first() {
        if reasons.is_empty() && !keep_failed {
            return Err(Error::Numerical(first.to_string()));
        }
        reasons.extend(failures.iter().map(|e| e.to_string()));
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu: BTreeMap<String, f64> = runs.iter().map(|(k, v)| (k.clone(), v.seconds)).collect();
    let provenance = provenance.record(serde_json::json!({
        "threads": rayon::current_num_threads(),
        "wall_seconds": wall,
        "run_seconds": cpu,
        "units": "inch, ton-force, second",
        "penalty": cfg.penalty,
        "delta": cfg.delta,
    }));
    Ok(SavedRuns {
        experiment: experiment.to_string(),
        provenance,
        config: cfg.forming.clone(),
        runs,
        valid: reasons.is_empty(),
        invalid_reasons: reasons,
    })
}
