//! The paper's first example, the `stretch_test` binary's study (classical ε = 1e7: cond
//! 2.705e5, modified δ = 1e-5 in: cond 3.721e2; its geometry figure is lost), rebuilt as the
//! clamped hemispherical-punch stretching test with published geometry (Ghosh–Hecker,
//! forming.md), in inches: clamp radius 2.330 in, punch radius 2.0 in, die profile radius
//! 0.25 in, the paper's sheet t = 0.035 in, μ = 0.2, 50 elements, 100 steps to 0.8 in. Runs,
//! records, figures and the table report through [`forming_runs`](super::forming_runs) (its
//! `record.rs`, `figures.rs`, `report.rs`); its own `--json` summary is in `report.rs`.

use super::forming_runs::{record::SavedRuns, Experiment, Forming, FormingExperiment};
use crate::forming::FormingConfig;
use serde_json::Value;

mod report;
pub use report::{json_summary, PAPER_COND2};

/// The experiment: its name (JSON file stem), title, condition figure and configuration.
pub const EXPERIMENT: Experiment = Experiment {
    name: "stretch_test",
    title: "Stretching test",
    cond_figure: "condition_per_step",
    about: "Clamped hemispherical-punch stretching (paper's first example): classical vs adaptive penalty",
    preset: FormingConfig::ghosh_hecker_stretching,
    out: "results/stretch_test",
};

/// The stretching test as a forming experiment (`--json` prints [`json_summary`]).
pub struct Stretching;

impl FormingExperiment for Stretching {
    const EXPERIMENT: Experiment = EXPERIMENT;
    fn json(doc: &SavedRuns) -> Value {
        json_summary(doc)
    }
}

/// The `stretch_test` study.
pub type StretchTest = Forming<Stretching>;
