//! The barrier's κ sensitivity: κ is the log barrier's second knob beside
//! d̂, and a row is only meaningful with it. On each Hertz case's middle mesh, at
//! d̂ = [`KAPPA_DHATS`]·a, the barrier is force-controlled at fixed κ over a log grid
//! ([`PER_DECADE`] values per decade) that spans both adaptive rules' clamps — from the `ipc`
//! rule's κ_min to the `balanced` rule's κ_max ([`barrier::kappa_bounds`]) — and
//! then with each rule itself, so the figure shows where along the curve each rule lands.
//! Rows are [`BenchRow`]s (`kappa_rule` `fixed`, `ipc` or `balanced`; κ in `kappa_final`).

use super::{run_job, BenchConfig, BenchJob, BenchRow, Prepared};
use crate::error::Result;
use crate::progress::Progress;
use crate::strategy::barrier::{self, KappaRule};
use crate::strategy::{Knobs, Method};
use rayon::prelude::*;

/// d̂ over a of the κ study.
pub const KAPPA_DHATS: [f64; 2] = [1e-3, 1e-4];
/// Fixed κ values per decade.
pub const PER_DECADE: f64 = 2.0;

/// The κ study's rows (empty when `barrier` is not among the methods or no Hertz case is).
pub fn kappa_sensitivity(cfg: &BenchConfig, progress: &Progress) -> Result<Vec<BenchRow>> {
    if !cfg
        .methods
        .iter()
        .any(|m| std::ptr::eq(*m, &barrier::STRATEGY))
    {
        return Ok(Vec::new());
    }
    let mut meshes = cfg.meshes.clone();
    meshes.sort_by(|a, b| a.total_cmp(b));
    let Some(&h_rel) = meshes.get(meshes.len() / 2) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for &case in cfg.cases.iter().filter(|c| c.is_rigid_hertz()) {
        let prep = Prepared::new(cfg, case, h_rel)?;
        // The rows' `err_discretization` and `err_domain` mean what they mean in rows.csv.
        let errors = prep.errors(cfg)?;
        let mesh = prep.mesh(&errors);
        let problem = &prep.scene().problem;
        let mut jobs = Vec::new();
        for &rel in &KAPPA_DHATS {
            let dhat = rel * cfg.a_target;
            let (lo, _, _) = barrier::kappa_bounds(problem, dhat, KappaRule::Ipc)?;
            let (_, hi, _) = barrier::kappa_bounds(problem, dhat, KappaRule::Balanced)?;
            let (a, b) = (
                (lo.log10() * PER_DECADE).floor() as i32,
                (hi.log10() * PER_DECADE).ceil() as i32,
            );
            let rules = (a..=b)
                .map(|k| KappaRule::Fixed(10f64.powf(f64::from(k) / PER_DECADE)))
                .chain([KappaRule::Ipc, KappaRule::Balanced]);
            for kappa in rules {
                let knobs = Knobs {
                    kappa,
                    ..Knobs::delta(dhat)
                };
                jobs.push(BenchJob {
                    method: Method::new(&barrier::STRATEGY, knobs)?,
                    knob: "delta",
                    rel: Some(rel),
                });
            }
        }
        progress.message(format!(
            "{} h/a = {h_rel}: barrier κ study, {} solves",
            case.name(),
            jobs.len()
        ));
        let rows: Vec<BenchRow> = jobs
            .par_iter()
            .map(|job| run_job(cfg, &mesh, job).0)
            .collect();
        out.extend(rows);
    }
    Ok(out)
}
