//! One CSV row per (scene, method, parameter). Empty cells where a column does not apply.
//!
//! Columns (in order): see [`COLUMNS`]. Units: `eps*` in stiffness units (force/length of the
//! scene), `delta` and `max_penetration` in the units of u, `seconds` wall time of the solve
//! plus metrics on one thread, split into `seconds_solve`, `seconds_cond` and `seconds_det`
//! (the lagrange row's `seconds` also holds the scene's bottom start for the penalized rows'
//! cond₂, [`crate::metrics::contact_bottom`]). Every column except those four ([`TIMING_COLUMNS`]) is deterministic: identical for any
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
    /// scene file stored ([`crate::route::Structure::prefers_sparse`]).
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
    /// Lower bound of cond₂ of the system matrix ([`crate::conditioning::CondReport`]).
    pub cond2_system_lo: Option<f64>,
    /// Upper bound of cond₂ of the system matrix.
    pub cond2_system_hi: Option<f64>,
    /// Lower bound of cond₂(K).
    pub cond2_k_lo: Option<f64>,
    /// Upper bound of cond₂(K).
    pub cond2_k_hi: Option<f64>,
    /// The relative accuracy asked of the cond₂ values (`--cond-tol`; empty: the contract).
    pub cond_tol: Option<f64>,
    /// Route of the system cond.
    pub cond_route: Option<String>,
    /// Every cond₂ bracket of the row (K's and the system's) is proven
    /// ([`crate::conditioning::CondReport::bounds_proven`]); empty where no cond₂ was taken.
    pub cond2_bounds_proven: Option<bool>,
    /// Every cond₂ value of the row is proven within the accuracy contract
    /// `max(1e-12, 4·ε_mach·cond₂)` ([`crate::conditioning::CondReport::within_contract`]).
    pub cond2_within_contract: Option<bool>,
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
    /// `barrier` rows: its stiffness κ at the first Newton solve (the rule's own second knob,
    /// [`crate::strategy::barrier::KappaReport`]); empty for other rules.
    pub kappa_initial: Option<f64>,
    /// `barrier` rows: κ of the returned solve.
    pub kappa_final: Option<f64>,
    /// `barrier` rows: times κ was doubled.
    pub kappa_increases: Option<usize>,
    /// The strategy's iteration reached its solution (`Stats::converged`); empty on error.
    pub converged: Option<bool>,
    /// Wall time of this row (s): the solve plus its metrics (the lagrange row: plus the
    /// scene's bottom start, [`crate::metrics::contact_bottom`]).
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
    /// `--metrics solver` ([`crate::metrics::solver`]; empty otherwise): cond₂ of the
    /// Jacobi-scaled system.
    pub cond2_jacobi: Option<f64>,
    /// CG iterations with Jacobi from 0 to ‖r‖ ≤ 1e-8‖b‖ (penalties; a residual test, not an
    /// accuracy: compare rules by `pcg_iters_jacobi_to_err`).
    pub pcg_iters_jacobi: Option<usize>,
    /// CG iterations with IC(0), the same test (penalties).
    pub pcg_iters_ic0: Option<usize>,
    /// Both CG runs reached τ.
    pub pcg_converged: Option<bool>,
    /// MINRES iterations (lagrange).
    pub minres_iters: Option<usize>,
    /// CG iterations with Jacobi from 0 to ‖u_k − u*‖∞ ≤ 1e-6‖u*‖∞ (u* the refined direct
    /// solution; penalties): the count that compares rules at equal accuracy.
    pub pcg_iters_jacobi_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_jacobi_to_err_converged: Option<bool>,
    /// CG iterations with IC(0) to the same error of u (penalties).
    pub pcg_iters_ic0_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_ic0_to_err_converged: Option<bool>,
    /// MINRES iterations to the same error of u (lagrange).
    pub minres_iters_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub minres_iters_to_err_converged: Option<bool>,
    /// CG iterations with scalar smoothed-aggregation AMG (B = ones, one V-cycle per
    /// application, [`crate::linalg::amg`]) to the same error of u (penalties).
    pub pcg_iters_amg_scalar_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_amg_scalar_to_err_converged: Option<bool>,
    /// CG iterations with nodal AMG (the scene's near-null space and block size) to the same
    /// error of u (penalties; empty where the scene gives no near-null space).
    pub pcg_iters_amg_nodal_to_err: Option<usize>,
    /// Whether that run reached the error target.
    pub pcg_iters_amg_nodal_to_err_converged: Option<bool>,
    /// Relative error of the plain direct solve's u against its double-double refinement.
    pub forward_err_u: Option<f64>,
    /// The same for the contact forces.
    pub forward_err_force: Option<f64>,
    /// Wall time of the solver-cost metrics (s).
    pub seconds_solver: Option<f64>,
    /// Warnings and errors, `; `-separated (empty when all is well).
    pub warnings: String,
}

