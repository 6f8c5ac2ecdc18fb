//! Scene files: one contact problem `K u = q`, `Dᵀu ⋚ û`, stored as JSON with an optional
//! Matrix Market stiffness.
//!
//! # Contract (binding, `shared/notes/methods.md`, "Scene files")
//!
//! ```json
//! {
//!   "name": "paper-beam",
//!   "stiffness": {"dense": [[420, 0, 0], [0, 420, 0], [0, 0, 420]]},
//!   "load": [0, -50, 1],
//!   "constraints": [{"dof": 1, "limit": 3.0, "kind": "bilateral"}]
//! }
//! ```
//!
//! * `name` (string), `stiffness`, `load` (N numbers) and `constraints` (an array, possibly
//!   empty) are required.
//! * `stiffness` is an object with **exactly one** key: `"dense"` (N rows of N numbers,
//!   row-major) or `"matrix_market"` (a path, relative to the scene file's directory, to a
//!   `coordinate real|integer general|symmetric` or `array real|integer general|symmetric`
//!   Matrix Market file). Any other key, both keys or neither is an error.
//! * `constraints` may instead be `{"matrix_market": "D.mtx", "limits": [û, ...], "kind": k}`
//!   (or `"kinds": [k, ...]`, one per row): the m×N matrix whose row c holds constraint c's
//!   coefficients (coordinate or array, real or integer, `general` — a `symmetric` header is
//!   refused; path relative to the scene file), for scenes with many coupled rows. A row's
//!   entries in file order are its terms, checked as below (a DOF given twice in a row is an
//!   error, not a sum; explicit zeros are dropped).
//! * Each constraint is `{"dof": d, "limit": û, "kind": k}` with a **0-based** DOF index `d`
//!   and `k` one of `bilateral`, `upper`, `lower` (see [`crate::system`]): `u[d] ⋚ û`; or,
//!   for a row that couples DOFs, `{"terms": [[d, a], ...], "limit": û, "kind": k}`:
//!   `Σ a·u[d] ⋚ û` (exactly one of `dof` and `terms`; each DOF at most once in a row, the
//!   coefficients finite and not all zero; a zero coefficient is dropped). `{"dof": d}`,
//!   `{"terms": [[d, 1]]}` and `{"terms": [[d, 1], [e, 0]]}` are the same constraint.
//! * Optional: `"description"` (string), `"units"` (string; documentation only, not kept)
//!   and `"meta"` (any JSON, kept as [`serde_json::Value`], for provenance such as the
//!   generator and its seed). Other top-level keys are ignored; extra keys inside a
//!   constraint are ignored too.
//! * Optional, for a nodal AMG (`solve`'s `pcg_iters_amg_nodal_to_err`): the near-null space
//!   of K, `"near_null_space": {"matrix_market": "B.mtx"}` (N×k, `array` or `coordinate`)
//!   with `"block_size": b` (DOFs per node, consecutive; default 1) — where supports fix some
//!   of a node's components, B has one row per *slot* (b per node) and `"slots": [s_0, …]`
//!   inside `near_null_space` gives each DOF's slot, increasing
//!   ([`crate::system::NearNull::with_slots`]) — or
//!   `"nodes": {"coordinates": [[x, y(, z)], ...], "dofs_per_node": 2 | 3}`, from which the
//!   rigid-body modes are built ([`crate::system::NearNull::rigid_body_modes`]; one DOF per
//!   node: a scalar field, whose near-null space is the default B = ones). `"nodes"`
//!   may also hold `"cells": [[n0, n1, …], …]` (node indices: a line, triangle, quad,
//!   tetrahedron or hexahedron in VTK's node order) for `solve --vtk` ([`Nodes`]).
//!
//! Units are whatever the user's model uses (the solver never converts); `units` only
//! documents them.
//!
//! # Reading
//!
//! [`read_scene`] reads a scene, resolves a Matrix Market stiffness and builds a validated
//! [`Problem`] (sizes, NaN/Inf, DOF range, duplicate DOFs). Every error is an
//! [`Error::Io`] naming the file, the place (line and column, or the JSON path such as
//! `constraints[2].kind`) and the problem, e.g.
//! `scenes/x.scene.json: constraint 2: DOF 12 is out of range (N = 9, DOFs are 0-based)` or
//! `K.mtx: line 7: expected 3 fields "row col value", found 2`.
//!
//! JSON is read with `serde_json` (its `float_roundtrip` feature converts decimal numbers
//! correctly rounded, which the bit-for-bit round trip of [`write_scene`] needs) into
//! `#[derive(Deserialize)]` types, through `serde_path_to_error` so that a type error names
//! its JSON path; `serde_json`'s messages are reworded in this module's terms ("expected
//! a number, found the string \"2\"", "missing required field \"load\""). Numbers that
//! overflow f64 (e.g. `1e999`) are rejected as not finite. No hostile input overflows the
//! stack: `meta` is limited to `serde_json`'s 128 levels of nesting, ignored keys are
//! skipped without recursion, and the typed fields reject anything nested deeper than they
//! expect. Only `stiffness` rejects unknown keys; a duplicate key among the scene's own
//! fields, a constraint's fields or anywhere inside `meta` is an error (duplicates of
//! ignored keys are not checked).
//!
//! The `stiffness.dense` block — nearly all of a dense scene's bytes — is read by a
//! hand-written fast path (`dense_block`: why, measured, and how it never answers differently
//! from `serde_json`), the rest of the file by `serde_json`; anything unexpected falls back
//! to `serde_json` alone.
//!
//! Matrix Market files are read by the line-based reader in [`matrix_market`] (see there
//! why it is hand-written), which returns [`Stiffness::Sparse`] (never densified).
//! Dimensions above [`MAX_DIM`] are refused.
//!
//! # Writing
//!
//! [`write_scene`] writes the same format; a sparse K, or one with N above a threshold,
//! goes to a sibling `<stem>.mtx` file. Numbers are written in shortest round-trip form, so
//! `read_scene(write_scene(p))` reproduces K, q and the limits bit for bit. Files are
//! written with [`write_atomic`](crate::provenance::write_atomic) (a temporary file in the target directory, renamed into
//! place), so an error never leaves a half-written file behind.

