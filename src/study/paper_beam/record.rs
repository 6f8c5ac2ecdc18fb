//! The record of the study (`paper_beam.json`) and its data files (`deflection.csv`,
//! `cond_vs_eps.csv`): types, writing and reading back.

use super::deflection::DeflectionRow;
use super::{Study, COND_DELTA_FILE, COND_FILE, DEFLECTION_FILE, JSON_FILE};
use crate::error::{Error, Result};
use crate::provenance;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;

/// Everything written to `paper_beam.json`.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Record {
    /// Experiment (`paper_beam`), build commit, crate versions and command: the one record
    /// header of every data file ([`provenance::Provenance`], flattened).
    #[serde(flatten)]
    pub provenance: provenance::Provenance,
    /// δ of the paper's example.
    pub delta: f64,
    /// The paper and the section reproduced.
    pub paper: String,
    /// The beam: geometry, section, load, constraints.
    pub beam: BeamInfo,
    /// Every number the paper prints for the beam (Eq. 31–37) against ours.
    pub paper_comparison: Vec<Row>,
    /// The `condensed` strategy at the same δ against methods.md and the exact requirement.
    pub condensed_comparison: Vec<Row>,
    /// One line per strategy.
    pub strategies: Vec<StrategyLine>,
    /// The cond-optimal penalties at δ (`optimal`, ours: the paper does not print it).
    #[serde(default)]
    pub optimum: Option<Optimum>,
    /// Explanations of every difference, with the numbers computed for them.
    pub notes: Vec<Note>,
    /// The computations behind the notes.
    pub checks: Value,
}

/// One constraint of the beam.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct ConstraintInfo {
    /// 1-based index c.
    pub c: usize,
    /// 0-based DOF.
    pub dof: usize,
    /// 1-based node number (node 1 is clamped).
    pub node: usize,
    /// "axial" or "transverse".
    pub component: String,
    /// Node coordinate x (mm).
    pub x: f64,
    /// Limit û.
    pub limit: f64,
    /// `bilateral`, `upper` or `lower`.
    pub kind: String,
}

/// The beam of Fig. 2.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct BeamInfo {
    /// Beam length (mm).
    pub length_mm: f64,
    /// Number of elements.
    pub n_elements: usize,
    /// Node coordinates x (mm).
    pub node_x: Vec<f64>,
    /// Young modulus in the example's units.
    pub e: f64,
    /// Section area.
    pub a: f64,
    /// Second moment of area.
    pub j: f64,
    /// The units of the example.
    pub units: String,
    /// The order of the DOFs.
    pub dof_order: String,
    /// Load vector q (Eq. 32).
    pub load: Vec<f64>,
    /// The constraints (Eq. 34).
    pub constraints: Vec<ConstraintInfo>,
}

/// One compared number.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Row {
    /// Stable id, e.g. `eq33.u7` (1-based entry numbers as in the paper).
    pub id: String,
    /// Equation (or column group) of the number.
    pub equation: String,
    /// What the number is.
    pub quantity: String,
    /// The reference exactly as printed (paper or methods.md); `None`: no reference value.
    pub reference_printed: Option<String>,
    /// The reference's value.
    pub reference: Option<f64>,
    /// "paper", "methods.md", "requirement" or "—".
    pub reference_source: String,
    /// Half a unit of the last printed digit (or the requirement's tolerance).
    pub tolerance: Option<f64>,
    /// Our value.
    pub ours: f64,
    /// `ours` formatted with two more digits than the reference.
    pub ours_printed: String,
    /// For the condensed table: the same quantity for Eq. 28 (our computation).
    pub contrast: Option<f64>,
    /// `|ours − reference| ≤ tolerance`; `None` when there is no reference.
    pub agree: Option<bool>,
    /// Short note; the long explanation is the note with the same key in `notes`.
    pub note: String,
}

/// The cond-optimal penalties at the paper's δ (`strategy::optimal`), next to Eq. 28 and
/// `condensed`. The paper prints no optimum, so every number here is ours; an outside
/// optimiser's 219.6 is quoted for comparison.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Optimum {
    /// δ.
    pub delta: f64,
    /// cond₂ of the optimal system.
    pub cond2: f64,
    /// Its penalties ε_c.
    pub penalties: Vec<f64>,
    /// Its signed gaps g_c.
    pub gaps: Vec<f64>,
    /// Constraints at penetration δ (relative 1e-4), 1-based.
    pub at_delta: Vec<usize>,
    /// cond₂ of Eq. 28 (paper) at δ.
    pub cond2_paper: f64,
    /// cond₂ of `condensed` at δ.
    pub cond2_condensed: f64,
    /// Certified lower bound λ_max(K)/λ_min(K_FF).
    pub cond2_lower_bound: f64,
    /// KKT residual of the optimiser.
    pub optimality: f64,
    /// Optimised starts and how many agreed within 1e-3.
    pub starts: usize,
    /// Optimised starts within 1e-3 of the best.
    pub starts_agreeing: usize,
    /// The outside optimiser's cond₂.
    pub outside_cond2: f64,
}

