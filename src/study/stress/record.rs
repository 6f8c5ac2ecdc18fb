//! A stress run as a whole: scenes, both studies with progress, and the CSV/JSON outputs
//! with their manifest.

use super::*;
use crate::error::{Error, Result};
use crate::generate::Family;
use crate::progress::Progress;
use crate::provenance::{self, csv_opt, Provenance};
use crate::stats::median;
use serde_json::{json, Value};
use std::path::Path;
use std::time::Instant;

/// What a stress run covers: the paper's beam plus `count` seeded scenes per family.
#[derive(Clone, Debug)]
pub struct StressRun {
    /// Master seed of the generated scenes.
    pub seed: u64,
    /// Generated scenes per family (at most [`MAX_COUNT`]).
    pub count: usize,
    /// Families of generated scenes (`beam`, `membrane`, `spectrum`); empty: the paper's beam
    /// only.
    pub families: Vec<Family>,
    /// The studies' configuration.
    pub config: StressConfig,
}

impl serde::Serialize for StressRun {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        let families: Vec<&str> = self.families.iter().map(|f| f.name()).collect();
        let v = json!({
            "seed": self.seed,
            "count": self.count,
            "families": families,
            "config": serde_json::to_value(&self.config).map_err(S::Error::custom)?,
        });
        serde::Serialize::serialize(&v, s)
    }
}

/// Largest `count` per family: the dense double-double reference grows like N³.
pub const MAX_COUNT: usize = 50;

/// The rows of a stress run.
#[derive(Clone, Debug)]
pub struct StressOutput {
    /// The scenes, in order.
    pub scenes: Vec<StressScene>,
    /// [`eps_study`] rows of every scene.
    pub eps_rows: Vec<EpsRow>,
    /// [`strategy_study`] rows of every scene.
    pub strategy_rows: Vec<StrategyRow>,
    /// Wall time of the run (s).
    pub wall_seconds: f64,
}

impl StressRun {
    /// Checks `count` ≤ [`MAX_COUNT`].
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--families", self.families.iter().map(|f| f.name()))?;
        if self.count == 0 && !self.families.is_empty() {
            return Err(Error::out_of_range(
                "--count",
                0,
                "≥ 1 where --families names a family (--families none: the paper's beam only)",
            ));
        }
        if self.count > MAX_COUNT {
            return Err(Error::out_of_range(
                "--count",
                self.count,
                format!("≤ {MAX_COUNT} (the dense double-double reference grows like N³)"),
            ));
        }
        Ok(())
    }
}

/// Runs both studies on every scene ([`StressRun::validate`]d first), one progress step per
/// scene.
pub fn run(r: &StressRun, progress: &Progress) -> Result<StressOutput> {
    r.validate()?;
    let t0 = Instant::now();
    let scenes = stress_scenes(r.seed, r.count, &r.families)?;
    progress.set_total(scenes.len());
    let mut eps_rows = Vec::new();
    let mut strategy_rows = Vec::new();
    for sc in &scenes {
        let t = Instant::now();
        progress.message(sc.name.clone());
        eps_rows.extend(eps_study(sc, &r.config)?);
        strategy_rows.extend(strategy_study(sc, &r.config)?);
        progress.step(&format!(
            "{} (N = {}, m = {}): {:.2} s",
            sc.name,
            sc.problem.n(),
            sc.problem.m(),
            t.elapsed().as_secs_f64()
        ));
    }
    progress.finish();
    Ok(StressOutput {
        scenes,
        eps_rows,
        strategy_rows,
        wall_seconds: t0.elapsed().as_secs_f64(),
    })
}

/// The record of a run (`stress.json`): provenance, what was run, the summary.
pub fn record(r: &StressRun, o: &StressOutput, provenance: &Provenance) -> Value {
    provenance.record(json!({
        "seed": r.seed,
        "count": r.count,
        "families": r.families,
        "config": r.config,
        "scenes": o.scenes.iter().map(|s| json!({"name": s.name, "family": s.family,
            "n": s.problem.n(), "m": s.problem.m()})).collect::<Vec<_>>(),
        "reference": "double-double Gaussian elimination with partial pivoting + 2 refinement steps (study::stress::PenalizedSystem::reference)",
        "plot_floor": PLOT_FLOOR,
        "wall_seconds": o.wall_seconds,
        "summary": summary(&o.eps_rows, &o.strategy_rows),
    }))
}