/// Column names, in file order.
pub const COLUMNS: [&str; 58] = [
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
    "cond2_system_lo",
    "cond2_system_hi",
    "cond2_K_lo",
    "cond2_K_hi",
    "cond_tol",
    "cond_route",
    "cond2_bounds_proven",
    "cond2_within_contract",
    "log10_det_ratio",
    "max_penetration",
    "error_vs_exact",
    "linear_solves",
    "iterations",
    "kappa_initial",
    "kappa_final",
    "kappa_increases",
    "converged",
    "seconds",
    "seconds_solve",
    "seconds_cond",
    "seconds_det",
    "cond_ratio_to_optimal",
    "cond2_jacobi",
    "pcg_iters_jacobi",
    "pcg_iters_ic0",
    "pcg_converged",
    "minres_iters",
    "pcg_iters_jacobi_to_err",
    "pcg_iters_jacobi_to_err_converged",
    "pcg_iters_ic0_to_err",
    "pcg_iters_ic0_to_err_converged",
    "minres_iters_to_err",
    "minres_iters_to_err_converged",
    "pcg_iters_amg_scalar_to_err",
    "pcg_iters_amg_scalar_to_err_converged",
    "pcg_iters_amg_nodal_to_err",
    "pcg_iters_amg_nodal_to_err_converged",
    "forward_err_u",
    "forward_err_force",
    "seconds_solver",
    "warnings",
];

/// The timing columns: the only ones that may differ between runs of the same configuration.
pub const TIMING_COLUMNS: [&str; 5] = [
    "seconds",
    "seconds_solve",
    "seconds_cond",
    "seconds_det",
    "seconds_solver",
];

/// One cell per column, written straight into the CSV writer: numbers are formatted into a
/// reused buffer (`{:e}` for floats, so they read back bit for bit), never one `String` per
/// cell (a third less time than one `String` per cell; docs/history/performance-log.md).
struct Cells<'a, W: std::io::Write> {
    w: &'a mut csv::Writer<W>,
    buf: &'a mut String,
}

impl<W: std::io::Write> Cells<'_, W> {
    fn text(&mut self, s: &str) -> csv::Result<()> {
        self.w.write_field(s)
    }

    fn float(&mut self, x: Option<f64>) -> csv::Result<()> {
        use std::fmt::Write as _;
        self.buf.clear();
        match x {
            Some(v) if v.is_finite() => {
                write!(self.buf, "{v:e}").expect("formatting into a String")
            }
            Some(v) if v.is_nan() => {}
            Some(v) if v > 0.0 => self.buf.push_str("inf"),
            Some(_) => self.buf.push_str("-inf"),
            None => {}
        }
        self.w.write_field(self.buf.as_bytes())
    }

    fn whole(&mut self, x: Option<usize>) -> csv::Result<()> {
        use std::fmt::Write as _;
        self.buf.clear();
        if let Some(v) = x {
            write!(self.buf, "{v}").expect("formatting into a String");
        }
        self.w.write_field(self.buf.as_bytes())
    }
}

