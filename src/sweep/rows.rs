//! One CSV row per (scene, method, parameter). Empty cells where a column does not apply.
//!
//! Columns (in order): see [`COLUMNS`]. Units: `eps*` in stiffness units (force/length of the
//! scene), `delta` and `max_penetration` in the units of u, `seconds` wall time of the solve
//! plus metrics on one thread, split into `seconds_solve`, `seconds_cond` and `seconds_det`.
//! Every column except those four ([`TIMING_COLUMNS`]) is deterministic: identical for any
//! thread count and shard split.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A result row.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// Scene name (`family-index` or the scene file's name).
    pub scene: String,
    /// Family (`beam`, `membrane`, `spectrum`, or `file`).
    pub family: String,
    /// Number of DOFs N.
    pub n: usize,
    /// Number of constraints m.
    pub m: usize,
    /// Storage K was solved in, `dense` or `sparse`, chosen from its structure whatever the
    /// scene file stored ([`crate::system::Structure::prefers_sparse`]).
    pub storage: String,
    /// Nonzero entries of K.
    pub nnz: usize,
    /// Half-bandwidth of K (natural ordering).
    pub half_bandwidth: usize,
    /// Strategy name.
    pub method: String,
    /// Knob ε (constant, augmented).
    pub eps: Option<f64>,
    /// Knob factor (scaled).
    pub factor: Option<f64>,
    /// Knob δ, absolute (spring, paper, condensed; tolerance for augmented).
    pub delta: Option<f64>,
    /// δ relative to the scene's displacement scale max_c |u0\[d_c\]| (when given so).
    pub delta_rel: Option<f64>,
    /// Smallest nonzero penalty used.
    pub eps_min: Option<f64>,
    /// Largest penalty used.
    pub eps_max: Option<f64>,
    /// Number of penalized / active constraints at the end.
    pub active: Option<usize>,
    /// cond₂ of the final system matrix.
    pub cond2_system: Option<f64>,
    /// cond₂ of K.
    pub cond2_k: Option<f64>,
    /// Route of the system cond.
    pub cond_route: Option<String>,
    /// log10|det system| − log10|det K|.
    pub log10_det_ratio: Option<f64>,
    /// Max penetration.
    pub max_penetration: Option<f64>,
    /// ‖u − u_lagrange‖/‖u_lagrange‖.
    pub error_vs_exact: Option<f64>,
    /// Linear solves (right-hand sides).
    pub linear_solves: Option<usize>,
    /// Outer iterations.
    pub iterations: Option<usize>,
    /// The strategy's iteration reached its solution (`Stats::converged`); empty on error.
    pub converged: Option<bool>,
    /// Wall time of this row (s): the solve plus its metrics.
    pub seconds: Option<f64>,
    /// Wall time of the solve alone (s).
    pub seconds_solve: Option<f64>,
    /// Wall time of cond₂ of the system matrix (s).
    pub seconds_cond: Option<f64>,
    /// Wall time of the determinant ratio (s).
    pub seconds_det: Option<f64>,
    /// δ-driven rows (spring, paper, condensed, optimal): cond2_system over the cond₂ of
    /// `optimal` at the same scene and δ, where the optimum was computed (≥ 1 up to rounding
    /// for feasible rows; a rule whose penetration exceeds δ may go below 1).
    pub cond_ratio_to_optimal: Option<f64>,
    /// Warnings and errors, `; `-separated (empty when all is well).
    pub warnings: String,
}

/// Column names, in file order.
pub const COLUMNS: [&str; 30] = [
    "scene",
    "family",
    "n",
    "m",
    "storage",
    "nnz",
    "half_bandwidth",
    "method",
    "eps",
    "factor",
    "delta",
    "delta_rel",
    "eps_min",
    "eps_max",
    "active",
    "cond2_system",
    "cond2_K",
    "cond_route",
    "log10_det_ratio",
    "max_penetration",
    "error_vs_exact",
    "linear_solves",
    "iterations",
    "converged",
    "seconds",
    "seconds_solve",
    "seconds_cond",
    "seconds_det",
    "cond_ratio_to_optimal",
    "warnings",
];

/// The timing columns: the only ones that may differ between runs of the same configuration.
pub const TIMING_COLUMNS: [&str; 4] = ["seconds", "seconds_solve", "seconds_cond", "seconds_det"];

fn f(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:e}"),
        Some(v) if v.is_nan() => String::new(),
        Some(v) if v > 0.0 => "inf".into(),
        Some(_) => "-inf".into(),
        None => String::new(),
    }
}

fn u(x: Option<usize>) -> String {
    x.map(|v| v.to_string()).unwrap_or_default()
}