use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};
use serde::de::{self, value::MapAccessDeserializer, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::fs;
use std::path::Path;

mod dense_block;
mod json_error;
use json_error::quote_short;
pub mod matrix_market;
mod near_null;
pub use near_null::Nodes;
mod write;

pub use write::{write_scene, write_scene_as, Storage};

pub use matrix_market::{
    parse_matrix_market_str, read_matrix_market, write_matrix_market, write_matrix_market_dense,
    write_matrix_market_vector, MAX_DIM,
};

/// A scene read from disk: a named, validated contact problem.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene's `name`.
    pub name: String,
    /// The optional `description`.
    pub description: Option<String>,
    /// K, q and the constraints, validated by [`Problem::new`].
    pub problem: Problem,
    /// The optional `meta` object (provenance: generator, seed, …), kept verbatim.
    /// `"meta": null` reads as `None`.
    pub meta: Option<serde_json::Value>,
    /// The optional `"nodes"` (coordinates, DOFs per node, cells): the near-null space's
    /// rigid-body modes and the VTK output are built from them.
    pub nodes: Option<Nodes>,
}

/// Turns a library error into a bare message (drops the `invalid input: ` prefix, whose
/// information the wrapping file error already conveys).
fn bare_message(e: Error) -> String {
    e.bare_message()
}

// ---------------------------------------------------------------------------------------
// Reading scenes
// ---------------------------------------------------------------------------------------

/// Reads and validates a scene file.
///
/// A `matrix_market` stiffness is resolved relative to the scene file's directory. Errors
/// (unreadable file, invalid UTF-8, malformed JSON, wrong types, missing fields, bad
/// stiffness file, sizes, NaN/Inf, DOF out of range, duplicate DOFs) are [`Error::Io`] with
/// the file name and a one-line explanation.
pub fn read_scene(path: &Path) -> Result<Scene> {
    read(path, false)
}