/// What a stress run records (and `--json` prints): the manifest (`stress.json`: provenance,
/// what was run, the summary) and the rows of both studies.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Record {
    /// [`record()`] of the run.
    pub manifest: Value,
    /// The ε study's rows.
    pub eps_study: Vec<EpsRow>,
    /// The strategy study's rows.
    pub strategies: Vec<StrategyRow>,
}

/// Writes `eps_study.csv`, `eps_study.json`, `strategies.csv`, `strategies.json` and the
/// manifest as `stress.json` into `out` (each atomically).
pub fn write(out: &Path, rec: &Record) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    let write = |name: &str, text: &str| provenance::write_atomic(&out.join(name), text.as_bytes());
    write("eps_study.csv", &eps_csv(&rec.eps_study))?;
    write(
        "eps_study.json",
        &serde_json::to_string(&rec.eps_study).expect("JSON value"),
    )?;
    write("strategies.csv", &strategy_csv(&rec.strategies))?;
    write(
        "strategies.json",
        &serde_json::to_string(&rec.strategies).expect("JSON value"),
    )?;
    provenance::write_json(&out.join("stress.json"), &rec.manifest)
}

/// Reads what [`write()`] wrote.
pub fn load(out: &Path) -> Result<Record> {
    // The ε study first: the data the figures are drawn from, named where it is missing.
    let eps_study = provenance::read_json(&out.join("eps_study.json"))?;
    Ok(Record {
        eps_study,
        strategies: provenance::read_json(&out.join("strategies.json"))?,
        manifest: provenance::read_json(&out.join("stress.json"))?,
    })
}

