//! The paper's second example, the `deep_drawing` binary's study: a Woo-like hemispherical-
//! punch deep draw (forming.md defaults) with the classical penalty (ε = 1e7), Eq. 28 on the
//! contact rows' residual (`adaptive`, δ = 1e-5 in), Eq. 28–29 as printed (`paper-literal`, a
//! diagnostic) and the exact `condensed` rule — the paper's Fig. 7. Runs, records, figures
//! and report through [`forming_runs`](super::forming_runs) (its `record.rs`, `figures.rs`,
//! `report.rs`).

use super::forming_runs::{Experiment, Forming, FormingExperiment};
use crate::forming::FormingConfig;

/// The experiment: its name (JSON file stem), title, condition figure and configuration.
pub const EXPERIMENT: Experiment = Experiment {
    name: "deep_drawing",
    title: "Deep drawing",
    cond_figure: "fig7_condition_per_step",
    about: "Woo-like hemispherical-punch deep draw: classical vs adaptive penalty (paper Fig. 7)",
    preset: FormingConfig::woo_deep_drawing,
    out: "results/deep_drawing",
};

/// The deep draw as a forming experiment (`--json` prints the whole document).
pub struct DeepDraw;

impl FormingExperiment for DeepDraw {
    const EXPERIMENT: Experiment = EXPERIMENT;
}

/// The `deep_drawing` study.
pub type DeepDrawing = Forming<DeepDraw>;