/// One strategy on the beam.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct StrategyLine {
    /// Strategy name.
    pub name: String,
    /// Its knob (ε, δ, …) as text.
    pub knob: String,
    /// Penalties per constraint (final ones for `augmented`).
    pub penalties: Vec<f64>,
    /// Signed gaps.
    pub gaps: Vec<f64>,
    /// Contact forces.
    pub forces: Vec<f64>,
    /// Max penetration.
    pub max_penetration: f64,
    /// cond₂ of the system matrix.
    pub cond2_system: f64,
    /// log10|det| of the system matrix.
    pub log10_det_system: f64,
    /// log10 of det(system)/det K.
    pub log10_det_ratio: f64,
    /// ‖u − u_Lagrange‖/‖u_Lagrange‖.
    pub error_vs_lagrange: f64,
    /// Linear solves.
    pub linear_solves: usize,
    /// Factorizations.
    pub factorizations: usize,
    /// Iterations.
    pub iterations: usize,
    /// Warnings of the solve.
    pub warnings: Vec<String>,
    /// The solution.
    pub u: Vec<f64>,
}

/// The explanation of a difference.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Note {
    /// `a`, `b`, …: the key the short notes of the tables refer to.
    pub key: String,
    /// One-line title.
    pub title: String,
    /// The explanation with the numbers computed for it.
    pub text: String,
}

/// Writes `paper_beam.json`, `deflection.csv` and `cond_vs_eps.csv` into `out` (created if
/// missing).
pub fn save(out: &Path, study: &Study) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    let text = serde_json::to_string_pretty(&study.record)
        .map_err(|e| Error::Numerical(format!("cannot serialize results: {e}")))?;
    provenance::write_atomic(&out.join(JSON_FILE), (text + "\n").as_bytes())?;
    provenance::write_csv(&out.join(DEFLECTION_FILE), &study.deflection)?;
    provenance::write_csv(&out.join(COND_FILE), &study.cond)?;
    provenance::write_csv(&out.join(COND_DELTA_FILE), &study.cond_delta)?;
    Ok(())
}

fn read_csv<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<Vec<T>> {
    let mut r = csv::Reader::from_path(path).map_err(|e| Error::io(path.display(), e))?;
    r.deserialize()
        .collect::<std::result::Result<Vec<T>, _>>()
        .map_err(|e| Error::bad_file(path.display(), e))
}

/// Reads back what [`save`] wrote into `out`.
pub fn load(out: &Path) -> Result<Study> {
    let jp = out.join(JSON_FILE);
    let text = std::fs::read_to_string(&jp).map_err(|e| {
        Error::io(
            format!("{} (run without --render-only first)", jp.display()),
            e,
        )
    })?;
    let record: Record = serde_json::from_str(&text).map_err(|e| Error::json(jp.display(), &e))?;
    Ok(Study {
        record,
        deflection: read_csv::<DeflectionRow>(&out.join(DEFLECTION_FILE))?,
        cond: read_csv::<CondRow>(&out.join(COND_FILE))?,
        cond_delta: read_csv::<CondRow>(&out.join(COND_DELTA_FILE))?,
    })
}

/// A row of `cond_vs_eps.csv`.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct CondRow {
    /// `K` (no penalty), `uniform`, `paper`, `condensed`, `spring`.
    pub series: String,
    /// δ for the δ-driven strategies (empty otherwise).
    pub delta: Option<f64>,
    /// Uniform ε, or max_c ε_c for the δ-driven strategies.
    pub eps: f64,
    /// ε of constraint 1.
    pub eps_1: f64,
    /// ε of constraint 2.
    pub eps_2: f64,
    /// ε of constraint 3.
    pub eps_3: f64,
    /// cond₂ of the system matrix.
    pub cond2: f64,
    /// Max penetration.
    pub max_penetration: f64,
    /// log10 det(K + ε)/det K.
    pub log10_det_ratio: f64,
}
