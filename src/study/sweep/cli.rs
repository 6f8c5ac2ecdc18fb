//! The sweep's configuration on the command line: flags that override a TOML file or the
//! built-in default (`SweepConfig`), shared by every binary that runs a sweep.

use super::{LogGrid, SweepConfig};
use crate::error::Result;
use std::path::PathBuf;

/// Command-line overrides of a [`SweepConfig`] (flattened into a binary's clap arguments).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ConfigArgs {
    /// TOML config (fields of SweepConfig); command-line flags override it.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Run over every *.scene.json in DIR instead of generating scenes.
    #[arg(long, value_name = "DIR")]
    scenes_dir: Option<PathBuf>,
    /// Families, comma-separated: beam, membrane, spectrum (the default), hertz, flat-punch (or patch, its old name).
    #[arg(long, value_delimiter = ',')]
    families: Option<Vec<String>>,
    /// Scenes per family.
    #[arg(long)]
    count: Option<usize>,
    /// Master seed (ChaCha8 streams per scene).
    #[arg(long)]
    seed: Option<u64>,
    /// ε grid for `constant`: LO:HI:N, log-spaced, inclusive.
    #[arg(long, value_name = "LO:HI:N")]
    eps: Option<String>,
    /// Factors for `scaled`, comma-separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    factors: Option<Vec<f64>>,
    /// Absolute δ values, comma-separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    deltas: Option<Vec<f64>>,
    /// Relative δ values R, comma-separated: δ = R times the largest unconstrained displacement at a constrained DOF.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    deltas_rel: Option<Vec<f64>>,
    /// Methods, comma-separated (lagrange always runs as the reference).
    #[arg(long, value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Metrics, comma-separated: cond, det ("none" for neither).
    #[arg(long, value_delimiter = ',')]
    metrics: Option<Vec<String>>,
    /// Relative accuracy asked of every cond₂, in (0, 1) (default: the accuracy contract,
    /// max(1e-12, 4·ε_mach·cond₂)); looser is faster, the bounds stay proven.
    #[arg(long, allow_negative_numbers = true)]
    cond_tol: Option<f64>,
}

impl ConfigArgs {
    /// The configuration: the TOML file (or the default) with every given flag applied,
    /// validated. Absolute δs given alone replace the relative ones and vice versa.
    pub fn config(&self) -> Result<SweepConfig> {
        let a = self;
        let mut c = match &a.config {
            Some(p) => SweepConfig::from_toml_file(p)?,
            None => SweepConfig::default(),
        };
        if let Some(v) = &a.families {
            c.families = v.iter().map(|s| s.trim().to_string()).collect();
        }
        if let Some(v) = a.count {
            c.count = v;
        }
        if let Some(v) = a.seed {
            c.seed = v;
        }
        if let Some(v) = &a.eps {
            c.eps = LogGrid::parse(v)?;
        }
        if let Some(v) = &a.factors {
            c.factors = v.clone();
        }
        if let Some(v) = &a.deltas {
            c.deltas = v.clone();
            if a.deltas_rel.is_none() {
                c.deltas_rel.clear();
            }
        }
        if let Some(v) = &a.deltas_rel {
            c.deltas_rel = v.clone();
            if a.deltas.is_none() {
                c.deltas.clear();
            }
        }
        if let Some(v) = &a.methods {
            c.methods = v.iter().map(|s| s.trim().to_string()).collect();
        }
        if let Some(v) = &a.metrics {
            c.metrics = v
                .iter()
                .map(|s| s.trim().to_string())
                .filter(|s| s != "none")
                .collect();
        }
        if let Some(t) = a.cond_tol {
            c.cond_tol = Some(t);
        }
        if let Some(d) = &a.scenes_dir {
            c.scenes_dir = Some(d.clone());
        }
        c.validate()?;
        Ok(c)
    }
}
