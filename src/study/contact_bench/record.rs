//! What the benchmark records: the leaderboard, the convergence rates, and the saved summary.

use super::analytic::Case;
use super::{BenchConfig, BenchRow, BenchRun, Floor, Profile, FINE_OVER_A, GROWTH};
use crate::error::{Error, Result};
use crate::strategy;
use serde::{Deserialize, Serialize};

/// The leaderboard's margin: a knob is admissible where its penalty error is at most this
/// fraction of the mesh's discretization error, so that the penalty's share of the total error
/// is negligible (a tenth: total ≤ 1.1 × the discretization error by the triangle inequality,
/// where "below" admitted a winner at 1.83×).
pub const MARGIN: f64 = 0.1;

/// Is the row admissible on the leaderboard ([`MARGIN`])?
pub fn admissible(r: &BenchRow) -> bool {
    r.error.is_empty() && r.cond2_system.is_some() && r.err_penalty <= MARGIN * r.err_discretization
}

/// One leaderboard entry: the cheapest knob of a rule on a mesh whose penalty error is within
/// the margin ([`MARGIN`]) of the discretization error.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Leader {
    /// Case.
    pub case: String,
    /// Element size at the contact.
    pub h: f64,
    /// Method, with its knob name (`augmented` appears as plain and adaptive).
    pub rule: String,
    /// Knob name.
    pub knob: String,
    /// The knob value (relative) with the smallest cond₂ among those below the line; None if
    /// none is (or the rule has no knob).
    pub knob_rel: Option<f64>,
    /// Its cond₂.
    pub cond2_system: Option<f64>,
    /// Its penalty error.
    pub err_penalty: Option<f64>,
    /// The mesh's discretization error.
    #[serde(deserialize_with = "crate::provenance::null_as_nan")]
    pub err_discretization: f64,
    /// Knob values tried (solved).
    pub tried: usize,
    /// The grid's resolution at the winner: the relative cond₂ difference to the next softer
    /// knob tried (which failed the margin, or was dearer); the cheapest admissible cond₂ lies
    /// between the two. None where there is no softer knob.
    #[serde(default)]
    pub resolution: Option<f64>,
    /// Within the resolution of the mesh's cheapest rule (its cond₂ above the cheapest by less
    /// than either entry's resolution): a tie, not a loss.
    #[serde(default)]
    pub tied_best: bool,
}

/// The rule name of a row on the leaderboard (`augmented` split by its adaptive switch).
pub fn rule_of(r: &BenchRow) -> String {
    if r.knob == "adaptive-tol" {
        format!("{} (adaptive)", r.method)
    } else {
        r.method.clone()
    }
}

/// Per (case, mesh, rule): the cheapest knob value (smallest cond₂) whose penalty error is
/// within the margin ([`MARGIN`]), the grid's resolution there, and whether it ties the
/// mesh's cheapest rule.
pub fn leaderboard(rows: &[BenchRow]) -> Vec<Leader> {
    let mut out = leaders(rows);
    let meshes: Vec<(String, f64)> = out.iter().map(|l| (l.case.clone(), l.h)).collect();
    for (case, h) in meshes {
        let best = out
            .iter()
            .filter(|l| l.case == case && l.h == h)
            .filter_map(|l| l.cond2_system.map(|c| (c, l.resolution.unwrap_or(0.0))))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((c_best, res_best)) = best else {
            continue;
        };
        for l in out.iter_mut().filter(|l| l.case == case && l.h == h) {
            if let Some(c) = l.cond2_system {
                l.tied_best = c / c_best - 1.0 <= res_best.max(l.resolution.unwrap_or(0.0));
            }
        }
    }
    out
}