/// The ε study as CSV (for spreadsheets; `eps_study.json` keeps every field exactly).
pub fn eps_csv(rows: &[EpsRow]) -> String {
    let mut t = String::from(
        "scene,family,n,m_active,eps,cond2,cond2_f64,cond_eps_mach,cond2_scaled,precision_warning,reference_correction,\
         err_plain,err_refined_working,err_refined_extended,err_equilibrated,\
         err_equilibrated_refined_extended,steps_extended,penalty_error,total_error_plain,\
         total_error_refined,variant_errors,strategy_status,strategy_max_penetration,\
         strategy_warnings,strategy_message\n",
    );
    for r in rows {
        let f = &r.forward;
        let cells = [
            r.scene.clone(),
            r.family.clone(),
            r.n.to_string(),
            r.m_active.to_string(),
            format!("{:e}", r.eps),
            csv_opt(r.cond2),
            csv_opt(r.cond2_f64),
            csv_opt(r.cond_eps_mach),
            csv_opt(r.cond2_scaled),
            r.precision_warning.to_string(),
            csv_opt(r.reference_correction),
            csv_opt(f.plain),
            csv_opt(f.refined_working),
            csv_opt(f.refined_extended),
            csv_opt(f.equilibrated),
            csv_opt(f.equilibrated_refined_extended),
            r.steps_extended.map_or(String::new(), |s| s.to_string()),
            csv_opt(r.penalty_error),
            csv_opt(r.total_error_plain),
            csv_opt(r.total_error_refined),
            r.variant_errors.join(" | "),
            r.strategy_status.clone(),
            csv_opt(r.strategy_max_penetration),
            r.strategy_warnings.to_string(),
            r.strategy_message.clone(),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

/// The strategy study as CSV.
pub fn strategy_csv(rows: &[StrategyRow]) -> String {
    let mut t = String::from(
        "scene,family,n,m,method,knob,value,value2,adaptive,status,max_penetration,max_penalty,\
         cond2_system,precision_expected,n_warnings,forward_error,error_vs_lagrange,message,\
         warnings\n",
    );
    for r in rows {
        let cells = [
            r.scene.clone(),
            r.family.clone(),
            r.n.to_string(),
            r.m.to_string(),
            r.method.clone(),
            r.knob.clone(),
            format!("{:e}", r.value),
            csv_opt(r.value2),
            r.adaptive.to_string(),
            r.status.clone(),
            csv_opt(r.max_penetration),
            csv_opt(r.max_penalty),
            csv_opt(r.cond2_system),
            r.precision_expected.to_string(),
            r.warnings.len().to_string(),
            csv_opt(r.forward_error),
            csv_opt(r.error_vs_lagrange),
            r.message.clone(),
            r.warnings.join(" | "),
        ];
        t.push_str(&provenance::csv_line(&cells));
        t.push('\n');
    }
    t
}

/// What the run found, in numbers (also the `summary` of the JSON outputs).
pub fn summary(eps_rows: &[EpsRow], strat: &[StrategyRow]) -> Value {
    let count = |s: &str| strat.iter().filter(|r| r.status == s).count();
    let unwarned: Vec<Value> = strat
        .iter()
        .filter(|r| r.precision_expected && r.warnings.is_empty())
        .map(|r| json!({"scene": r.scene, "method": r.method, "value": r.value}))
        .collect();
    let bad: Vec<Value> = strat
        .iter()
        .filter(|r| r.status == "panic" || r.status == "non_finite")
        .map(|r| {
            json!({"scene": r.scene, "method": r.method, "knob": r.knob, "value": r.value,
                   "value2": r.value2, "adaptive": r.adaptive, "status": r.status,
                   "message": r.message})
        })
        .collect();
    // Refinement in the regime where theory says it converges (cond·ε_mach < 1e-2).
    let regime: Vec<&EpsRow> = eps_rows
        .iter()
        .filter(|r| r.cond_eps_mach.is_some_and(|c| c < 1e-2))
        .collect();
    let med = |f: &dyn Fn(&EpsRow) -> Option<f64>, rows: &[&EpsRow]| {
        median(&rows.iter().filter_map(|r| f(r)).collect::<Vec<_>>())
    };
    let beyond: Vec<&EpsRow> = eps_rows
        .iter()
        .filter(|r| r.cond_eps_mach.is_none_or(|c| c >= 1e-2))
        .collect();
    let plain_failed_equil_ok = eps_rows
        .iter()
        .filter(|r| r.forward.plain.is_none() && r.forward.equilibrated.is_some())
        .count();
    let max_cond = eps_rows
        .iter()
        .filter_map(|r| r.cond2)
        .chain(strat.iter().filter_map(|r| r.cond2_system))
        .fold(0.0f64, f64::max);
    json!({
        "strategy_runs": strat.len(),
        "ok": count("ok"),
        "clean_errors": count("error"),
        "non_finite": count("non_finite"),
        "panics": count("panic"),
        "panics_or_non_finite": bad,
        "precision_expected_but_unwarned": unwarned,
        "eps_points": eps_rows.len(),
        "max_cond2_seen": max_cond,
        "refinement_regime_cond_eps_below_1e-2": {
            "points": regime.len(),
            "median_err_plain": med(&|r| r.forward.plain, &regime),
            "median_err_refined_working": med(&|r| r.forward.refined_working, &regime),
            "median_err_refined_extended": med(&|r| r.forward.refined_extended, &regime),
            "median_err_equilibrated": med(&|r| r.forward.equilibrated, &regime),
        },
        "beyond_cond_eps_1e-2": {
            "points": beyond.len(),
            "plain_solved": beyond.iter().filter(|r| r.forward.plain.is_some()).count(),
            "equilibrated_solved": beyond.iter().filter(|r| r.forward.equilibrated.is_some()).count(),
            "median_err_plain": med(&|r| r.forward.plain, &beyond),
            "median_err_refined_extended": med(&|r| r.forward.refined_extended, &beyond),
            "median_err_equilibrated_refined_extended":
                med(&|r| r.forward.equilibrated_refined_extended, &beyond),
        },
        "points_where_plain_is_refused_but_equilibrated_solves": plain_failed_equil_ok,
    })
}
