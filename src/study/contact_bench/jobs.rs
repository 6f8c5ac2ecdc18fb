//! The jobs of a mesh: every method over its knob grid, and the values added near each
//! rule's leaderboard threshold.

use super::{admissible, run_job, BenchConfig, BenchRow, Mesh, LONG_JOB_S};
use crate::model::elasticity::Indentation;
use crate::progress::Progress;
use crate::strategy::{self, Method};
use crate::study::grid::{Augmented, KnobGrid, Level};
use rayon::prelude::*;

/// One method at one knob value.
#[derive(Clone, Copy, Debug)]
pub struct BenchJob {
    /// The method.
    pub method: Method,
    /// Knob name for the row.
    pub knob: &'static str,
    /// Its value relative to its scale.
    pub rel: Option<f64>,
}

/// The jobs of one scene: every method over its knob grid ([`KnobGrid::points`]; absolute
/// values from the scene's a, E* and K). `augmented` runs plain at ε = the constraints' mean
/// K_dd and adaptive from [`ADAPTIVE_START`] times it: the adaptive rule starts soft (ε/100)
/// and raises ε where Uzawa contracts slowly; at ε = mean K_dd plain Uzawa already contracts
/// ≈ 10× per update and the rule has nothing to do.
pub fn jobs(cfg: &BenchConfig, scene: &Indentation, a: f64) -> Vec<BenchJob> {
    let aug_eps = scene.problem.mean_constraint_stiffness();
    let grid = KnobGrid {
        eps: cfg
            .eps_rel
            .iter()
            .map(|&r| Level {
                value: r * cfg.e_star() / cfg.a_target,
                rel: Some(r),
            })
            .collect(),
        factors: cfg
            .factors
            .iter()
            .map(|&f| Level {
                value: f,
                rel: Some(f),
            })
            .collect(),
        deltas: Level::relatives(&cfg.deltas_rel, a),
        tols: Level::relatives(&cfg.deltas_rel, a),
        augmented: vec![
            Augmented {
                eps: aug_eps,
                adaptive: false,
                name: "tol",
            },
            Augmented {
                eps: ADAPTIVE_START * aug_eps,
                adaptive: true,
                name: "adaptive-tol",
            },
        ],
        exact: Some(Level {
            value: 0.0,
            rel: None,
        }),
    };
    grid.points(&cfg.methods)
        .into_iter()
        .map(|p| BenchJob {
            method: p.method,
            knob: p.knob,
            rel: p.level.rel,
        })
        .collect()
}

/// The adaptive augmented Lagrangian's starting penalty, relative to the plain one's ε (the
/// constraints' mean K_dd): soft, so that the rule's raise of ε
/// ([`strategy::augmented::adapted_penalty`]) is what the row measures.
pub const ADAPTIVE_START: f64 = 1e-2;

/// Knob values added near the leaderboard's threshold: where a rule's
/// admissibility ([`admissible`]) flips between two adjacent values of its grid, two
/// more log-spaced between them — three per decade there. `optimal` is not refined (one of
/// its rows costs minutes to an hour at 5 000 DOFs).
pub fn refinement_jobs(
    cfg: &BenchConfig,
    scene: &Indentation,
    scale: f64,
    rows: &[&BenchRow],
) -> Vec<BenchJob> {
    let mut out = Vec::new();
    for &s in cfg
        .methods
        .iter()
        .filter(|s| !std::ptr::eq(**s, &strategy::optimal::STRATEGY))
    {
        for knob in ["eps", "factor", "delta", "tol", "adaptive-tol"] {
            let mut grid: Vec<(f64, bool)> = rows
                .iter()
                .filter(|r| r.method == s.name && r.knob == knob)
                .filter_map(|r| r.knob_rel.map(|k| (k, admissible(r))))
                .collect();
            grid.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut new: Vec<f64> = Vec::new();
            for w in grid.windows(2) {
                if w[0].1 != w[1].1 {
                    let ratio = w[1].0 / w[0].0;
                    new.push(w[0].0 * ratio.powf(1.0 / 3.0));
                    new.push(w[0].0 * ratio.powf(2.0 / 3.0));
                }
            }
            if new.is_empty() {
                continue;
            }
            let sub = BenchConfig {
                methods: vec![s],
                eps_rel: new.clone(),
                factors: new.clone(),
                deltas_rel: new,
                ..cfg.clone()
            };
            out.extend(
                jobs(&sub, scene, scale)
                    .into_iter()
                    .filter(|j| j.knob == knob),
            );
        }
    }
    out
}

/// Solves `jobs` on one mesh in parallel, rows in job order, with progress.
pub(crate) fn solve_jobs(
    cfg: &BenchConfig,
    mesh: &Mesh<'_>,
    jobs: &[BenchJob],
    progress: &Progress,
    h_rel: f64,
) -> Vec<(BenchRow, Vec<f64>)> {
    let done = std::sync::atomic::AtomicUsize::new(0);
    jobs.par_iter()
        .map(|job| {
            let (row, p) = run_job(cfg, mesh, job);
            let k = 1 + done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let name = mesh.case.name();
            progress.message(format!("{name} h/a = {h_rel}: {k}/{} jobs", jobs.len()));
            if row.seconds >= LONG_JOB_S {
                let knob = row
                    .knob_rel
                    .map_or(String::new(), |v| format!(" {} {v:e} (relative)", row.knob));
                progress.note(&format!(
                    "  {name} h/a = {h_rel}: {}{knob} done in {:.0} s, {} solves",
                    row.method, row.seconds, row.force_solves
                ));
            }
            (row, p)
        })
        .collect()
}