/// [`read_scene`] with K in the storage its structure prefers: bit for bit
/// `read_scene(path)?.problem.in_preferred_storage()`, but a structurally sparse matrix
/// written `"dense"` is built straight from its nonzero entries, without the N×N
/// intermediate and its two N² scans (the sweep reads scene folders this way).
pub fn read_scene_preferred(path: &Path) -> Result<Scene> {
    read(path, true)
}

fn read(path: &Path, preferred: bool) -> Result<Scene> {
    let origin = path.display().to_string();
    let bytes =
        fs::read(path).map_err(|e| Error::io(&origin, format!("cannot read scene file: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        Error::io(
            &origin,
            format!(
                "not valid UTF-8 text (first bad byte at offset {}); JSON must be UTF-8",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    let base = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    parse_scene(&text, base, &origin, preferred)
}

/// Parses a scene from JSON text.
///
/// `base_dir` is the directory a relative `matrix_market` path is resolved against;
/// `origin` is the name used in error messages (normally the scene file's path). Used by
/// [`read_scene`]; handy for tests and fuzzing. Never panics.
pub fn parse_scene_str(json: &str, base_dir: &Path, origin: &str) -> Result<Scene> {
    parse_scene(json, base_dir, origin, false)
}

/// The scene with its `stiffness.dense` block read by [`dense_block`] and the rest by
/// `serde_json` (the block replaced by `[]`), or `None` where that fast path does not apply
/// or the patched text is refused (the caller then parses the original text).
fn read_fast(json: &str) -> Option<Obj<RawScene>> {
    let block = dense_block::find(json)?;
    let patched = [&json[..block.start], "[]", &json[block.end..]].concat();
    let mut raw: Obj<RawScene> = serde_json::from_str(&patched).ok()?;
    let dense = raw.0.stiffness.0.dense.as_mut()?;
    *dense = block.rows;
    Some(raw)
}

/// [`parse_scene_str`], with K in its preferred storage where `preferred`.
fn parse_scene(json: &str, base_dir: &Path, origin: &str, preferred: bool) -> Result<Scene> {
    let json = json.strip_prefix('\u{feff}').unwrap_or(json);
    if json.trim_ascii().is_empty() {
        return Err(Error::io(
            origin,
            "the file is empty (expected a JSON object)",
        ));
    }
    // Fast paths: the dense block read by `dense_block` and the rest by plain serde_json,
    // else plain serde_json. Only a file that fails is parsed again through
    // serde_path_to_error, whose path tracking costs ≈ 10 % of a dense sweep's run time.
    let raw: Obj<RawScene> = match read_fast(json) {
        Some(raw) => raw,
        None => match serde_json::from_str(json) {
            Ok(raw) => raw,
            Err(_) => {
                let mut de = serde_json::Deserializer::from_str(json);
                let raw: Obj<RawScene> =
                    serde_path_to_error::deserialize(&mut de).map_err(|e| {
                        let path = e.path().to_string();
                        Error::io(origin, json_error::describe(e.inner(), Some(&path), json))
                    })?;
                de.end()
                    .map_err(|e| Error::io(origin, json_error::describe(&e, None, json)))?;
                raw
            }
        },
    };
    let RawScene {
        name,
        description,
        _units: _,
        meta,
        stiffness: Obj(stiffness),
        load,
        constraints,
        near_null_space,
        block_size,
        nodes,
    } = raw.0;
    let meta = meta.map(|Meta(v)| v);
    let at = |path: &str, msg: String| Error::io(origin, format!("{path}: {msg}"));

    const EXACTLY_ONE: &str =
        r#"give exactly one of "dense" (rows of numbers) or "matrix_market" (a file path)"#;
    let k = match (stiffness.dense, stiffness.matrix_market) {
        (Some(_), Some(_)) => {
            return Err(at(
                "stiffness",
                format!("both \"dense\" and \"matrix_market\" are present; {EXACTLY_ONE}"),
            ))
        }
        (None, None) => {
            return Err(at(
                "stiffness",
                format!("neither \"dense\" nor \"matrix_market\" is given; {EXACTLY_ONE}"),
            ))
        }
        (Some(rows), None) => if preferred {
            Stiffness::from_row_entries_preferred(&rows.row_lens, rows.entries)
        } else {
            Stiffness::from_row_entries(&rows.row_lens, rows.entries)
        }
        .map_err(|e| at("stiffness.dense", bare_message(e)))?,
        (None, Some(rel)) => {
            if rel.trim().is_empty() {
                return Err(at("stiffness.matrix_market", "empty file path".into()));
            }
            let k = read_matrix_market(&base_dir.join(&rel))
                .map_err(|e| at("stiffness.matrix_market", e.to_string()))?;
            if preferred {
                k.in_preferred_storage()
            } else {
                k
            }
        }
    };
    let q = load.into_iter().map(|Num(x)| x).collect();
    let constraints = match constraints {
        RawConstraints::List(list) => list
            .into_iter()
            .enumerate()
            .map(|(c, Obj(raw))| {
                raw.into_constraint()
                    .map_err(|m| at(&format!("constraints[{c}]"), m))
            })
            .collect::<Result<Vec<_>>>()?,
        RawConstraints::Matrix(Obj(rows)) => rows.into_constraints(base_dir, k.n(), &at)?,
    };
    let problem =
        Problem::new(k, q, constraints).map_err(|e| Error::io(origin, bare_message(e)))?;
    let nodes = nodes
        .map(|Obj(r)| near_null::nodes(r, problem.n()).map_err(|m| at("nodes", m)))
        .transpose()?;
    let near_null = near_null::parse(
        near_null_space.map(|Obj(r)| r),
        block_size,
        nodes.as_ref(),
        problem.n(),
        base_dir,
        &at,
    )?;
    let problem = match near_null {
        Some(nn) => problem
            .with_near_null(nn)
            .map_err(|e| Error::io(origin, bare_message(e)))?,
        None => problem,
    };
    Ok(Scene {
        name,
        description,
        problem,
        meta,
        nodes,
    })
}

// ---------------------------------------------------------------------------------------
// The scene as written: serde types
// ---------------------------------------------------------------------------------------

/// A scene file as written, before validation. Unknown top-level keys are ignored (the
/// contract); `name`, `stiffness`, `load` and `constraints` are required.
#[derive(Deserialize)]
struct RawScene {
    name: String,
    description: Option<String>,
    /// `units`: documentation only, checked for type, not kept.
    #[serde(rename = "units")]
    _units: Option<String>,
    meta: Option<Meta>,
    stiffness: Obj<RawStiffness>,
    load: Vec<Num>,
    constraints: RawConstraints,
    near_null_space: Option<Obj<near_null::RawNearNull>>,
    block_size: Option<usize>,
    nodes: Option<Obj<near_null::RawNodes>>,
}

/// `constraints`: an array of constraint objects, or the rows of D in a Matrix Market file.
enum RawConstraints {
    List(Vec<Obj<RawConstraint>>),
    Matrix(Obj<RawRows>),
}

impl<'de> Deserialize<'de> for RawConstraints {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawConstraints;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    r#"an array of constraints ([] for none) or {"matrix_market": "D.mtx", "limits": [...], "kind": k}"#,
                )
            }
            fn visit_seq<A: de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> std::result::Result<RawConstraints, A::Error> {
                Vec::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(RawConstraints::List)
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                map: A,
            ) -> std::result::Result<RawConstraints, A::Error> {
                RawRows::deserialize(MapAccessDeserializer::new(map))
                    .map(|r| RawConstraints::Matrix(Obj(r)))
            }
        }
        d.deserialize_any(V)
    }
}