impl Row {
    /// The row's cells, in [`COLUMNS`] order.
    pub fn cells(&self) -> Vec<String> {
        vec![
            self.scene.clone(),
            self.family.clone(),
            self.n.to_string(),
            self.m.to_string(),
            self.storage.clone(),
            self.nnz.to_string(),
            self.half_bandwidth.to_string(),
            self.method.clone(),
            f(self.eps),
            f(self.factor),
            f(self.delta),
            f(self.delta_rel),
            f(self.eps_min),
            f(self.eps_max),
            u(self.active),
            f(self.cond2_system),
            f(self.cond2_k),
            self.cond_route.clone().unwrap_or_default(),
            f(self.log10_det_ratio),
            f(self.max_penetration),
            f(self.error_vs_exact),
            u(self.linear_solves),
            u(self.iterations),
            self.converged.map(|c| c.to_string()).unwrap_or_default(),
            f(self.seconds),
            f(self.seconds_solve),
            f(self.seconds_cond),
            f(self.seconds_det),
            f(self.cond_ratio_to_optimal),
            self.warnings.clone(),
        ]
    }

    /// The row without its timing (for determinism comparisons).
    pub fn without_timing(&self) -> Row {
        Row {
            seconds: None,
            seconds_solve: None,
            seconds_cond: None,
            seconds_det: None,
            ..self.clone()
        }
    }
}

/// Writes the header line.
pub fn header() -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    w.write_record(COLUMNS).expect("in-memory write");
    String::from_utf8(w.into_inner().expect("in-memory")).expect("utf8")
}

/// Formats rows as CSV lines (no header).
pub fn format_rows(rows: &[Row]) -> String {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    for r in rows {
        w.write_record(r.cells()).expect("in-memory write");
    }
    String::from_utf8(w.into_inner().expect("in-memory")).expect("utf8")
}

fn parse_opt<T: std::str::FromStr>(s: &str) -> std::result::Result<Option<T>, String> {
    if s.is_empty() {
        Ok(None)
    } else {
        s.parse::<T>()
            .map(Some)
            .map_err(|_| format!("bad number '{s}'"))
    }
}

/// Reads rows.csv. With `lenient`, a malformed last line (a run killed mid-write) is dropped
/// instead of being an error; the number of bytes of well-formed content is returned too.
pub fn read_rows(path: &Path, lenient: bool) -> Result<(Vec<Row>, usize)> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
    let mut lines = text.split_inclusive('\n');
    let head = lines
        .next()
        .ok_or_else(|| Error::io(path.display(), "empty file (no header)"))?;
    if head.trim_end() != header().trim_end() {
        return Err(Error::io(
            path.display(),
            "header does not match this version's columns",
        ));
    }
    let mut good = head.len();
    let mut rows = Vec::new();
    for (ln, line) in lines.enumerate() {
        let parsed = if line.ends_with('\n') {
            parse_line(line)
        } else {
            Err("truncated line".to_string())
        };
        match parsed {
            Ok(r) => {
                rows.push(r);
                good += line.len();
            }
            Err(e) if lenient => {
                let _ = e;
                break;
            }
            Err(e) => return Err(Error::io(path.display(), format!("line {}: {e}", ln + 2))),
        }
    }
    Ok((rows, good))
}

fn parse_line(line: &str) -> std::result::Result<Row, String> {
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(line.as_bytes());
    let rec = rd
        .records()
        .next()
        .ok_or("empty line")?
        .map_err(|e| e.to_string())?;
    if rec.len() != COLUMNS.len() {
        return Err(format!(
            "expected {} fields, found {}",
            COLUMNS.len(),
            rec.len()
        ));
    }
    let mut cells = rec.iter();
    let mut next = || cells.next().unwrap_or("");
    let fl = |s: &str| -> std::result::Result<Option<f64>, String> {
        match s {
            "inf" => Ok(Some(f64::INFINITY)),
            "-inf" => Ok(Some(f64::NEG_INFINITY)),
            s => parse_opt(s),
        }
    };
    let whole = |s: &str, what: &str| s.parse::<usize>().map_err(|_| format!("bad {what} '{s}'"));
    Ok(Row {
        scene: next().into(),
        family: next().into(),
        n: whole(next(), "n")?,
        m: whole(next(), "m")?,
        storage: next().into(),
        nnz: whole(next(), "nnz")?,
        half_bandwidth: whole(next(), "half_bandwidth")?,
        method: next().into(),
        eps: fl(next())?,
        factor: fl(next())?,
        delta: fl(next())?,
        delta_rel: fl(next())?,
        eps_min: fl(next())?,
        eps_max: fl(next())?,
        active: parse_opt(next())?,
        cond2_system: fl(next())?,
        cond2_k: fl(next())?,
        cond_route: Some(next().to_string()).filter(|s| !s.is_empty()),
        log10_det_ratio: fl(next())?,
        max_penetration: fl(next())?,
        error_vs_exact: fl(next())?,
        linear_solves: parse_opt(next())?,
        iterations: parse_opt(next())?,
        converged: {
            let c = next();
            parse_opt(c).map_err(|_| format!("bad converged '{c}'"))?
        },
        seconds: fl(next())?,
        seconds_solve: fl(next())?,
        seconds_cond: fl(next())?,
        seconds_det: fl(next())?,
        cond_ratio_to_optimal: fl(next())?,
        warnings: next().into(),
    })
}