impl Row {
    /// Writes the row as one CSV record, cells in [`COLUMNS`] order; `buf` is scratch space.
    fn write_record<W: std::io::Write>(
        &self,
        w: &mut csv::Writer<W>,
        buf: &mut String,
    ) -> csv::Result<()> {
        let mut c = Cells { w, buf };
        c.text(&self.scene)?;
        c.text(&self.family)?;
        c.whole(Some(self.n))?;
        c.whole(Some(self.m))?;
        c.text(&self.storage)?;
        c.whole(Some(self.nnz))?;
        c.whole(Some(self.half_bandwidth))?;
        c.text(&self.method)?;
        c.float(self.eps)?;
        c.float(self.factor)?;
        c.float(self.delta)?;
        c.float(self.delta_rel)?;
        c.float(self.eps_min)?;
        c.float(self.eps_max)?;
        c.whole(self.active)?;
        c.float(self.cond2_system)?;
        c.float(self.cond2_k)?;
        c.float(self.cond2_system_lo)?;
        c.float(self.cond2_system_hi)?;
        c.float(self.cond2_k_lo)?;
        c.float(self.cond2_k_hi)?;
        c.float(self.cond_tol)?;
        c.text(self.cond_route.as_deref().unwrap_or(""))?;
        c.text(flag(self.cond2_bounds_proven))?;
        c.text(flag(self.cond2_within_contract))?;
        c.float(self.log10_det_ratio)?;
        c.float(self.max_penetration)?;
        c.float(self.error_vs_exact)?;
        c.whole(self.linear_solves)?;
        c.whole(self.iterations)?;
        c.float(self.kappa_initial)?;
        c.float(self.kappa_final)?;
        c.whole(self.kappa_increases)?;
        c.text(flag(self.converged))?;
        c.float(self.seconds)?;
        c.float(self.seconds_solve)?;
        c.float(self.seconds_cond)?;
        c.float(self.seconds_det)?;
        c.float(self.cond_ratio_to_optimal)?;
        c.float(self.cond2_jacobi)?;
        c.whole(self.pcg_iters_jacobi)?;
        c.whole(self.pcg_iters_ic0)?;
        c.text(flag(self.pcg_converged))?;
        c.whole(self.minres_iters)?;
        c.whole(self.pcg_iters_jacobi_to_err)?;
        c.text(flag(self.pcg_iters_jacobi_to_err_converged))?;
        c.whole(self.pcg_iters_ic0_to_err)?;
        c.text(flag(self.pcg_iters_ic0_to_err_converged))?;
        c.whole(self.minres_iters_to_err)?;
        c.text(flag(self.minres_iters_to_err_converged))?;
        c.whole(self.pcg_iters_amg_scalar_to_err)?;
        c.text(flag(self.pcg_iters_amg_scalar_to_err_converged))?;
        c.whole(self.pcg_iters_amg_nodal_to_err)?;
        c.text(flag(self.pcg_iters_amg_nodal_to_err_converged))?;
        c.float(self.forward_err_u)?;
        c.float(self.forward_err_force)?;
        c.float(self.seconds_solver)?;
        c.text(&self.warnings)?;
        c.w.write_record(None::<&[u8]>)
    }

    /// The row without its timing (for determinism comparisons).
    pub fn without_timing(&self) -> Row {
        Row {
            seconds: None,
            seconds_solve: None,
            seconds_cond: None,
            seconds_det: None,
            seconds_solver: None,
            ..self.clone()
        }
    }
}

