//! The paper's first example, the `stretch_test` binary's study (classical ε = 1e7: cond
//! 2.705e5, modified δ = 1e-5 in: cond 3.721e2; its geometry figure is lost), rebuilt as the
//! clamped hemispherical-punch stretching test with published geometry (Ghosh–Hecker,
//! forming.md), in inches: clamp radius 2.330 in, punch radius 2.0 in, die profile radius
//! 0.25 in, the paper's sheet t = 0.035 in, μ = 0.2, 50 elements, 100 steps to 0.8 in. Runs,
//! records, figures and report through [`forming_runs`](super::forming_runs) (its `record.rs`,
//! `figures.rs`, `report.rs`).

use super::forming_runs::{record::SavedRuns, Experiment, Forming, FormingExperiment};
use crate::forming::FormingConfig;
use serde_json::{json, Value};

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

/// The paper's two printed condition numbers of this example.
pub const PAPER_COND2: (f64, f64) = (2.705008e5, 3.721074e2);

/// The `--json` summary: cond₂ of the classical, adaptive and condensed runs at the
/// **representative step = the last step (full punch travel)**, their medians over all
/// steps, the paper's values, validity and every run's per-step series.
pub fn json_summary(doc: &SavedRuns) -> Value {
    let at_last = |name: &str| {
        doc.runs
            .get(name)
            .and_then(|r| r.steps.last())
            .map(|s| s.cond2)
    };
    let median = |name: &str| {
        doc.runs.get(name).and_then(|r| {
            let c: Vec<f64> = r.steps.iter().map(|s| s.cond2).collect();
            crate::stats::median(&c)
        })
    };
    json!({
        "representative_step": doc.config.steps,
        "representative_step_note": "the last step (full punch travel)",
        "cond2_classical": at_last("classical"),
        "cond2_adaptive": at_last("adaptive"),
        "cond2_condensed": at_last("condensed"),
        "cond2_classical_matched": at_last(super::forming_runs::CLASSICAL_MATCHED),
        "median_cond2_classical": median("classical"),
        "median_cond2_adaptive": median("adaptive"),
        "median_cond2_condensed": median("condensed"),
        "median_cond2_classical_matched": median(super::forming_runs::CLASSICAL_MATCHED),
        "comparisons": super::forming_runs::comparisons(doc),
        "paper": {"cond2_classical": PAPER_COND2.0, "cond2_adaptive": PAPER_COND2.1},
        "valid": doc.valid,
        "invalid_reasons": doc.invalid_reasons,
        "runs": doc.runs,
        "provenance": doc.provenance,
    })
}