/// `{"matrix_market": "D.mtx", "limits": [...], "kind": k}` or `..., "kinds": [k, ...]`: the
/// m×N matrix of the rows (row c = constraint c), the m limits, one kind for all or one each.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRows {
    matrix_market: String,
    limits: Vec<Num>,
    kind: Option<Kind>,
    kinds: Option<Vec<Kind>>,
}

impl RawRows {
    /// The constraints, row by row, with errors at `constraints.*` (through `at`).
    fn into_constraints(
        self,
        base_dir: &Path,
        n: usize,
        at: &dyn Fn(&str, String) -> Error,
    ) -> Result<Vec<Constraint>> {
        if self.matrix_market.trim().is_empty() {
            return Err(at("constraints.matrix_market", "empty file path".into()));
        }
        let (m, cols, entries) =
            matrix_market::read_matrix_market_entries(&base_dir.join(&self.matrix_market))
                .map_err(|e| at("constraints.matrix_market", e.to_string()))?;
        if cols != n {
            return Err(at(
                "constraints.matrix_market",
                format!("D has {cols} columns but K is {n}×{n} (one row per constraint)"),
            ));
        }
        if self.limits.len() != m {
            return Err(at(
                "constraints.limits",
                format!("{} limits for the {m} rows of D", self.limits.len()),
            ));
        }
        let kinds: Vec<ConstraintKind> =
            match (self.kind, self.kinds) {
                (Some(Kind(k)), None) => vec![k; m],
                (None, Some(ks)) if ks.len() == m => ks.into_iter().map(|Kind(k)| k).collect(),
                (None, Some(ks)) => {
                    return Err(at(
                        "constraints.kinds",
                        format!("{} kinds for the {m} rows of D", ks.len()),
                    ))
                }
                _ => return Err(at(
                    "constraints",
                    r#"give exactly one of "kind" (one for every row) or "kinds" (one per row)"#
                        .into(),
                )),
            };
        let mut terms: Vec<Vec<(usize, f64)>> = vec![Vec::new(); m];
        for (r, c, v) in entries {
            terms[r].push((c, v));
        }
        Ok(terms
            .into_iter()
            .zip(self.limits)
            .zip(kinds)
            .map(|((t, Num(l)), k)| Constraint::row(t, l, k))
            .collect())
    }
}

