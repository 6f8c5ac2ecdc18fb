//! The `contact_bench` binary's flags and the study as the shared entry runs it
//! ([`crate::study::shape::main`]): flags → [`BenchConfig`] here, nowhere else.

use super::{analytic::Case, figures, BenchConfig, Summary};
use crate::error::{Error, Result};
use crate::strategy::registry;
use crate::study::checkpoint::Checkpoints;
use crate::study::shape::{Drawing, RunContext, Study};
use std::path::Path;

/// The checkpoint folder under `--out` (one file per case and mesh).
const CHECKPOINTS: &str = "meshes";

/// The `contact_bench` binary's flags (each replaces the default of [`BenchConfig`]).
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Cases: hertz-plane, hertz-axi, flat-punch, inclined-15, inclined-30, inclined-45,
    /// patch-two-body-mortar, patch-two-body-nts-1 (the default: these), hertz-two-body (an
    /// elastic cylinder on the block, ≈ 1 min on 2 cores), hertz-normals (the rigid
    /// cylinder with rows along its nodal normals) and patch-two-body-nts-2 (two-pass
    /// node-to-segment: Lagrange refuses its dependent rows, so no penalty error), asked for
    /// by name; `patch` reads as flat-punch.
    #[arg(long, value_delimiter = ',')]
    cases: Option<Vec<String>>,
    /// Element sizes at the contact over a (Hertz) or over the block half-width (flat punch).
    #[arg(long, value_delimiter = ',')]
    meshes: Option<Vec<f64>>,
    /// Methods (default: every registered one but `spring`, which carries no load here and
    /// fails on every row: `BenchConfig::default_methods`).
    #[arg(long, value_parser = registry::method_parser(), value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// `constant`: ε grid over E*/a (E* = E/(1 − ν²)): ε per unit contact length/area.
    #[arg(long, value_delimiter = ',')]
    eps_rel: Option<Vec<f64>>,
    /// `scaled`: factors f of ε_c = f·K_dd (d the constraint's DOF).
    #[arg(long, value_delimiter = ',')]
    factors: Option<Vec<f64>>,
    /// δ-rules, barrier d̂ and augmented tolerances over the case's length scale (a; the
    /// flat punch's compression).
    #[arg(long, value_delimiter = ',')]
    deltas_rel: Option<Vec<f64>>,
    /// `optimal` runs on meshes of at most this many DOFs (default 100, at most 20000; one
    /// δ took 60–132 s at 2 211 DOFs, 8–64 min at 5 253 on 2 cores: see `--resume`).
    #[arg(long)]
    optimal_max_n: Option<usize>,
    /// Relative accuracy asked of cond₂.
    #[arg(long)]
    cond_tol: Option<f64>,
    /// Hertz block size over a (default 16; the domain study's blocks are fixed).
    #[arg(long)]
    block_over_a: Option<f64>,
    /// Elements across the second body per elements across the first in the two-body cases,
    /// UPPER:LOWER (default 7:4; e.g. 3:2, 5:3, 7:4 for the patch test's 2:3, 3:5, 4:7).
    #[arg(long, value_parser = crate::study::grid::parse_ratio)]
    mesh_ratio: Option<(usize, usize)>,
    /// Write every solved row of the single-body cases (hertz-plane, hertz-axi, flat-punch,
    /// hertz-normals) as a VTK file `DIR/<case>_h<h>_<method>[_<knob><value>].vtu`: u, the
    /// contact pressure and gap per node (ParaView, meshio). The folder must not hold `.vtu`
    /// files already.
    #[arg(long, value_name = "DIR")]
    vtk: Option<std::path::PathBuf>,
}

