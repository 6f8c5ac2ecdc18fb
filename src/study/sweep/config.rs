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

/// Everything that determines the rows (the manifest stores it; `--resume` checks it). Names
/// are parsed once, where they enter (the TOML file, the command line): families, methods,
/// metrics and `optimal_families` are held typed and written back by name.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SweepConfig {
    /// Families to generate (ignored with `scenes_dir`).
    pub families: Vec<Family>,
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
    #[serde(
        serialize_with = "registry::serialize_names",
        deserialize_with = "registry::deserialize_names"
    )]
    pub methods: Vec<&'static strategy::Strategy>,
    /// Metrics: any of `cond`, `det`, `solver` (penetration, error and timing are always
    /// recorded).
    pub metrics: Vec<Metric>,
    /// Generator size ranges.
    pub generator: GeneratorConfig,
    /// Run over every `*.scene.json` in this folder instead of generating.
    pub scenes_dir: Option<PathBuf>,
    /// Families on which `optimal` runs (`file` for scene files); its rows on other families
    /// say so in `warnings`. The default, beam and files, keeps the default sweep under a
    /// minute: one optimisation costs tens to hundreds of dense eigendecompositions.
    pub optimal_families: Vec<Source>,
    /// Relative accuracy asked of every cond₂ (`--cond-tol`, in (0, 1)); `None` (the default):
    /// the accuracy contract `max(1e-12, 4·ε_mach·cond₂)`. A looser value stops the Lanczos
    /// runs earlier; the bounds stay proven and rows.csv records both (`cond_tol`, the bound
    /// columns).
    pub cond_tol: Option<f64>,
    /// With `metrics` holding `solver`: the relative error of u the Krylov counts
    /// `*_to_err` are taken to (`--krylov-err`, in (0, 1); default 1e-6).
    pub krylov_err: f64,
}

impl Default for SweepConfig {
    fn default() -> Self {
        SweepConfig {
            families: generate::DEFAULT_FAMILIES
                .iter()
                .map(|s| Family::from_name(s).expect("a default family is a family"))
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
                .copied()
                .filter(|s| s.bilateral)
                .collect(),
            metrics: vec![Metric::Cond, Metric::Det],
            generator: GeneratorConfig::default(),
            scenes_dir: None,
            optimal_families: vec![Source::Generated(Family::Beam), Source::Files],
            cond_tol: None,
            krylov_err: crate::metrics::solver::DEFAULT_ERR_TARGET,
        }
    }
}

/// Metric names accepted in `metrics`.
pub const METRIC_NAMES: [&str; 3] = ["cond", "det", "solver"];

/// A metric set of the sweep's rows ([`METRIC_NAMES`]; penetration, error and time are always
/// recorded).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    /// cond₂ of K and of every system, with proven bounds.
    Cond,
    /// log10|det| of K and of every system.
    Det,
    /// The solver-cost metrics ([`crate::metrics::solver`]).
    Solver,
}

impl Metric {
    /// Its name ([`METRIC_NAMES`]).
    pub fn name(self) -> &'static str {
        match self {
            Metric::Cond => "cond",
            Metric::Det => "det",
            Metric::Solver => "solver",
        }
    }

    /// Parses a metric name; the error lists the valid ones.
    pub fn from_name(name: &str) -> Result<Metric> {
        match name {
            "cond" => Ok(Metric::Cond),
            "det" => Ok(Metric::Det),
            "solver" => Ok(Metric::Solver),
            _ => Err(Error::unknown(
                "metric",
                name,
                &METRIC_NAMES,
                "; penetration, error and time are always recorded",
            )),
        }
    }
}

/// Where a scene comes from, as `optimal_families` names it: a generated family, or scene
/// files (`file`, the rows' family of a `--scenes-dir` run).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// Scenes generated from a family.
    Generated(Family),
    /// Scene files (`file`).
    Files,
}

impl Source {
    /// Parses `file` or a family name; the error lists the valid ones.
    pub fn from_name(name: &str) -> Result<Source> {
        match name {
            "file" => Ok(Source::Files),
            _ => Family::from_name(name)
                .map(Source::Generated)
                .map_err(|_| Error::unknown("family", name, &generate::FAMILY_NAMES, ", file")),
        }
    }

    /// The name (the rows' `family` column).
    pub fn name(self) -> &'static str {
        match self {
            Source::Generated(f) => f.name(),
            Source::Files => "file",
        }
    }
}

impl Serialize for Source {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Source {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Source::from_name(&name).map_err(|e| serde::de::Error::custom(e.bare_message()))
    }
}

