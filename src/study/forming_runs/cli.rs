//! The `deep_drawing` and `stretch_test` binaries' flags and the study as the shared entry
//! runs it ([`crate::study::shape::main`]): [`Forming`] of an [`Experiment`].

use super::record::{self, SavedRuns};
use super::{figures, report, run_with, ExperimentConfig, Overrides};
use crate::error::{Error, Result};
use crate::forming::FormingConfig;
use crate::study::shape::{Drawing, RunContext, Study};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

/// The command line shared by `deep_drawing` and `stretch_test` .
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Flags {
    /// Number of elements (default 50).
    #[arg(long)]
    pub elements: Option<usize>,
    /// Number of time steps (default 100).
    #[arg(long)]
    pub steps: Option<usize>,
    /// Punch travel in inches (default: the experiment's, given below).
    #[arg(long, allow_negative_numbers = true)]
    pub travel: Option<f64>,
    /// Coulomb friction coefficient (default 0.2).
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// Classical penalty ε in ton-force·s/in (default 1e7).
    #[arg(long, allow_negative_numbers = true)]
    pub penalty: Option<f64>,
    /// Allowed penetration δ in inches for the adaptive runs (default 1e-5).
    #[arg(long, allow_negative_numbers = true)]
    pub delta: Option<f64>,
    /// TOML file: `penalty`, `delta`, `condensed`, `paper_literal`, and a `[forming]` table;
    /// flags override it.
    #[arg(long, value_name = "FILE.toml")]
    pub config: Option<PathBuf>,
    /// Complete (status 0) a run that left the model's domain, with `"valid": false` and the
    /// reasons in the JSON, the CSV files and the figure titles (without it: status 3).
    #[arg(long)]
    pub allow_invalid: bool,
}

/// The exit statuses of the experiment binaries, for their `--help`.
pub const EXIT_STATUSES: &str = "Exit status: 0 ok; 2 bad input or a failed run; 3 the run left \
     the model's domain (blank drawn off the holder or through the die, a node through a tool, \
     volume drift > 1 %, a step longer than half an element, Picard unconverged in > 5 % of the \
     steps; the paper-literal run is a diagnostic whose own validity is reported per run): one \
     line on stderr names the reasons, and nothing is written; --allow-invalid completes such \
     a run with \"valid\": false.";

/// What an experiment binary passes besides its flags.
#[derive(Clone, Copy, Debug)]
pub struct Experiment {
    /// Name: the JSON file stem and `experiment` field (`deep_drawing`, `stretch_test`).
    pub name: &'static str,
    /// Figure title prefix.
    pub title: &'static str,
    /// File stem of the cond-per-step figure (`fig7_condition_per_step` for the deep draw).
    pub cond_figure: &'static str,
    /// The preset the TOML file and flags modify.
    pub preset: fn() -> FormingConfig,
    /// One line for `--help`.
    pub about: &'static str,
    /// `--out`'s default.
    pub out: &'static str,
}

impl Flags {
    /// The experiment configuration: the TOML file (or the paper's knobs) on the preset, then
    /// the flags; validated.
    pub fn config(&self, preset: FormingConfig) -> Result<ExperimentConfig> {
        let (c, text) = match &self.config {
            Some(p) => {
                let (c, text) = ExperimentConfig::from_toml_file(p, preset)?;
                (c, Some(text))
            }
            None => (ExperimentConfig::paper_knobs(preset), None),
        };
        c.apply(&Overrides {
            elements: self.elements,
            steps: self.steps,
            travel: self.travel,
            friction: self.friction,
            penalty: self.penalty,
            delta: self.delta,
        })
        .map_err(|e| self.placed(e, text.as_deref()))
    }

