//! The printed report of forming runs: one line per run and the δ-rules against the classical
//! runs, step by step.

use super::diagnostic_only;
use super::record::SavedRuns;
use crate::forming::config::ContactRule;
use serde::Serialize;

/// One line per run: steps, Picard-converged steps, the largest final change of a step that
/// stopped at the cap (`-` if none did), median cond₂, final punch force, mean Picard
/// iterations, max penetration, clipped (Eq. 28 literal) or floored (Eq. 28 at the residual)
/// penalties, factorizations, seconds, validity; then what finding `classical-matched`'s ε cost
/// (its search's runs, factorizations and seconds, beside the one run in the table), the
/// comparisons, and one line per reason of an invalid run.
pub fn summary_table(doc: &SavedRuns) -> String {
    let mut out = format!(
        "{:<17} {:>5} {:>9} {:>10} {:>11} {:>11} {:>9} {:>12} {:>7} {:>7} {:>6} {:>6}\n",
        "run",
        "steps",
        "converged",
        "cap change",
        "median cond",
        "final force",
        "mean iter",
        "max pen (in)",
        "clipped",
        "factor.",
        "sec",
        "valid"
    );
    for (name, r) in &doc.runs {
        let c: Vec<f64> = r.steps.iter().map(|s| s.cond2).collect();
        let med = crate::stats::median(&c).unwrap_or(f64::NAN);
        let conv = r.steps.iter().filter(|s| s.converged).count();
        let capped = r
            .steps
            .iter()
            .filter(|s| !s.converged)
            .map(|s| s.picard_change)
            .fold(None, |a: Option<f64>, x| Some(a.map_or(x, |a| a.max(x))));
        let it: f64 =
            r.steps.iter().map(|s| s.iterations as f64).sum::<f64>() / r.steps.len().max(1) as f64;
        let pen = r
            .steps
            .iter()
            .map(|s| s.max_penetration)
            .fold(0.0, f64::max);
        let clip: usize = r.steps.iter().map(|s| s.clipped).sum();
        let f = r.steps.last().map_or(f64::NAN, |s| s.punch_force);
        let fact: usize = r.steps.iter().map(|s| s.factorizations).sum();
        out.push_str(&format!(
            "{name:<17} {:>5} {:>9} {:>10} {:>11.3e} {:>11.4} {:>9.1} {:>12.2e} {:>7} {:>7} {:>6.2} {:>6}\n",
            r.steps.len(),
            conv,
            capped.map_or("-".to_string(), |x| format!("{x:.2e}")),
            med,
            f,
            it,
            pen,
            clip,
            fact,
            r.seconds,
            if r.valid { "yes" } else { "NO" }
        ));
    }
    for (name, r) in &doc.runs {
        if let (Some(s), Some(eps)) = (r.search, r.eps) {
            out.push_str(&format!(
                "{name}: ε = {} found in {} trial run{} from the classical run's penetration \
                 (the last is the run above; {} factorizations, {:.2} s in all): a search a user \
                 without δ has to make\n",
                crate::study::text::fmt_e_trim(eps, 3),
                s.runs,
                if s.runs == 1 { "" } else { "s" },
                s.factorizations,
                s.seconds
            ));
        }
    }
    for c in comparisons(doc) {
        let name = if c.metric == "cond2" {
            "cond₂"
        } else {
            c.metric
        };
        let ties = if c.ties > 0 {
            format!(", {} ties", c.ties)
        } else {
            String::new()
        };
        out.push_str(&format!(
            "{} beats {} (ε = {}) in {}/{} steps{ties} (median {name} ratio {}/{} = {:.3})\n",
            c.rule,
            c.classical,
            crate::study::text::fmt_e_trim(c.eps, 3),
            c.wins,
            c.steps,
            c.classical,
            c.rule,
            c.median_ratio
        ));
    }
    for r in doc.runs.values() {
        for reason in &r.invalid_reasons {
            out.push_str(&format!("invalid: {reason}\n"));
        }
    }
    out
}

/// One δ-rule against one classical run, step by step, in one metric (lower is better).
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// The metric: `cond2`, `cond2_jacobi`, `pcg_iters_jacobi_to_err`, `pcg_iters_ic0_to_err`
    /// or `forward_err_u` ([`METRICS`]).
    pub metric: &'static str,
    /// The δ-rule's run (`adaptive`, `condensed`).
    pub rule: String,
    /// The classical run (`classical`, `classical-matched`).
    pub classical: String,
    /// The classical run's ε.
    pub eps: f64,
    /// Steps where the δ-rule's value is below the classical run's.
    pub wins: usize,
    /// Steps where the two are equal (iteration counts often are).
    pub ties: usize,
    /// Steps compared (both runs have them, with the metric).
    pub steps: usize,
    /// Median over the steps of value(classical) / value(rule): > 1 = the δ-rule is better.
    pub median_ratio: f64,
}

/// Reads one metric off a step (`None` where the step does not have it).
type StepMetric = fn(&crate::forming::solver::StepRecord) -> Option<f64>;

/// The metrics the δ-rules are compared in, each lower-is-better: cond₂ of the system (the
/// paper's), after Jacobi scaling, CG iterations with Jacobi and with IC(0) to the fixed error
/// of the velocities (steps whose run missed it left out), and the forward error of the direct
/// solve.
pub const METRICS: [(&str, StepMetric); 5] = [
    ("cond2", |s| Some(s.cond2)),
    ("cond2_jacobi", |s| Some(s.cond2_jacobi)),
    ("pcg_iters_jacobi_to_err", |s| {
        s.jacobi_iters_to_err().map(|i| i as f64)
    }),
    ("pcg_iters_ic0_to_err", |s| {
        s.ic0_iters_to_err().map(|i| i as f64)
    }),
    ("forward_err_u", |s| Some(s.forward_err_u)),
];

/// Every δ-rule of the document (not the diagnostic `paper-literal`) against every classical
/// run, in every metric of [`METRICS`]: in how many steps its value is lower, and the median
/// ratio — the paper's claim, stated against the classical penalty of the paper (ε = 1e7, far
/// more accurate than δ) and against `classical-matched` (the same accuracy).
pub fn comparisons(doc: &SavedRuns) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (metric, get) in METRICS {
        for (cname, c) in &doc.runs {
            let ContactRule::Classical { eps } = c.rule else {
                continue;
            };
            for (rname, r) in &doc.runs {
                if matches!(r.rule, ContactRule::Classical { .. }) || diagnostic_only(&r.rule) {
                    continue;
                }
                let pairs: Vec<(f64, f64)> = c
                    .steps
                    .iter()
                    .zip(&r.steps)
                    .filter_map(|(a, b)| Some((get(a)?, get(b)?)))
                    .filter(|(a, b)| a.is_finite() && b.is_finite())
                    .collect();
                if pairs.is_empty() {
                    continue;
                }
                let ratios: Vec<f64> = pairs.iter().map(|(a, b)| a / b).collect();
                out.push(Comparison {
                    metric,
                    rule: rname.clone(),
                    classical: cname.clone(),
                    eps,
                    wins: pairs.iter().filter(|(a, b)| b < a).count(),
                    ties: pairs.iter().filter(|(a, b)| a == b).count(),
                    steps: pairs.len(),
                    median_ratio: crate::stats::median(&ratios).unwrap_or(f64::NAN),
                });
            }
        }
    }
    out
}