/// `{"dense": [[...], ...]}` or `{"matrix_market": "K.mtx"}`: any other key is an error;
/// "exactly one" is checked after parsing.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStiffness {
    dense: Option<DenseRows>,
    matrix_market: Option<String>,
}

/// `"dense"`: N rows of N numbers, kept as the nonzero entries and the length of each row
/// (checked square by `Stiffness::from_row_entries`). A dense scene of the sweep's folder is
/// ≈ 98 % zeros: not storing them as `Vec<Vec<f64>>` rows first halves the time the sweep
/// spends reading it (allocations and first-touch page faults, which two threads contend
/// for).
struct DenseRows {
    /// Entries per row, in order.
    row_lens: Vec<usize>,
    /// `(row, column, value)` of the entries other than +0.0, row by row.
    entries: Vec<(usize, usize, f64)>,
}

impl<'de> Deserialize<'de> for DenseRows {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        /// One row: its numbers appended to `entries` (nonzeros only), its length returned.
        struct Row<'a> {
            row: usize,
            entries: &'a mut Vec<(usize, usize, f64)>,
        }
        impl<'de> de::DeserializeSeed<'de> for Row<'_> {
            type Value = usize;
            fn deserialize<D: Deserializer<'de>>(
                self,
                d: D,
            ) -> std::result::Result<usize, D::Error> {
                d.deserialize_seq(self)
            }
        }
        impl<'de> Visitor<'de> for Row<'_> {
            type Value = usize;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of numbers (a row)")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<usize, A::Error> {
                let mut len = 0;
                while let Some(Num(x)) = seq.next_element()? {
                    // +0.0 only: −0.0 is kept, so the round trip stays bit for bit.
                    if x.to_bits() != 0 {
                        self.entries.push((self.row, len, x));
                    }
                    len += 1;
                }
                Ok(len)
            }
        }
        struct Rows;
        impl<'de> Visitor<'de> for Rows {
            type Value = DenseRows;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an array of rows (arrays of numbers)")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<DenseRows, A::Error> {
                let mut out = DenseRows {
                    row_lens: Vec::new(),
                    entries: Vec::new(),
                };
                loop {
                    let row = Row {
                        row: out.row_lens.len(),
                        entries: &mut out.entries,
                    };
                    match seq.next_element_seed(row)? {
                        Some(len) => out.row_lens.push(len),
                        None => return Ok(out),
                    }
                }
            }
        }
        d.deserialize_seq(Rows)
    }
}

