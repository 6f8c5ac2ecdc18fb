//! The paper's beam example (Sec. 4.2, Eq. 30–37) number by number: every number the paper
//! prints next to ours with the half-unit-of-last-digit agreement test and a note, the same
//! for the `condensed` strategy (against methods.md), one line per other strategy, the
//! computations behind every explanation, the deflection curves and cond₂ against ε.
//!
//! [`run`] computes a [`Study`]; [`save`] writes it into a directory:
//! * `paper_beam.json` — the [`Record`];
//! * `deflection.csv` — nodal values and Hermite-interpolated deflection curves
//!   ([`DeflectionRow`]);
//! * `cond_vs_eps.csv` — cond₂(K + εDDᵀ) and max penetration for a uniform ε on a log grid,
//!   plus the δ-driven strategies (`paper`, `condensed`, `spring`) at δ ∈ [`DELTAS`]
//!   ([`CondRow`]).
//!
//! [`figures::drawings`] draws `fig3_deflection_free`, `fig4_deflection_contact` and
//! `cond_vs_eps`, `cond_vs_delta` (PNG + SVG) from what [`load`] reads back, never from live state;
//! [`report::text`] is the printed report; [`PaperBeam`] is the study as the shared entry
//! ([`crate::study::shape::main`]) runs it.
//!
//! * [`printed`] — the paper's printed numbers (one copy, also used by the tests).
//! * [`record`] — the record's types, writing and reading.
//! * `solves` — the strategies at δ and the equal-accuracy comparisons.
//! * `checks` — the computations behind the notes; `tables` — the comparison rows;
//!   `notes` — the explanations.
//! * `deflection`, `cond_vs_eps` — the data behind the figures; [`figures`] — the figures.

mod checks;
mod cond_vs_eps;
mod deflection;
pub mod figures;
mod notes;
pub mod printed;
pub mod record;
pub mod report;
mod solves;
mod tables;

pub use deflection::DeflectionRow;
pub use record::CondRow;
pub use record::{load, save, Optimum, Record};

use crate::error::Result;
use crate::model::beam::paper;
use crate::strategy;
use crate::study::shape::{self, Drawing, RunContext};
use record::{BeamInfo, ConstraintInfo};

/// δ of the paper's example (mm).
pub const DELTA: f64 = 0.1;
/// δ values at which the δ-driven strategies are marked in `cond_vs_eps`.
pub const DELTAS: [f64; 4] = [1.0, 0.1, 0.01, 0.001];
/// Number of points of the uniform-ε grid, log-spaced over `[EPS_LO, EPS_HI]`.
pub const N_EPS: usize = 100;
/// Smallest ε of the uniform-ε grid (and of the bisection for a target penetration).
pub const EPS_LO: f64 = 1e-1;
/// Largest ε of the uniform-ε grid (and of the bisection for a target penetration).
pub const EPS_HI: f64 = 1e9;
/// Interpolation points per element for the deflection curves.
pub const PTS_PER_ELEMENT: usize = 80;

/// The record's file name.
pub const JSON_FILE: &str = "paper_beam.json";
/// The deflection curves' file name.
pub const DEFLECTION_FILE: &str = "deflection.csv";
/// The cond₂-against-ε file name.
pub const COND_FILE: &str = "cond_vs_eps.csv";
/// The cond₂-against-δ file name (Eq. 28, condensed, spring, optimal).
pub const COND_DELTA_FILE: &str = "cond_vs_delta.csv";

/// The outcome of the study: the record and the data behind the figures.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Study {
    /// `paper_beam.json`.
    pub record: Record,
    /// `deflection.csv`: `free`, `paper`, `condensed`, `lagrange`.
    pub deflection: Vec<DeflectionRow>,
    /// `cond_vs_eps.csv`.
    pub cond: Vec<CondRow>,
    /// `cond_vs_delta.csv`.
    pub cond_delta: Vec<CondRow>,
}

/// The beam of Fig. 2 as recorded.
fn beam_info(frame: &crate::model::beam::Frame, p: &crate::system::Problem) -> BeamInfo {
    let constraints = p
        .constraints
        .iter()
        .enumerate()
        .map(|(c, con)| {
            let (node, k) = (0..frame.nodes.len())
                .flat_map(|nd| (0..3).map(move |k| (nd, k)))
                .find(|&(nd, k)| frame.dof(nd, k) == Some(con.lead_dof()))
                .expect("constrained DOF exists");
            ConstraintInfo {
                c: c + 1,
                dof: con.lead_dof(),
                node: node + 1,
                component: ["axial", "transverse", "rotation"][k].into(),
                x: frame.nodes[node].0,
                limit: con.limit,
                kind: format!("{:?}", con.kind).to_lowercase(),
            }
        })
        .collect();
    let sec = crate::model::beam::Section::rectangle(paper::E, 1.0, 1.0);
    BeamInfo {
        length_mm: paper::LENGTH,
        n_elements: paper::N_ELEMENTS,
        node_x: frame.nodes.iter().map(|n| n.0).collect(),
        e: sec.e,
        a: sec.a,
        j: sec.j,
        units: "length mm, force 100 N (so E = 2100 = 210 GPa), see note (d)".into(),
        dof_order: "(axial u, transverse w, rotation θ) per free node 2, 3, 4; node 1 clamped"
            .into(),
        load: p.q.clone(),
        constraints,
    }
}

