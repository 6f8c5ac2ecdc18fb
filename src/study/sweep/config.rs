//! The sweep's configuration: what determines the rows ([`SweepConfig`]), its ε grid and
//! its checks.

use crate::error::{Error, Result};
use crate::generate::{self, Family, GeneratorConfig};
use crate::metrics::MetricSet;
use crate::strategy::{self, registry, Knob};
pub use crate::study::grid::LogGrid;
use crate::study::grid::{Augmented, KnobGrid, Level};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Everything that determines the rows (the manifest stores it; `--resume` checks it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SweepConfig {
    /// Families to generate (ignored with `scenes_dir`).
    pub families: Vec<String>,
    /// Scenes per family.
    pub count: usize,
    /// Master seed.
    pub seed: u64,
    /// ε grid for `constant`.
    pub eps: LogGrid,
    /// Factors for `scaled`.
    pub factors: Vec<f64>,
    /// Absolute δ values.
    pub deltas: Vec<f64>,
    /// Relative δ values (δ = R · max_c |u0\[d_c\]|).
    pub deltas_rel: Vec<f64>,
    /// Methods to run (`lagrange` always runs: it is the reference).
    pub methods: Vec<String>,
    /// Metrics: any of `cond`, `det` (penetration, error and timing are always recorded).
    pub metrics: Vec<String>,
    /// Generator size ranges.
    pub generator: GeneratorConfig,
    /// Run over every `*.scene.json` in this folder instead of generating.
    pub scenes_dir: Option<PathBuf>,
    /// Families on which `optimal` runs (`file` for scene files); its rows on other families
    /// say so in `warnings`. The default, beam and files, keeps the default sweep under a
    /// minute: one optimisation costs tens to hundreds of dense eigendecompositions.
    pub optimal_families: Vec<String>,
    /// Relative accuracy asked of every cond₂ (`--cond-tol`, in (0, 1)); `None` (the default):
    /// the accuracy contract `max(1e-12, 4·ε_mach·cond₂)`. A looser value stops the Lanczos
    /// runs earlier; the bounds stay proven and rows.csv records both (`cond_tol`, the bound
    /// columns).
    pub cond_tol: Option<f64>,
}

impl Default for SweepConfig {
    fn default() -> Self {
        SweepConfig {
            families: generate::DEFAULT_FAMILIES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            count: 8,
            seed: 2011,
            eps: LogGrid {
                lo: 1e-2,
                hi: 1e12,
                n: 15,
            },
            factors: vec![1.0, 10.0, 100.0, 1e3, 1e4],
            deltas: vec![],
            deltas_rel: vec![1e-1, 1e-2, 1e-3],
            // The default families tie 30 % of their constraints bilaterally.
            methods: registry::BUILT_IN
                .iter()
                .filter(|s| s.bilateral)
                .map(|s| s.name.to_string())
                .collect(),
            metrics: vec!["cond".into(), "det".into()],
            generator: GeneratorConfig::default(),
            scenes_dir: None,
            optimal_families: vec!["beam".into(), "file".into()],
            cond_tol: None,
        }
    }
}

/// Metric names accepted in `metrics`.
pub const METRIC_NAMES: [&str; 3] = ["cond", "det", "solver"];

impl SweepConfig {
    /// Reads a TOML config (fields as in [`SweepConfig`]; missing fields take defaults).
    pub fn from_toml_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
        let cfg: SweepConfig = toml::from_str(&text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            let msg = e.message().replace('\n', " ");
            match line {
                Some(l) => Error::parse(path.display(), l, msg),
                None => Error::io(path.display(), msg),
            }
        })?;
        Ok(cfg)
    }

    /// Validates names, ranges and knobs; errors name the problem and the valid choices.
    pub fn validate(&self) -> Result<()> {
        MetricSet::check_cond_tol(self.cond_tol).map_err(|e| e.for_flag("--cond-tol"))?;
        if self.scenes_dir.is_none() {
            if self.families.is_empty() {
                return Err(Error::input(format!(
                    "no families given (valid: {})",
                    generate::FAMILY_NAMES.join(", ")
                )));
            }
            for f in &self.families {
                Family::from_name(f)?;
            }
            if self.count == 0 {
                return Err(Error::input("--count must be ≥ 1"));
            }
        }
        for m in &self.methods {
            registry::lookup(m)?;
        }
        for f in &self.optimal_families {
            if f != "file" && Family::from_name(f).is_err() {
                return Err(
                    Error::unknown("family", f, &generate::FAMILY_NAMES, ", file")
                        .for_flag("optimal_families"),
                );
            }
        }
        for m in &self.metrics {
            if !METRIC_NAMES.contains(&m.as_str()) {
                return Err(Error::unknown(
                    "metric",
                    m,
                    &METRIC_NAMES,
                    "; penetration, error and time are always recorded",
                ));
            }
        }
        self.eps.validate()?;
        for (what, v) in [
            ("factor", &self.factors),
            ("δ (--deltas)", &self.deltas),
            ("relative δ (--deltas-rel)", &self.deltas_rel),
        ] {
            for &x in v {
                Error::positive(what, x)?;
            }
        }
        let with_knob = |knobs: &[Knob]| -> Vec<&str> {
            self.strategies()
                .into_iter()
                .filter(|s| knobs.contains(&s.knob))
                .map(|s| s.name)
                .collect()
        };
        let needs_delta = with_knob(&[Knob::Delta, Knob::EpsTol]);
        if !needs_delta.is_empty() && self.deltas.is_empty() && self.deltas_rel.is_empty() {
            return Err(Error::input(format!(
                "{} need δ values (--deltas or --deltas-rel)",
                needs_delta.join("/")
            )));
        }
        let needs_factors = with_knob(&[Knob::Factor]);
        if !needs_factors.is_empty() && self.factors.is_empty() {
            return Err(Error::input(format!(
                "{} needs --factors",
                needs_factors.join("/")
            )));
        }
        self.generator.validate()
    }

    pub(super) fn metric_set(&self) -> MetricSet {
        MetricSet {
            cond: self.metrics.iter().any(|m| m == "cond"),
            det: self.metrics.iter().any(|m| m == "det"),
            cond_tol: self.cond_tol,
        }
    }

    /// The solver-cost metrics' options where `metrics` has `solver` ([`crate::metrics::solver`]:
    /// τ = 1e-8, cond₂ of the Jacobi-scaled system to `cond_tol`); `None` otherwise (the
    /// default: they cost nothing unless asked for).
    pub(super) fn solver_options(&self) -> Option<crate::metrics::solver::SolverOptions> {
        self.metrics
            .iter()
            .any(|m| m == "solver")
            .then(|| crate::metrics::solver::SolverOptions {
                cond_tol: self.cond_tol,
                ..Default::default()
            })
    }

    /// The strategies of `methods` (unknown names, which [`SweepConfig::validate`] refuses,
    /// left out).
    pub fn strategies(&self) -> Vec<&'static strategy::Strategy> {
        self.methods
            .iter()
            .filter_map(|m| registry::find(m))
            .collect()
    }

    /// The knob grid of a scene whose displacement scale is `scale` (the relative δs multiply
    /// it) and whose `augmented` runs at ε = `aug_eps`: ε on the log grid, the factors, δ
    /// absolute then relative, `augmented` at each δ as its tolerance with the adaptive update;
    /// no exact method (lagrange is every scene's first row).
    pub fn knob_grid(&self, scale: f64, aug_eps: f64) -> KnobGrid {
        let deltas: Vec<Level> = self
            .deltas
            .iter()
            .map(|&d| Level::absolute(d))
            .chain(Level::relatives(&self.deltas_rel, scale))
            .collect();
        KnobGrid {
            eps: self.eps.values().into_iter().map(Level::absolute).collect(),
            factors: self.factors.iter().map(|&f| Level::absolute(f)).collect(),
            tols: deltas.clone(),
            deltas,
            augmented: vec![Augmented {
                eps: aug_eps,
                adaptive: true,
                name: "tol",
            }],
            exact: None,
        }
    }

    /// Rows produced per scene: the lagrange reference and the grid's points.
    pub fn rows_per_scene(&self) -> usize {
        1 + self.knob_grid(1.0, 1.0).count(&self.strategies())
    }
}