/// `{"dof": d, "limit": û, "kind": k}` or `{"terms": [[d, a], ...], "limit": û, "kind": k}`
/// (exactly one of `dof` and `terms`, checked after parsing); extra keys are ignored (the
/// contract).
#[derive(Deserialize)]
struct RawConstraint {
    dof: Option<Dof>,
    terms: Option<Vec<Term>>,
    limit: Num,
    kind: Kind,
}

impl RawConstraint {
    /// The constraint, or the message for `constraints[c]` when it gives both or neither of
    /// `dof` and `terms`.
    fn into_constraint(self) -> std::result::Result<Constraint, String> {
        let (limit, kind) = (self.limit.0, self.kind.0);
        match (self.dof, self.terms) {
            (Some(Dof(d)), None) => Ok(Constraint::on_dof(d, limit, kind)),
            (None, Some(terms)) => Ok(Constraint::row(
                terms.into_iter().map(|Term(d, a)| (d, a)).collect(),
                limit,
                kind,
            )),
            (Some(_), Some(_)) => Err(format!("both \"dof\" and \"terms\" are present; {ONE_OF}")),
            (None, None) => Err(format!("neither \"dof\" nor \"terms\" is given; {ONE_OF}")),
        }
    }
}

/// One term `[dof, coefficient]` of a constraint row: exactly two entries.
struct Term(usize, f64);

impl<'de> Deserialize<'de> for Term {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Term;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a pair [dof, coefficient]")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<Term, A::Error> {
                const PAIR: &str = "a term is a pair [dof, coefficient]";
                let Some(Dof(d)) = seq.next_element()? else {
                    return Err(de::Error::custom(format_args!("{PAIR}; found []")));
                };
                let Some(Num(a)) = seq.next_element()? else {
                    return Err(de::Error::custom(format_args!("{PAIR}; found [{d}]")));
                };
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::custom(format_args!(
                        "{PAIR}; found more than two entries"
                    )));
                }
                Ok(Term(d, a))
            }
        }
        d.deserialize_seq(V)
    }
}

/// How a constraint names its row.
const ONE_OF: &str =
    r#"give exactly one of "dof" (a single DOF) or "terms" ([[dof, coefficient], ...])"#;

/// What an object in the scene should look like, for "expected …, found …" messages.
trait Expecting {
    const EXPECTING: &'static str;
}

impl Expecting for RawScene {
    const EXPECTING: &'static str = "a JSON object {...} (a scene)";
}

impl Expecting for RawStiffness {
    const EXPECTING: &'static str =
        r#"an object {"dense": [[...], ...]} or {"matrix_market": "K.mtx"}"#;
}

impl Expecting for RawConstraint {
    const EXPECTING: &'static str =
        r#"an object {"dof": d, "limit": x, "kind": k} or {"terms": [[d, a], ...], ...}"#;
}

/// A JSON object only: derived structs would also accept an array of their fields in
/// order, which no scene file means.
struct Obj<T>(T);

impl<'de, T: Deserialize<'de> + Expecting> Deserialize<'de> for Obj<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de> + Expecting> Visitor<'de> for V<T> {
            type Value = Obj<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(T::EXPECTING)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> std::result::Result<Obj<T>, A::Error> {
                T::deserialize(MapAccessDeserializer::new(map)).map(Obj)
            }
        }
        d.deserialize_map(V(std::marker::PhantomData))
    }
}

/// The `meta` value, kept verbatim as a [`serde_json::Value`]; a duplicate key anywhere
/// inside it is an error (the value would otherwise silently keep the last one).
struct Meta(serde_json::Value);