impl Flags {
    /// The configuration these flags ask for, validated.
    pub fn config(&self) -> Result<BenchConfig> {
        let mut cfg = BenchConfig::default();
        if let Some(cs) = &self.cases {
            cfg.cases = cs
                .iter()
                .map(|c| {
                    Case::from_name(c).ok_or_else(|| {
                        let names: Vec<&str> = Case::ALL.iter().map(|c| c.name()).collect();
                        Error::unknown("case", c, &names, "").for_flag("--cases")
                    })
                })
                .collect::<Result<_>>()?;
        }
        if let Some(m) = &self.meshes {
            cfg.meshes = m.clone();
        }
        if let Some(m) = &self.methods {
            cfg.methods = registry::lookup_all(m)?;
        }
        for (grid, v) in [
            (&mut cfg.eps_rel, &self.eps_rel),
            (&mut cfg.factors, &self.factors),
            (&mut cfg.deltas_rel, &self.deltas_rel),
        ] {
            if let Some(v) = v {
                *grid = v.clone();
            }
        }
        if let Some(n) = self.optimal_max_n {
            cfg.optimal_max_n = n;
        }
        if let Some(t) = self.cond_tol {
            cfg.cond_tol = t;
        }
        if let Some(b) = self.block_over_a {
            cfg.block_over_a = b;
        }
        if let Some(r) = self.mesh_ratio {
            cfg.mesh_ratio = r;
        }
        // A case's own flag with none of its cases selected would be ignored: refused.
        let hertz = |c: &Case| !c.is_uniform();
        for (flag, given, uses) in [
            (
                "--block-over-a",
                self.block_over_a.is_some(),
                &hertz as &dyn Fn(&Case) -> bool,
            ),
            ("--mesh-ratio", self.mesh_ratio.is_some(), &|c: &Case| {
                c.two_bodies()
            }),
        ] {
            if given && !cfg.cases.iter().any(uses) {
                let names: Vec<&str> = Case::ALL
                    .iter()
                    .filter(|c| uses(c))
                    .map(|c| c.name())
                    .collect();
                return Err(Error::unsupported(
                    flag,
                    format!("one of the cases {} among --cases", names.join(", ")),
                ));
            }
        }
        cfg.validate()?;
        // Last, after every check: the folder is created here.
        if let Some(dir) = &self.vtk {
            if !cfg.cases.iter().any(|c| c.vtk_base().is_some()) {
                return Err(Error::unsupported(
                    "--vtk",
                    "one of the cases hertz-plane, hertz-axi, flat-punch, hertz-normals among --cases",
                ));
            }
            crate::vtk::check_empty_dir(dir).map_err(|e| e.for_flag("--vtk"))?;
            cfg.vtk = Some(dir.clone());
        }
        Ok(cfg)
    }
}

/// The study as the shared entry runs it.
pub struct ContactBench;

impl Study for ContactBench {
    const NAME: &'static str = "contact_bench";
    const ABOUT: &'static str =
        "Contact rules against Hertz and a flat punch: pressure errors, cond2, leaderboard";
    const PROGRESS: &'static str = "contact_bench (meshes)";
    const DEFAULT_OUT: &'static str = "results/contact_bench";
    const RESUMABLE: bool = true;
    type Flags = Flags;
    type Config = BenchConfig;
    type Record = Summary;

    fn config(flags: &Flags) -> Result<BenchConfig> {
        flags.config()
    }

    /// Runs with the checkpoints of `OUT/meshes/` (reused with `--resume`).
    fn run(cfg: &BenchConfig, ctx: &RunContext) -> Result<Summary> {
        let checkpoints = Checkpoints::new(ctx.out, CHECKPOINTS, cfg, ctx.resume)?;
        let run = super::run(cfg, ctx.progress, Some(&checkpoints))?;
        Ok(super::summary(cfg, run, ctx.provenance))
    }

    /// Writes the record, then removes the checkpoints it makes redundant.
    fn save(
        out: &Path,
        _cfg: &BenchConfig,
        summary: &Summary,
        _provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        super::save(out, summary)?;
        Checkpoints::remove_in(out, CHECKPOINTS)
    }

    fn load(out: &Path) -> Result<Summary> {
        super::load(out)
    }

    fn figures(summary: &Summary) -> Result<Vec<Drawing>> {
        figures::drawings(summary)
    }

    fn after_help() -> String {
        "Exit status: 0 ok, 2 bad configuration or input, 3 a run outside its model, 4 a \
         method failed on every mesh it ran on (rows and figures written; the report names \
         its first error)."
            .into()
    }

    fn report(summary: &Summary) -> String {
        super::tables(summary)
    }

    /// Exit status 4 where a method failed on every mesh it ran on (skipped rows aside).
    fn failure(summary: &Summary) -> Option<String> {
        super::report::tally(summary).all_failed()
    }

    fn json(summary: &Summary) -> Result<String> {
        crate::provenance::json_text("contact_bench summary", summary)
    }
}