/// Runs the study: every solve, check, comparison and note, and the data of the figures.
/// The record carries `provenance` (the entry's).
pub fn run(provenance: &crate::provenance::Provenance) -> Result<Study> {
    let frame = paper::frame();
    let p = paper::problem();
    let s = solves::solve_all(&p)?;
    let ch = checks::compute(&p, &s)?;
    let paper_comparison = tables::paper_comparison(&p, &frame, &s, &ch);
    let condensed_comparison = tables::condensed_comparison(&p, &frame, &s, &ch);
    let cond = cond_vs_eps::cond_rows(&p)?;
    let cond_delta = cond_vs_eps::cond_delta_rows(&p)?;
    let optimum = optimum(&s);
    let record = Record {
        provenance: provenance.clone(),
        delta: DELTA,
        paper: "Bednarek, Kowalczyk, Marczewski, Sosnowski, CMMS 2011, Sec. 4.2, Eq. 30-37".into(),
        beam: beam_info(&frame, &p),
        paper_comparison,
        condensed_comparison,
        notes: notes::notes(&s, &ch, &cond),
        checks: ch.to_json(&s),
        strategies: s.strategies.clone(),
        optimum: Some(optimum),
    };
    let mut deflection = deflection::deflection_rows(&frame, "free", &s.u0);
    for (name, u) in [
        (strategy::paper::STRATEGY.name, &s.pap.sol.u),
        (strategy::condensed::STRATEGY.name, &s.con.sol.u),
        (strategy::lagrange::STRATEGY.name, &s.lag.sol.u),
    ] {
        deflection.extend(deflection::deflection_rows(&frame, name, u));
    }
    Ok(Study {
        record,
        deflection,
        cond,
        cond_delta,
    })
}

/// The optimum at δ next to Eq. 28 and `condensed` (ours: the paper prints none).
fn optimum(s: &solves::Solves) -> Optimum {
    let o = &s.opt.sol;
    let rep = o.stats.optimal.clone().unwrap_or_default();
    Optimum {
        delta: DELTA,
        cond2: s.opt.cond2,
        penalties: o.penalties.clone(),
        gaps: o.gaps.clone(),
        at_delta: o
            .gaps
            .iter()
            .enumerate()
            .filter(|(_, g)| g.abs() >= DELTA * (1.0 - 1e-4))
            .map(|(c, _)| c + 1)
            .collect(),
        cond2_paper: s.pap.cond2,
        cond2_condensed: s.con.cond2,
        cond2_lower_bound: rep.cond2_lower_bound,
        optimality: rep.optimality,
        starts: rep.starts,
        starts_agreeing: rep.starts_agreeing,
        outside_cond2: printed::OUTSIDE_OPTIMUM_COND2,
    }
}

/// The `paper_beam` binary: no flags of its own.
#[derive(clap::Args, Debug)]
pub struct Flags {}

/// The study as the shared entry runs it.
pub struct PaperBeam;

impl shape::Study for PaperBeam {
    const NAME: &'static str = "paper_beam";
    const ABOUT: &'static str =
        "The paper's beam example (Eq. 30-37): paper's numbers vs ours, data files and figures";
    const PROGRESS: &'static str = "paper_beam";
    const DEFAULT_OUT: &'static str = "results/paper_beam";
    const FIGURES_DIR: &'static str = "";
    type Flags = Flags;
    type Config = ();
    type Record = Study;

    fn config(_: &Flags) -> Result<()> {
        Ok(())
    }
    fn run(_: &(), ctx: &RunContext) -> Result<Study> {
        run(ctx.provenance)
    }
    fn save(
        out: &std::path::Path,
        _: &(),
        study: &Study,
        _provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        save(out, study)
    }
    fn load(out: &std::path::Path) -> Result<Study> {
        load(out)
    }
    fn figures(study: &Study) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(study))
    }
    fn report(study: &Study) -> String {
        report::text(&study.record)
    }
    fn json(study: &Study) -> Result<String> {
        crate::provenance::json_text("paper_beam results", &study.record)
    }
}