impl<'de> Deserialize<'de> for Meta {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde_json::Value;
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Meta;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("any JSON value")
            }
            fn visit_map<A: MapAccess<'de>>(
                self,
                mut map: A,
            ) -> std::result::Result<Meta, A::Error> {
                let mut out = serde_json::Map::new();
                while let Some(key) = map.next_key::<String>()? {
                    if out.contains_key(&key) {
                        return Err(de::Error::custom(format_args!(
                            "duplicate key {}",
                            quote_short(&key)
                        )));
                    }
                    let Meta(v) = map.next_value()?;
                    out.insert(key, v);
                }
                Ok(Meta(Value::Object(out)))
            }
            fn visit_seq<A: de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<Meta, A::Error> {
                let mut out = Vec::new();
                while let Some(Meta(v)) = seq.next_element()? {
                    out.push(v);
                }
                Ok(Meta(Value::Array(out)))
            }
            fn visit_unit<E>(self) -> std::result::Result<Meta, E> {
                Ok(Meta(Value::Null))
            }
            fn visit_bool<E>(self, b: bool) -> std::result::Result<Meta, E> {
                Ok(Meta(Value::Bool(b)))
            }
            fn visit_u64<E>(self, v: u64) -> std::result::Result<Meta, E> {
                Ok(Meta(v.into()))
            }
            fn visit_i64<E>(self, v: i64) -> std::result::Result<Meta, E> {
                Ok(Meta(v.into()))
            }
            fn visit_f64<E>(self, v: f64) -> std::result::Result<Meta, E> {
                Ok(Meta(v.into()))
            }
            fn visit_str<E>(self, s: &str) -> std::result::Result<Meta, E> {
                Ok(Meta(s.into()))
            }
        }
        d.deserialize_any(V)
    }
}

/// A number (an f64; JSON cannot hold NaN/Inf, and `serde_json` rejects numbers that
/// overflow f64). A quoted number is an error with a hint (`json_error::data`).
struct Num(f64);

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Num;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> std::result::Result<Num, E> {
                Ok(Num(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> std::result::Result<Num, E> {
                Ok(Num(v as f64))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> std::result::Result<Num, E> {
                Ok(Num(v as f64))
            }
        }
        // `deserialize_f64`, not `_any`: serde_json goes straight to its number parser (≈ 10 %
        // of reading a dense scene). A quoted number is then an "invalid type" error, which
        // `json_error::data` words with the hint.
        d.deserialize_f64(V)
    }
}

/// A 0-based DOF index: a non-negative integer (`4.0` and `4e0` are accepted).
struct Dof(usize);

impl<'de> Deserialize<'de> for Dof {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        fn bad<E: de::Error>(shown: impl fmt::Display) -> E {
            E::custom(format_args!(
                "expected a non-negative integer DOF index (0-based), found {shown}"
            ))
        }
        impl Visitor<'_> for V {
            type Value = Dof;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a non-negative integer DOF index (0-based)")
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> std::result::Result<Dof, E> {
                usize::try_from(v).map(Dof).map_err(|_| bad(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> std::result::Result<Dof, E> {
                usize::try_from(v).map(Dof).map_err(|_| bad(v))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> std::result::Result<Dof, E> {
                if v.fract() == 0.0 && (0.0..9_007_199_254_740_992.0).contains(&v) {
                    Ok(Dof(v as usize))
                } else {
                    Err(bad(format_args!("{v:?}")))
                }
            }
            fn visit_str<E: de::Error>(self, s: &str) -> std::result::Result<Dof, E> {
                Err(bad(format_args!("the string {}", quote_short(s))))
            }
        }
        d.deserialize_any(V)
    }
}

/// `"bilateral"`, `"upper"` or `"lower"`.
struct Kind(ConstraintKind);

impl<'de> Deserialize<'de> for Kind {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        ConstraintKind::from_name(&name).map(Kind).ok_or_else(|| {
            de::Error::custom(format_args!(
                "unknown kind {} (valid kinds: bilateral, upper, lower)",
                quote_short(&name)
            ))
        })
    }
}
