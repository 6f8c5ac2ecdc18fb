//! The stretching test's `--json` summary: cond₂ of each run at the representative step and
//! its median, beside the paper's two printed values.

use super::super::forming_runs::{self, record::SavedRuns};
use serde_json::{json, Value};

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
        "cond2_classical_matched": at_last(forming_runs::CLASSICAL_MATCHED),
        "median_cond2_classical": median("classical"),
        "median_cond2_adaptive": median("adaptive"),
        "median_cond2_condensed": median("condensed"),
        "median_cond2_classical_matched": median(forming_runs::CLASSICAL_MATCHED),
        "comparisons": forming_runs::comparisons(doc),
        "paper": {"cond2_classical": PAPER_COND2.0, "cond2_adaptive": PAPER_COND2.1},
        "valid": doc.valid,
        "invalid_reasons": doc.invalid_reasons,
        "runs": doc.runs,
        "provenance": doc.provenance,
    })
}