/// [`leaderboard`] before the ties.
fn leaders(rows: &[BenchRow]) -> Vec<Leader> {
    let mut keys: Vec<(String, f64, String)> = Vec::new();
    for r in rows {
        let k = (r.case.clone(), r.h, rule_of(r));
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .map(|(case, h, rule)| {
            let group: Vec<&BenchRow> = rows
                .iter()
                .filter(|r| r.case == case && r.h == h && rule_of(r) == rule && r.error.is_empty())
                .collect();
            let err_discretization = rows
                .iter()
                .find(|r| r.case == case && r.h == h && r.err_discretization.is_finite())
                .map_or(f64::NAN, |r| r.err_discretization);
            let best = group
                .iter()
                .filter(|r| admissible(r))
                .min_by(|a, b| a.cond2_system.unwrap().total_cmp(&b.cond2_system.unwrap()));
            // The next softer knob tried: cond₂ falls towards the soft end, so the cheapest
            // admissible value lies between the winner and it.
            let resolution = best.and_then(|b| {
                let (cb, kb) = (b.cond2_system?, b.knob_rel?);
                let soft = |r: &&&BenchRow| match r.knob.as_str() {
                    "eps" | "factor" => r.knob_rel.is_some_and(|k| k < kb),
                    _ => r.knob_rel.is_some_and(|k| k > kb),
                };
                group
                    .iter()
                    .filter(soft)
                    .filter(|r| r.cond2_system.is_some())
                    .min_by(|a, b| {
                        let d = |r: &BenchRow| (r.knob_rel.unwrap() / kb).ln().abs();
                        d(a).total_cmp(&d(b))
                    })
                    .map(|n| (cb / n.cond2_system.unwrap() - 1.0).abs())
            });
            Leader {
                case,
                h,
                knob: group.first().map_or(String::new(), |r| r.knob.clone()),
                rule,
                knob_rel: best.and_then(|r| r.knob_rel),
                cond2_system: best.and_then(|r| r.cond2_system),
                err_penalty: best.map(|r| r.err_penalty),
                err_discretization,
                tried: group.len(),
                resolution,
                tied_best: false,
            }
        })
        .collect()
}

/// Convergence of Lagrange's pressure error with h per Hertz case: the least-squares slope of
/// log(err) against log(h) over the meshes (None with fewer than two meshes). The flat punch
/// has none: its error is rounding on every mesh.
pub fn convergence_rates(rows: &[BenchRow]) -> Vec<(String, Option<f64>)> {
    let mut out = Vec::new();
    for case in [Case::HertzPlane, Case::HertzAxi] {
        let (h, e): (Vec<f64>, Vec<f64>) = rows
            .iter()
            .filter(|r| r.case == case.name() && r.method == strategy::lagrange::STRATEGY.name)
            .map(|r| (r.h, r.err_discretization))
            .unzip();
        if h.is_empty() {
            continue;
        }
        out.push((case.name().to_string(), crate::stats::loglog_slope(&h, &e)));
    }
    out
}

/// The saved record: provenance with the config, the rows, the leaderboard and the rates.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    /// Provenance and config.
    pub provenance: serde_json::Value,
    /// Least-squares slope of log(err_discretization) against log(h), per case.
    pub rates: Vec<(String, Option<f64>)>,
    /// Per (case, mesh, rule): the cheapest knob below the discretization error.
    pub leaderboard: Vec<Leader>,
    /// Every row.
    pub rows: Vec<BenchRow>,
    /// Nodal pressures on each case's finest mesh.
    pub profiles: Vec<Profile>,
    /// Per (case, mesh): the cond₂ no penalties can go below.
    #[serde(default)]
    pub floors: Vec<Floor>,
    /// The barrier at fixed κ and under each κ rule ([`super::kappa`]).
    #[serde(default)]
    pub kappa: Vec<BenchRow>,
    /// Lagrange per Hertz mesh and block size ([`super::domain`]).
    #[serde(default)]
    pub domain: Vec<super::domain::DomainRow>,
}

/// The record of a run: provenance with `cfg`, the rates, the leaderboard, and the run's rows,
/// profiles, floors and both studies.
pub fn summary(
    cfg: &BenchConfig,
    run: BenchRun,
    provenance: &crate::provenance::Provenance,
) -> Summary {
    Summary {
        provenance: provenance.record(serde_json::json!({
            "config": cfg,
            // The jobs of a mesh run on rayon's pool (results do not depend on it; `seconds` do).
            "threads": rayon::current_num_threads(),
            "domain_sizes": super::domain::DOMAIN_SIZES,
            "growth": GROWTH,
            "fine_over_a": FINE_OVER_A,
        })),
        rates: convergence_rates(&run.rows),
        leaderboard: leaderboard(&run.rows),
        rows: run.rows,
        profiles: run.profiles,
        floors: run.floors,
        kappa: run.kappa,
        domain: run.domain,
    }
}

/// Writes `OUT/rows.csv`, `OUT/kappa.csv` (the κ study, if run), `OUT/domain.csv` (the domain
/// study, with a Hertz case) and `OUT/summary.json` (everything).
pub fn save(out: &std::path::Path, summary: &Summary) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
    crate::provenance::write_csv(&out.join("rows.csv"), &summary.rows)?;
    if !summary.kappa.is_empty() {
        crate::provenance::write_csv(&out.join("kappa.csv"), &summary.kappa)?;
    }
    if !summary.domain.is_empty() {
        crate::provenance::write_csv(&out.join("domain.csv"), &summary.domain)?;
    }
    crate::provenance::write_json(&out.join("summary.json"), summary)
}

/// Reads `OUT/summary.json` back.
pub fn load(out: &std::path::Path) -> Result<Summary> {
    crate::provenance::read_json(&out.join("summary.json"))
}

/// The mesh's conditioning floor ([`super::Floor`]), where the summary has one.
pub(super) fn floor_of(s: &Summary, case: &str, h: f64) -> Option<f64> {
    s.floors
        .iter()
        .find(|f| f.case == case && f.h == h)
        .map(|f| f.cond2_floor)
}