/// A field of the configuration as a TOML file writes it: `(table, key)`, the table `None` at
/// the top level.
pub(super) type Field = (Option<&'static str>, &'static str);

impl SweepConfig {
    /// Reads a TOML config (fields as in [`SweepConfig`]; missing fields take defaults).
    pub fn from_toml_file(path: &Path) -> Result<Self> {
        crate::provenance::read_toml(path)
    }

    /// Validates names, ranges and knobs; errors name the problem and the valid choices.
    pub fn validate(&self) -> Result<()> {
        self.check().map_err(|(_, e)| e)
    }

    /// [`SweepConfig::validate`], each error with the field it is about — `(table, key)` as in
    /// a TOML file (`None` for two fields at once) — and naming the quantity, not a flag:
    /// [`ConfigArgs`](super::cli::ConfigArgs) names the flag where one set the value, else the
    /// file's key and line.
    pub(super) fn check(&self) -> std::result::Result<(), (Option<Field>, Error)> {
        let at = |key: &'static str| move |e: Error| (Some((None, key)), e);
        Error::distinct("families", self.families.iter().map(|f| f.name()))
            .map_err(at("families"))?;
        Error::distinct("methods", self.methods.iter().map(|s| s.name)).map_err(at("methods"))?;
        Error::distinct("metrics", self.metrics.iter().map(|m| m.name())).map_err(at("metrics"))?;
        Error::distinct(
            "optimal_families",
            self.optimal_families.iter().map(|s| s.name()),
        )
        .map_err(at("optimal_families"))?;
        Error::distinct("factors", &self.factors).map_err(at("factors"))?;
        Error::distinct("deltas", &self.deltas).map_err(at("deltas"))?;
        Error::distinct("deltas_rel", &self.deltas_rel).map_err(at("deltas_rel"))?;
        MetricSet::check_cond_tol(self.cond_tol).map_err(at("cond_tol"))?;
        Error::fraction("krylov_err", self.krylov_err).map_err(at("krylov_err"))?;
        if self.scenes_dir.is_none() {
            if self.families.is_empty() {
                return Err(at("families")(Error::none_given(
                    "families",
                    format!(" (valid: {})", generate::FAMILY_NAMES.join(", ")),
                )));
            }
            if self.count == 0 {
                return Err(at("count")(Error::out_of_range("count", 0, "≥ 1")));
            }
        }
        self.eps.validate().map_err(at("eps"))?;
        for (key, what, v) in [
            ("factors", "factor", &self.factors),
            ("deltas", "δ", &self.deltas),
            ("deltas_rel", "relative δ", &self.deltas_rel),
        ] {
            for &x in v {
                Error::positive(what, x).map_err(at(key))?;
            }
        }
        let with_knob = |knobs: &[Knob]| -> Vec<&str> {
            self.methods
                .iter()
                .filter(|s| knobs.contains(&s.knob))
                .map(|s| s.name)
                .collect()
        };
        let needs_delta = with_knob(&[Knob::Delta, Knob::EpsTol]);
        if !needs_delta.is_empty() && self.deltas.is_empty() && self.deltas_rel.is_empty() {
            return Err((
                None,
                Error::unsupported(needs_delta.join("/"), "δ values (--deltas or --deltas-rel)"),
            ));
        }
        let needs_factors = with_knob(&[Knob::Factor]);
        if !needs_factors.is_empty() && self.factors.is_empty() {
            return Err((
                None,
                Error::unsupported(needs_factors.join("/"), "--factors"),
            ));
        }
        self.generator
            .check()
            .map_err(|(key, e)| (Some((Some("generator"), key)), e))
    }

    pub(super) fn metric_set(&self) -> MetricSet {
        MetricSet {
            cond: self.metrics.contains(&Metric::Cond),
            det: self.metrics.contains(&Metric::Det),
            cond_tol: self.cond_tol,
        }
    }

    /// The solver-cost metrics' options where `metrics` has `solver` ([`crate::metrics::solver`]:
    /// τ = 1e-8, the error-based counts to `krylov_err`, cond₂ of the Jacobi-scaled system to
    /// `cond_tol`); `None` otherwise (the default: they cost nothing unless asked for).
    pub(super) fn solver_options(&self) -> Option<crate::metrics::solver::SolverOptions> {
        self.metrics
            .contains(&Metric::Solver)
            .then(|| crate::metrics::solver::SolverOptions {
                cond_tol: self.cond_tol,
                err_target: self.krylov_err,
                ..Default::default()
            })
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
        1 + self.knob_grid(1.0, 1.0).count(&self.methods)
    }
}