    /// A validation error of the configuration placed where its value came from: the flag
    /// that set it, else the file's key (`penalty`, `delta` at the top level, the others in
    /// `[forming]`, `punch.radius` in `[forming.punch]`) and line, else as it is (a default,
    /// or a condition between two fields).
    fn placed(&self, e: Error, text: Option<&str>) -> Error {
        let Some(token) = e.quantity().and_then(|q| q.split_whitespace().next()) else {
            return e;
        };
        let path = match token {
            "penalty" => "penalty",
            "δ" => "delta",
            t => t,
        }
        .to_string();
        let flag = match path.as_str() {
            "elements" => self.elements.map(|_| "--elements"),
            "steps" => self.steps.map(|_| "--steps"),
            "travel" => self.travel.map(|_| "--travel"),
            "friction" => self.friction.map(|_| "--friction"),
            "penalty" => self.penalty.map(|_| "--penalty"),
            "delta" => self.delta.map(|_| "--delta"),
            _ => None,
        };
        if let Some(flag) = flag {
            return e.for_flag(flag);
        }
        let (Some(file), Some(text)) = (&self.config, text) else {
            return e;
        };
        let (table, key) = match (path.as_str(), path.rsplit_once('.')) {
            ("penalty" | "delta", _) => (None, path.as_str()),
            (_, Some((table, key))) => (Some(format!("forming.{table}")), key),
            (key, None) => (Some("forming".to_string()), key),
        };
        crate::provenance::in_toml_file(e, file, text, table.as_deref(), key)
    }
}

/// One forming experiment: what it declares and what `--json` prints.
pub trait FormingExperiment {
    /// The experiment.
    const EXPERIMENT: Experiment;
    /// What `--json` prints: the whole document by default.
    fn json(doc: &SavedRuns) -> serde_json::Value {
        serde_json::to_value(doc).unwrap_or(serde_json::Value::Null)
    }
}

/// The study of the forming experiment `E` (`--out DIR` gets `<name>.json`, `steps_<run>.csv`
/// and the figures; a run outside the model's domain is an error unless `--allow-invalid`).
pub struct Forming<E>(PhantomData<E>);

impl<E: FormingExperiment> Study for Forming<E> {
    const NAME: &'static str = E::EXPERIMENT.name;
    const ABOUT: &'static str = E::EXPERIMENT.about;
    const PROGRESS: &'static str = E::EXPERIMENT.name;
    const DEFAULT_OUT: &'static str = E::EXPERIMENT.out;
    const FIGURES_DIR: &'static str = "";
    type Flags = Flags;
    type Config = (ExperimentConfig, bool);
    type Record = SavedRuns;

    fn after_help() -> String {
        format!(
            "Default travel {:.1} in. Units: inch, ton-force, second. {EXIT_STATUSES}",
            (E::EXPERIMENT.preset)().travel
        )
    }

    fn config(flags: &Flags) -> Result<(ExperimentConfig, bool)> {
        Ok((flags.config((E::EXPERIMENT.preset)())?, flags.allow_invalid))
    }

    fn run(cfg: &(ExperimentConfig, bool), ctx: &RunContext) -> Result<SavedRuns> {
        let (cfg, allow_invalid) = (&cfg.0, cfg.1);
        let doc = run_with(ctx.provenance, cfg, allow_invalid)?;
        if !doc.valid && !allow_invalid {
            return Err(Error::OutsideModel(format!(
                "{} (rerun with --allow-invalid to keep the outputs)",
                doc.invalid_reasons.join("; ")
            )));
        }
        Ok(doc)
    }

    fn save(
        out: &Path,
        _cfg: &(ExperimentConfig, bool),
        doc: &SavedRuns,
        _provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        record::save(out, E::EXPERIMENT.name, doc).map(|_| ())
    }

    fn load(out: &Path) -> Result<SavedRuns> {
        record::load(&out.join(format!("{}.json", E::EXPERIMENT.name)))
    }

    fn figures(doc: &SavedRuns) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(
            doc,
            E::EXPERIMENT.title,
            E::EXPERIMENT.cond_figure,
        ))
    }

    fn report(doc: &SavedRuns) -> String {
        report::summary_table(doc)
    }

    fn json(doc: &SavedRuns) -> Result<String> {
        crate::provenance::json_text(doc.experiment.as_str(), &E::json(doc))
    }
}