/// A boolean cell: `true`, `false`, or empty for none.
fn flag(b: Option<bool>) -> &'static str {
    match b {
        Some(true) => "true",
        Some(false) => "false",
        None => "",
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
        .from_writer(Vec::with_capacity(256 * rows.len()));
    let mut buf = String::new();
    for r in rows {
        r.write_record(&mut w, &mut buf).expect("in-memory write");
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

/// Reads rows.csv. With `lenient`, a malformed last record (a run killed mid-write) is dropped
/// instead of being an error; the number of bytes of well-formed content is returned too.
/// Quoted cells may span lines (a warning with a newline).
pub fn read_rows(path: &Path, lenient: bool) -> Result<(Vec<Row>, usize)> {
    let mut rows = Vec::new();
    let good = scan_rows(path, lenient, |rec| {
        rows.push(parse_record(rec)?);
        Ok(())
    })?;
    Ok((rows, good))
}

/// The rows of `path` counted per method as solved, failed or skipped (from each row's
/// `warnings` cell, [`crate::study::outcomes`]); the records are checked as [`read_rows`]
/// checks them (field count, torn last line), the values not parsed.
pub fn tally_rows(path: &Path) -> Result<crate::study::outcomes::Tally> {
    let col = |name: &str| COLUMNS.iter().position(|c| *c == name).unwrap_or(0);
    let (method, warnings) = (col("method"), col("warnings"));
    let mut tally = crate::study::outcomes::Tally::default();
    scan_rows(path, false, |rec| {
        if rec.len() != COLUMNS.len() {
            return Err(field_count_error(rec.len()));
        }
        tally.add(&rec[method], &rec[warnings]);
        Ok(())
    })?;
    Ok(tally)
}

/// The scan of [`read_rows`]: the header checked, then `row` on every complete record in
/// order; returns the bytes of well-formed content.
fn scan_rows(
    path: &Path,
    lenient: bool,
    mut row: impl FnMut(&csv::StringRecord) -> std::result::Result<(), String>,
) -> Result<usize> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut rec = csv::StringRecord::new();
    let complete = |rd: &csv::Reader<&[u8]>| {
        let end = rd.position().byte() as usize;
        (end, text.as_bytes()[..end].ends_with(b"\n"))
    };
    let head = matches!(rd.read_record(&mut rec), Ok(true)) && rec.iter().eq(COLUMNS);
    let (mut good, _) = complete(&rd);
    if !head {
        return Err(Error::io(
            path.display(),
            if text.is_empty() {
                "empty file (no header)"
            } else {
                "header does not match this version's columns"
            },
        ));
    }
    loop {
        let parsed = match rd.read_record(&mut rec) {
            Ok(false) => break,
            Ok(true) => match complete(&rd) {
                (end, true) => row(&rec).map(|()| end),
                (_, false) => Err("truncated line".to_string()),
            },
            Err(e) => Err(e.to_string()),
        };
        match parsed {
            Ok(end) => good = end,
            Err(_) if lenient => break,
            Err(e) => {
                let line = rec.position().map_or(0, |p| p.line());
                return Err(Error::parse(path.display(), line as usize, e.to_string()));
            }
        }
    }
    Ok(good)
}

fn field_count_error(found: usize) -> String {
    format!("expected {} fields, found {found}", COLUMNS.len())
}

fn parse_record(rec: &csv::StringRecord) -> std::result::Result<Row, String> {
    if rec.len() != COLUMNS.len() {
        return Err(field_count_error(rec.len()));
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
    let boolean = |c: &str, what: &str| parse_opt(c).map_err(|_| format!("bad {what} '{c}'"));
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
        cond2_system_lo: fl(next())?,
        cond2_system_hi: fl(next())?,
        cond2_k_lo: fl(next())?,
        cond2_k_hi: fl(next())?,
        cond_tol: fl(next())?,
        cond_route: Some(next().to_string()).filter(|s| !s.is_empty()),
        cond2_bounds_proven: {
            let c = next();
            parse_opt(c).map_err(|_| format!("bad cond2_bounds_proven '{c}'"))?
        },
        cond2_within_contract: {
            let c = next();
            parse_opt(c).map_err(|_| format!("bad cond2_within_contract '{c}'"))?
        },
        log10_det_ratio: fl(next())?,
        max_penetration: fl(next())?,
        error_vs_exact: fl(next())?,
        linear_solves: parse_opt(next())?,
        iterations: parse_opt(next())?,
        kappa_initial: fl(next())?,
        kappa_final: fl(next())?,
        kappa_increases: parse_opt(next())?,
        converged: {
            let c = next();
            parse_opt(c).map_err(|_| format!("bad converged '{c}'"))?
        },
        seconds: fl(next())?,
        seconds_solve: fl(next())?,
        seconds_cond: fl(next())?,
        seconds_det: fl(next())?,
        cond_ratio_to_optimal: fl(next())?,
        cond2_jacobi: fl(next())?,
        pcg_iters_jacobi: parse_opt(next())?,
        pcg_iters_ic0: parse_opt(next())?,
        pcg_converged: {
            let c = next();
            parse_opt(c).map_err(|_| format!("bad pcg_converged '{c}'"))?
        },
        minres_iters: parse_opt(next())?,
        pcg_iters_jacobi_to_err: parse_opt(next())?,
        pcg_iters_jacobi_to_err_converged: boolean(next(), "pcg_iters_jacobi_to_err_converged")?,
        pcg_iters_ic0_to_err: parse_opt(next())?,
        pcg_iters_ic0_to_err_converged: boolean(next(), "pcg_iters_ic0_to_err_converged")?,
        minres_iters_to_err: parse_opt(next())?,
        minres_iters_to_err_converged: boolean(next(), "minres_iters_to_err_converged")?,
        pcg_iters_amg_scalar_to_err: parse_opt(next())?,
        pcg_iters_amg_scalar_to_err_converged: boolean(
            next(),
            "pcg_iters_amg_scalar_to_err_converged",
        )?,
        pcg_iters_amg_nodal_to_err: parse_opt(next())?,
        pcg_iters_amg_nodal_to_err_converged: boolean(
            next(),
            "pcg_iters_amg_nodal_to_err_converged",
        )?,
        forward_err_u: fl(next())?,
        forward_err_force: fl(next())?,
        seconds_solver: fl(next())?,
        warnings: next().into(),
    })
}

#[cfg(test)]
mod tests;
