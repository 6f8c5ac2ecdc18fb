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
//! * Each constraint is `{"dof": d, "limit": û, "kind": k}` with a **0-based** DOF index `d`
//!   and `k` one of `bilateral`, `upper`, `lower` (see [`crate::system`]).
//! * Optional: `"description"` (string), `"units"` (string; documentation only, not kept)
//!   and `"meta"` (any JSON, kept as [`serde_json::Value`], for provenance such as the
//!   generator and its seed). Other top-level keys are ignored; extra keys inside a
//!   constraint are ignored too.
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
//! JSON is parsed by a small strict parser in this module rather than by `serde_json`:
//! `serde_json` without its `float_roundtrip` feature does not round decimal numbers
//! correctly (it can be off by an ulp), which would break the bit-for-bit round trip of
//! [`write_scene`]. Numbers here are converted with Rust's correctly rounded
//! `str::parse::<f64>`; numbers that overflow f64 (e.g. `1e999`) are rejected as not finite;
//! nesting deeper than 128 levels is rejected (no stack overflow on hostile input).
//!
//! Matrix Market files are likewise read by this module's own line-based reader (not
//! `nalgebra_sparse::io`, whose pest-based reader panics on some malformed input, e.g. an
//! index too large for `usize`, and gives errors without line numbers). The reader returns
//! [`Stiffness::Sparse`] (never densified), expands `symmetric` storage (one triangle
//! stored; the lower one by convention, an upper-only file is accepted, a file with entries
//! on both sides of the diagonal is rejected), sums duplicate entries, and rejects
//! `complex`, `pattern`, `skew-symmetric` and `hermitian` files, non-square or empty
//! matrices, truncated files, indices out of range and NaN/Inf values. `array` files are
//! supported; their exact `+0.0` entries are not stored. Dimensions above [`MAX_DIM`] are
//! refused (the sparse structure allocates O(N) memory up front).
//!
//! # Writing
//!
//! [`write_scene`] writes the same format; a sparse K, or one with N above a threshold,
//! goes to a sibling `<stem>.mtx` file. Numbers are written in shortest round-trip form, so
//! `read_scene(write_scene(p))` reproduces K, q and the limits bit for bit. Files are
//! written to a temporary file in the target directory and renamed into place, so an error
//! never leaves a half-written file behind.

use crate::error::{Error, Result};
use crate::system::{Constraint, ConstraintKind, Problem, Stiffness};
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Largest accepted matrix dimension N in a Matrix Market file (2²⁴ ≈ 16.8 million).
///
/// A guard against a corrupt or hostile size line: the sparse structure allocates O(N)
/// memory before any entry is read.
pub const MAX_DIM: usize = 1 << 24;

/// Maximum nesting depth of JSON arrays/objects accepted in a scene file.
const MAX_JSON_DEPTH: usize = 128;

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
}

/// Turns a library error into a bare message (drops the `invalid input: ` prefix, whose
/// information the wrapping file error already conveys).
fn bare_message(e: Error) -> String {
    match e {
        Error::Input(m) => m,
        other => other.to_string(),
    }
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
    parse_scene_str(&text, base, &origin)
}

/// Parses a scene from JSON text.
///
/// `base_dir` is the directory a relative `matrix_market` path is resolved against;
/// `origin` is the name used in error messages (normally the scene file's path). Used by
/// [`read_scene`]; handy for tests and fuzzing. Never panics.
pub fn parse_scene_str(json: &str, base_dir: &Path, origin: &str) -> Result<Scene> {
    let root = json::parse(json).map_err(|e| {
        Error::io(
            origin,
            format!(
                "line {}, column {}: malformed JSON: {}",
                e.line, e.col, e.msg
            ),
        )
    })?;
    let cx = Cx { origin };
    let json::Val::Obj(fields) = &root.v else {
        return Err(cx.at(
            &root,
            "scene",
            format!(
                "expected a JSON object {{...}}, found {}",
                root.v.describe()
            ),
        ));
    };

    let name = match json::get(fields, "name") {
        Some(n) => cx.string(n, "name")?.to_owned(),
        None => return Err(cx.missing(&root, "name", "a string")),
    };
    let description = cx.opt_string(json::get(fields, "description"), "description")?;
    // `units` is documentation only: checked for type, not kept.
    cx.opt_string(json::get(fields, "units"), "units")?;
    let meta = match json::get(fields, "meta") {
        None => None,
        Some(n) if matches!(n.v, json::Val::Null) => None,
        Some(n) => Some(n.to_value()),
    };

    let Some(stiff_node) = json::get(fields, "stiffness") else {
        return Err(cx.missing(
            &root,
            "stiffness",
            r#"{"dense": [[...], ...]} or {"matrix_market": "K.mtx"}"#,
        ));
    };
    let k = cx.stiffness(stiff_node, base_dir)?;

    let Some(load_node) = json::get(fields, "load") else {
        return Err(cx.missing(&root, "load", "an array of N numbers"));
    };
    let q = cx.number_array(load_node, "load")?;

    let Some(cons_node) = json::get(fields, "constraints") else {
        return Err(cx.missing(
            &root,
            "constraints",
            r#"an array of {"dof", "limit", "kind"} objects; use [] for none"#,
        ));
    };
    let constraints = cx.constraints(cons_node)?;

    let problem =
        Problem::new(k, q, constraints).map_err(|e| Error::io(origin, bare_message(e)))?;
    Ok(Scene {
        name,
        description,
        problem,
        meta,
    })
}

/// Context for turning JSON nodes into typed values with located error messages.
struct Cx<'a> {
    origin: &'a str,
}

impl Cx<'_> {
    /// An error located at `node`: `origin: line L, column C: what: msg`.
    fn at(&self, node: &json::Node, what: &str, msg: impl std::fmt::Display) -> Error {
        Error::io(
            self.origin,
            format!("line {}, column {}: {what}: {msg}", node.line, node.col),
        )
    }

    fn missing(&self, obj: &json::Node, key: &str, expected: &str) -> Error {
        self.at(
            obj,
            "scene",
            format!("missing required field \"{key}\" ({expected})"),
        )
    }

    fn string<'n>(&self, node: &'n json::Node, what: &str) -> Result<&'n str> {
        match &node.v {
            json::Val::Str(s) => Ok(s),
            other => Err(self.at(
                node,
                what,
                format!("expected a string, found {}", other.describe()),
            )),
        }
    }

    fn opt_string(&self, node: Option<&json::Node>, what: &str) -> Result<Option<String>> {
        match node {
            None => Ok(None),
            Some(n) if matches!(n.v, json::Val::Null) => Ok(None),
            Some(n) => self.string(n, what).map(|s| Some(s.to_owned())),
        }
    }

    fn number(&self, node: &json::Node, what: &str) -> Result<f64> {
        match &node.v {
            json::Val::Num { value, .. } => Ok(*value),
            json::Val::Str(s) => Err(self.at(
                node,
                what,
                format!(
                    "expected a number, found the string {} (write numbers without quotes)",
                    json::quote_short(s)
                ),
            )),
            other => Err(self.at(
                node,
                what,
                format!("expected a number, found {}", other.describe()),
            )),
        }
    }

    fn array<'n>(&self, node: &'n json::Node, what: &str) -> Result<&'n [json::Node]> {
        match &node.v {
            json::Val::Arr(items) => Ok(items),
            other => Err(self.at(
                node,
                what,
                format!("expected an array [...], found {}", other.describe()),
            )),
        }
    }

    fn number_array(&self, node: &json::Node, what: &str) -> Result<Vec<f64>> {
        self.array(node, what)?
            .iter()
            .enumerate()
            .map(|(i, x)| self.number(x, &format!("{what}[{i}]")))
            .collect()
    }

    fn stiffness(&self, node: &json::Node, base_dir: &Path) -> Result<Stiffness> {
        const EXPECTED: &str =
            r#"give exactly one of "dense" (rows of numbers) or "matrix_market" (a file path)"#;
        let json::Val::Obj(fields) = &node.v else {
            return Err(self.at(
                node,
                "stiffness",
                format!(
                    "expected an object, found {}; {EXPECTED}",
                    node.v.describe()
                ),
            ));
        };
        for (key, val) in fields {
            if key != "dense" && key != "matrix_market" {
                return Err(self.at(
                    val,
                    "stiffness",
                    format!("unknown key {}; {EXPECTED}", json::quote_short(key)),
                ));
            }
        }
        let dense = json::get(fields, "dense");
        let mm = json::get(fields, "matrix_market");
        match (dense, mm) {
            (Some(_), Some(_)) => Err(self.at(
                node,
                "stiffness",
                format!("both \"dense\" and \"matrix_market\" are present; {EXPECTED}"),
            )),
            (None, None) => Err(self.at(node, "stiffness", format!("empty object; {EXPECTED}"))),
            (Some(d), None) => {
                let rows = self.array(d, "stiffness.dense")?;
                let rows = rows
                    .iter()
                    .enumerate()
                    .map(|(i, r)| self.number_array(r, &format!("stiffness.dense[{i}]")))
                    .collect::<Result<Vec<_>>>()?;
                Stiffness::from_rows(&rows)
                    .map_err(|e| self.at(d, "stiffness.dense", bare_message(e)))
            }
            (None, Some(m)) => {
                let rel = self.string(m, "stiffness.matrix_market")?;
                if rel.trim().is_empty() {
                    return Err(self.at(m, "stiffness.matrix_market", "empty file path"));
                }
                let path = base_dir.join(rel);
                read_matrix_market(&path).map_err(|e| self.at(m, "stiffness.matrix_market", e))
            }
        }
    }

    fn constraints(&self, node: &json::Node) -> Result<Vec<Constraint>> {
        let items = self.array(node, "constraints")?;
        let mut out = Vec::with_capacity(items.len());
        for (c, item) in items.iter().enumerate() {
            let what = format!("constraints[{c}]");
            let json::Val::Obj(fields) = &item.v else {
                return Err(self.at(
                    item,
                    &what,
                    format!(
                        r#"expected an object {{"dof": d, "limit": x, "kind": k}}, found {}"#,
                        item.v.describe()
                    ),
                ));
            };
            let field = |key: &str| {
                json::get(fields, key).ok_or_else(|| {
                    self.at(item, &what, format!("missing required field \"{key}\""))
                })
            };
            let dof = self.dof(field("dof")?, &format!("{what}.dof"))?;
            let limit = self.number(field("limit")?, &format!("{what}.limit"))?;
            let kind_node = field("kind")?;
            let kind_what = format!("{what}.kind");
            let kind = match self.string(kind_node, &kind_what)? {
                "bilateral" => ConstraintKind::Bilateral,
                "upper" => ConstraintKind::Upper,
                "lower" => ConstraintKind::Lower,
                other => {
                    return Err(self.at(
                        kind_node,
                        &kind_what,
                        format!(
                            "unknown kind {} (valid kinds: bilateral, upper, lower)",
                            json::quote_short(other)
                        ),
                    ))
                }
            };
            out.push(Constraint { dof, limit, kind });
        }
        Ok(out)
    }

    fn dof(&self, node: &json::Node, what: &str) -> Result<usize> {
        let bad = |shown: String| {
            self.at(
                node,
                what,
                format!("expected a non-negative integer DOF index (0-based), found {shown}"),
            )
        };
        match &node.v {
            json::Val::Num {
                int: Some(i),
                value,
            } => usize::try_from(*i).map_err(|_| bad(format!("{value:?}"))),
            // 4.0 or 4e0: accepted when exactly a non-negative integer.
            json::Val::Num { value, int: None } => {
                if value.fract() == 0.0 && *value >= 0.0 && *value < 9_007_199_254_740_992.0 {
                    Ok(*value as usize)
                } else {
                    Err(bad(format!("{value:?}")))
                }
            }
            json::Val::Str(s) => Err(bad(format!("the string {}", json::quote_short(s)))),
            other => Err(bad(other.describe().to_owned())),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Matrix Market
// ---------------------------------------------------------------------------------------

/// Reads a Matrix Market file into a [`Stiffness::Sparse`] (never densified).
///
/// Accepted: `%%MatrixMarket matrix coordinate|array real|double|integer general|symmetric`,
/// square, 1 ≤ N ≤ [`MAX_DIM`]. Symmetric storage is expanded, duplicates are summed.
/// Errors name the file and the line. Invalid UTF-8 bytes (e.g. Latin-1 comments) are
/// replaced, not rejected.
pub fn read_matrix_market(path: &Path) -> Result<Stiffness> {
    let origin = path.display().to_string();
    let bytes = fs::read(path).map_err(|e| Error::io(&origin, format!("cannot read file: {e}")))?;
    let text = String::from_utf8_lossy(&bytes);
    parse_matrix_market_str(&text, &origin)
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum MmFormat {
    Coordinate,
    Array,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum MmField {
    Real,
    Integer,
}

/// Parses Matrix Market text (see [`read_matrix_market`]); `origin` names the source in
/// error messages. Never panics.
pub fn parse_matrix_market_str(text: &str, origin: &str) -> Result<Stiffness> {
    let at = |line: usize, msg: String| Error::io(origin, format!("line {line}: {msg}"));
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));

    // Header.
    const HEADER: &str = "%%MatrixMarket matrix coordinate real general";
    let Some((hl, header)) = lines.next() else {
        return Err(Error::io(
            origin,
            format!("file is empty (expected a Matrix Market header such as \"{HEADER}\")"),
        ));
    };
    let toks: Vec<&str> = header.split_ascii_whitespace().collect();
    if toks.first().map(|t| t.to_ascii_lowercase()) != Some("%%matrixmarket".into()) {
        return Err(at(
            hl,
            format!(
                "not a Matrix Market file: the first line must be a header such as \"{HEADER}\""
            ),
        ));
    }
    if toks.len() != 5 {
        return Err(at(
            hl,
            format!(
                "header must have 5 fields \"%%MatrixMarket matrix <format> <field> <symmetry>\", found {}",
                toks.len()
            ),
        ));
    }
    let lower: Vec<String> = toks.iter().map(|t| t.to_ascii_lowercase()).collect();
    if lower[1] != "matrix" {
        return Err(at(
            hl,
            format!(
                "unsupported object \"{}\" (only \"matrix\" is supported)",
                clip(toks[1])
            ),
        ));
    }
    let format = match lower[2].as_str() {
        "coordinate" => MmFormat::Coordinate,
        "array" => MmFormat::Array,
        _ => {
            return Err(at(
                hl,
                format!(
                    "unknown format \"{}\" (expected coordinate or array)",
                    clip(toks[2])
                ),
            ))
        }
    };
    let field = match lower[3].as_str() {
        "real" | "double" => MmField::Real,
        "integer" => MmField::Integer,
        "complex" => {
            return Err(at(
                hl,
                "complex matrices are not supported (K must be real)".into(),
            ))
        }
        "pattern" => {
            return Err(at(
                hl,
                "pattern matrices are not supported (they carry no values; K needs real or integer entries)"
                    .into(),
            ))
        }
        _ => {
            return Err(at(
                hl,
                format!(
                    "unknown field \"{}\" (expected real or integer)",
                    clip(toks[3])
                ),
            ))
        }
    };
    let symmetric = match lower[4].as_str() {
        "general" => false,
        "symmetric" => true,
        "skew-symmetric" | "hermitian" => {
            return Err(at(
                hl,
                format!(
                    "{} matrices are not supported (expected general or symmetric)",
                    lower[4]
                ),
            ))
        }
        _ => {
            return Err(at(
                hl,
                format!(
                    "unknown symmetry \"{}\" (expected general or symmetric)",
                    clip(toks[4])
                ),
            ))
        }
    };

    // Size line (after comments and blank lines).
    let mut size = None;
    for (ln, line) in lines.by_ref() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('%') {
            continue;
        }
        size = Some((ln, line));
        break;
    }
    let Some((sl, size_line)) = size else {
        return Err(Error::io(
            origin,
            "file ends before the size line (\"rows cols entries\" for coordinate, \"rows cols\" for array)",
        ));
    };
    let toks: Vec<&str> = size_line.split_ascii_whitespace().collect();
    let want = if format == MmFormat::Coordinate { 3 } else { 2 };
    let want_desc = if format == MmFormat::Coordinate {
        "\"rows cols entries\""
    } else {
        "\"rows cols\""
    };
    if toks.len() != want {
        return Err(at(
            sl,
            format!(
                "size line: expected {want} integers {want_desc}, found {} field(s)",
                toks.len()
            ),
        ));
    }
    let mut dims = [0usize; 3];
    for (d, t) in dims.iter_mut().zip(&toks) {
        *d = t.parse::<usize>().map_err(|_| {
            at(
                sl,
                format!(
                    "size line: \"{}\" is not a non-negative integer (expected {want_desc})",
                    clip(t)
                ),
            )
        })?;
    }
    let (nr, nc) = (dims[0], dims[1]);
    if nr != nc {
        return Err(at(
            sl,
            format!("matrix is not square: {nr} rows × {nc} columns (K must be N×N)"),
        ));
    }
    let n = nr;
    if n == 0 {
        return Err(at(sl, "matrix is empty (0×0)".into()));
    }
    if n > MAX_DIM {
        return Err(at(
            sl,
            format!("matrix dimension N = {n} exceeds the supported maximum {MAX_DIM}"),
        ));
    }
    let n128 = n as u128;
    let capacity = if symmetric {
        n128 * (n128 + 1) / 2
    } else {
        n128 * n128
    };
    let declared: u128 = match format {
        MmFormat::Coordinate => dims[2] as u128,
        MmFormat::Array => capacity,
    };
    let storage = if symmetric { "symmetric" } else { "general" };
    if declared > capacity {
        return Err(at(
            sl,
            format!(
                "size line declares {declared} entries but a {n}×{n} {storage} matrix stores at most {capacity}"
            ),
        ));
    }

    let parse_value = |ln: usize, tok: &str| -> Result<f64> {
        let v = match field {
            MmField::Integer => match tok.parse::<i128>() {
                Ok(i) => i as f64,
                Err(_) => {
                    return Err(at(
                        ln,
                        format!(
                            "value \"{}\" is not an integer (the header says \"integer\")",
                            clip(tok)
                        ),
                    ))
                }
            },
            MmField::Real => match tok.parse::<f64>() {
                Ok(v) => v,
                // Fortran-style exponents: 1.5D+03.
                Err(_) => match tok.replace(['d', 'D'], "e").parse::<f64>() {
                    Ok(v) if tok.contains(['d', 'D']) => v,
                    _ => {
                        return Err(at(ln, format!("value \"{}\" is not a number", clip(tok))));
                    }
                },
            },
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(at(
                ln,
                format!(
                    "value \"{}\" is not finite (NaN/Inf, or overflows f64)",
                    clip(tok)
                ),
            ))
        }
    };

    let declared = declared as usize; // ≤ capacity ≤ MAX_DIM², fits in 64-bit usize
    let mut triplets: Vec<(usize, usize, f64)> =
        Vec::with_capacity(declared.min(1 << 16) * if symmetric { 2 } else { 1 });
    let mut count = 0usize;

    match format {
        MmFormat::Coordinate => {
            // Line numbers of the first strictly-lower / strictly-upper entry (symmetric).
            let mut lower_at: Option<(usize, usize, usize)> = None;
            let mut upper_at: Option<(usize, usize, usize)> = None;
            for (ln, line) in lines {
                let t = line.trim();
                if t.is_empty() || t.starts_with('%') {
                    continue;
                }
                let f: Vec<&str> = t.split_ascii_whitespace().take(4).collect();
                if f.len() != 3 {
                    let shown = if f.len() == 4 {
                        "4 or more".to_string()
                    } else {
                        f.len().to_string()
                    };
                    return Err(at(
                        ln,
                        format!("expected 3 fields \"row col value\", found {shown}"),
                    ));
                }
                if count == declared {
                    return Err(at(
                        ln,
                        format!(
                            "more entries than the {declared} declared on the size line (line {sl})"
                        ),
                    ));
                }
                let r = parse_index(f[0], n, "row").map_err(|m| at(ln, m))?;
                let c = parse_index(f[1], n, "column").map_err(|m| at(ln, m))?;
                let v = parse_value(ln, f[2])?;
                count += 1;
                triplets.push((r, c, v));
                if symmetric && r != c {
                    if r > c {
                        lower_at.get_or_insert((ln, r, c));
                    } else {
                        upper_at.get_or_insert((ln, r, c));
                    }
                    if let (Some((l1, r1, c1)), Some((l2, r2, c2))) = (lower_at, upper_at) {
                        return Err(at(
                            ln,
                            format!(
                                "symmetric file stores entries on both sides of the diagonal \
                                 (line {l1}: row {} col {}; line {l2}: row {} col {}); \
                                 store only the lower triangle (row ≥ col)",
                                r1 + 1,
                                c1 + 1,
                                r2 + 1,
                                c2 + 1
                            ),
                        ));
                    }
                    triplets.push((c, r, v));
                }
            }
        }
        MmFormat::Array => {
            // Column-major; symmetric stores column j from row j down.
            let (mut i, mut j) = (0usize, 0usize);
            for (ln, line) in lines {
                let t = line.trim();
                if t.is_empty() || t.starts_with('%') {
                    continue;
                }
                for tok in t.split_ascii_whitespace() {
                    if count == declared {
                        return Err(at(
                            ln,
                            format!(
                                "more values than the {declared} expected for a {n}×{n} {storage} array"
                            ),
                        ));
                    }
                    let v = parse_value(ln, tok)?;
                    if v.to_bits() != 0 {
                        triplets.push((i, j, v));
                        if symmetric && i != j {
                            triplets.push((j, i, v));
                        }
                    }
                    count += 1;
                    i += 1;
                    if i == n {
                        j += 1;
                        i = if symmetric { j } else { 0 };
                    }
                }
            }
        }
    }
    if count < declared {
        return Err(Error::io(
            origin,
            format!(
                "truncated: the size line (line {sl}) declares {declared} entries but the file ends after {count}"
            ),
        ));
    }
    Stiffness::from_triplets(n, &triplets).map_err(|e| Error::io(origin, bare_message(e)))
}

/// Parses a 1-based Matrix Market index into a 0-based one, with a message on failure.
fn parse_index(tok: &str, n: usize, what: &str) -> std::result::Result<usize, String> {
    let numeric = {
        let t = tok.strip_prefix(['-', '+']).unwrap_or(tok);
        !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit())
    };
    match tok.parse::<usize>() {
        Ok(i) if (1..=n).contains(&i) => Ok(i - 1),
        _ if numeric => Err(format!(
            "{what} index {} is out of range (1..={n}; Matrix Market indices are 1-based)",
            clip(tok)
        )),
        _ => Err(format!("{what} index \"{}\" is not an integer", clip(tok))),
    }
}

/// Shortens a token for an error message.
fn clip(s: &str) -> String {
    const MAX: usize = 40;
    if s.chars().count() <= MAX {
        s.to_owned()
    } else {
        let mut t: String = s.chars().take(MAX).collect();
        t.push('…');
        t
    }
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

/// Formats an f64 so that Rust's `str::parse::<f64>` (and this module's JSON reader) gives
/// back the identical bits: integers below 10¹⁵ as integers, everything else in shortest
/// round-trip form (`{:?}`, e.g. `0.1`, `-0.0`, `1e-300`). The value must be finite.
fn fmt_f64(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 && !(v == 0.0 && v.is_sign_negative()) {
        format!("{}", v as i64)
    } else {
        format!("{v:?}")
    }
}

/// `true` if K equals its transpose bit for bit, including the sparsity structure (so that
/// writing one triangle and mirroring it reproduces K exactly).
fn exactly_symmetric(k: &Stiffness) -> bool {
    match k {
        Stiffness::Dense(m) => {
            let n = m.nrows();
            (0..n).all(|j| (0..j).all(|i| m[(i, j)].to_bits() == m[(j, i)].to_bits()))
        }
        Stiffness::Sparse(_) => {
            let mut map = std::collections::HashMap::with_capacity(k.nnz());
            k.for_each_entry(|i, j, v| {
                map.insert((i, j), v.to_bits());
            });
            map.iter()
                .all(|(&(i, j), &b)| i == j || map.get(&(j, i)) == Some(&b))
        }
    }
}

/// Writes K in Matrix Market coordinate format (1-based). Dense K: only entries whose bits
/// are not `+0.0` are written.
fn write_mm_body(w: &mut impl Write, k: &Stiffness) -> std::io::Result<()> {
    let n = k.n();
    let symmetric = exactly_symmetric(k);
    let dense = !k.is_sparse();
    let keep = |i: usize, j: usize, v: f64| (!symmetric || i >= j) && !(dense && v.to_bits() == 0);
    let mut nnz = 0usize;
    k.for_each_entry(|i, j, v| nnz += usize::from(keep(i, j, v)));
    writeln!(
        w,
        "%%MatrixMarket matrix coordinate real {}",
        if symmetric { "symmetric" } else { "general" }
    )?;
    writeln!(w, "% written by penalty-lab {}", env!("CARGO_PKG_VERSION"))?;
    writeln!(w, "{n} {n} {nnz}")?;
    let mut res = Ok(());
    k.for_each_entry(|i, j, v| {
        if res.is_ok() && keep(i, j, v) {
            res = writeln!(w, "{} {} {}", i + 1, j + 1, fmt_f64(v));
        }
    });
    res
}

/// Writes K to a Matrix Market file: `coordinate real symmetric` (lower triangle) when K
/// is exactly symmetric, `coordinate real general` otherwise; values in shortest
/// round-trip form, so [`read_matrix_market`] gives back identical bits. The file is
/// written atomically (temporary file + rename). Non-finite entries are an error.
pub fn write_matrix_market(path: &Path, k: &Stiffness) -> Result<()> {
    if !k.all_finite() {
        return Err(Error::io(
            path.display(),
            "cannot write: the stiffness matrix contains NaN or Inf",
        ));
    }
    TempFile::write_with(path, |w| write_mm_body(w, k))?.persist()
}

/// Checks what [`Problem::new`] checks, for a problem whose public fields may have been
/// changed since: anything written must be readable again.
fn check_writable(p: &Problem) -> std::result::Result<(), String> {
    let n = p.k.n();
    if n == 0 {
        return Err("the stiffness matrix is empty".into());
    }
    if p.q.len() != n {
        return Err(format!(
            "load vector has {} entries but K is {n}×{n}",
            p.q.len()
        ));
    }
    if !p.k.all_finite() {
        return Err("the stiffness matrix contains NaN or Inf (JSON cannot hold them)".into());
    }
    if let Some(i) = p.q.iter().position(|v| !v.is_finite()) {
        return Err(format!("load entry {i} is not finite"));
    }
    let mut seen = vec![false; n];
    for (c, con) in p.constraints.iter().enumerate() {
        if con.dof >= n {
            return Err(format!(
                "constraint {c}: DOF {} is out of range (N = {n})",
                con.dof
            ));
        }
        if !con.limit.is_finite() {
            return Err(format!("constraint {c}: limit is not finite"));
        }
        if std::mem::replace(&mut seen[con.dof], true) {
            return Err(format!(
                "constraint {c}: DOF {} is constrained twice",
                con.dof
            ));
        }
    }
    Ok(())
}

fn write_number_list(w: &mut impl Write, xs: &[f64]) -> std::io::Result<()> {
    w.write_all(b"[")?;
    for (i, &x) in xs.iter().enumerate() {
        if i > 0 {
            w.write_all(b", ")?;
        }
        w.write_all(fmt_f64(x).as_bytes())?;
    }
    w.write_all(b"]")
}

/// Writes a scene file.
///
/// The stiffness goes to a sibling Matrix Market file `<stem>.mtx` (where `path` is
/// `<stem>.scene.json`, or `<stem>.json`) when it is sparse or `N > mtx_threshold`, and
/// is referenced as `{"matrix_market": "<stem>.mtx"}`; otherwise it is written inline as
/// dense rows. `meta`, if given, is written as the `"meta"` object. Numbers are written in
/// shortest round-trip form: [`read_scene`] gives back K, q and the constraints bit for bit
/// (a dense K written to Matrix Market reads back as sparse storage with identical values;
/// its exact `+0.0` entries are not stored). Both files are written to temporary files in
/// the target directory and renamed into place (the `.mtx` first), so an error never
/// leaves a half-written file.
pub fn write_scene(
    path: &Path,
    scene_name: &str,
    problem: &Problem,
    meta: Option<&serde_json::Value>,
    mtx_threshold: usize,
) -> Result<()> {
    let origin = path.display().to_string();
    check_writable(problem).map_err(|m| Error::io(&origin, format!("cannot write scene: {m}")))?;
    let file_name = path
        .file_name()
        .and_then(|s| s.to_str())
        .ok_or_else(|| Error::io(&origin, "scene path must end in a UTF-8 file name"))?;
    let stem = file_name
        .strip_suffix(".scene.json")
        .or_else(|| file_name.strip_suffix(".json"))
        .unwrap_or(file_name);
    let mtx_name = format!("{stem}.mtx");
    let use_mtx = problem.k.is_sparse() || problem.n() > mtx_threshold;

    let to_io = |e: serde_json::Error| std::io::Error::other(e.to_string());
    let body = |w: &mut BufWriter<fs::File>| -> std::io::Result<()> {
        writeln!(w, "{{")?;
        writeln!(
            w,
            "  \"name\": {},",
            serde_json::to_string(scene_name).map_err(to_io)?
        )?;
        if use_mtx {
            writeln!(
                w,
                "  \"stiffness\": {{\"matrix_market\": {}}},",
                serde_json::to_string(&mtx_name).map_err(to_io)?
            )?;
        } else {
            writeln!(w, "  \"stiffness\": {{\"dense\": [")?;
            let k = &problem.k;
            let n = k.n();
            let mut row = vec![0.0; n];
            for i in 0..n {
                for (j, r) in row.iter_mut().enumerate() {
                    *r = k.get(i, j);
                }
                w.write_all(b"    ")?;
                write_number_list(w, &row)?;
                writeln!(w, "{}", if i + 1 < n { "," } else { "" })?;
            }
            writeln!(w, "  ]}},")?;
        }
        w.write_all(b"  \"load\": ")?;
        write_number_list(w, &problem.q)?;
        writeln!(w, ",")?;
        if problem.constraints.is_empty() {
            write!(w, "  \"constraints\": []")?;
        } else {
            writeln!(w, "  \"constraints\": [")?;
            let m = problem.constraints.len();
            for (c, con) in problem.constraints.iter().enumerate() {
                let kind = match con.kind {
                    ConstraintKind::Bilateral => "bilateral",
                    ConstraintKind::Upper => "upper",
                    ConstraintKind::Lower => "lower",
                };
                writeln!(
                    w,
                    "    {{\"dof\": {}, \"limit\": {}, \"kind\": \"{kind}\"}}{}",
                    con.dof,
                    fmt_f64(con.limit),
                    if c + 1 < m { "," } else { "" }
                )?;
            }
            write!(w, "  ]")?;
        }
        if let Some(meta) = meta {
            let text = serde_json::to_string_pretty(meta).map_err(to_io)?;
            write!(w, ",\n  \"meta\": {}", text.replace('\n', "\n  "))?;
        }
        writeln!(w, "\n}}")
    };

    if use_mtx {
        let mtx_path = path.with_file_name(&mtx_name);
        let mtx = TempFile::write_with(&mtx_path, |w| write_mm_body(w, &problem.k))?;
        let scene = TempFile::write_with(path, body)?;
        mtx.persist()?;
        scene.persist()
    } else {
        TempFile::write_with(path, body)?.persist()
    }
}

/// A temporary file next to its destination; removed on drop unless persisted.
struct TempFile {
    tmp: PathBuf,
    dest: PathBuf,
    persisted: bool,
}

impl TempFile {
    /// Creates `.<name>.<pid>.<n>.tmp` in the destination's directory and fills it.
    fn write_with(
        dest: &Path,
        fill: impl FnOnce(&mut BufWriter<fs::File>) -> std::io::Result<()>,
    ) -> Result<TempFile> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let origin = dest.display().to_string();
        let name = dest
            .file_name()
            .ok_or_else(|| Error::io(&origin, "not a file path"))?
            .to_string_lossy();
        let tmp = dest.with_file_name(format!(
            ".{name}.{}.{}.tmp",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let file = fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| {
                Error::io(
                    &origin,
                    format!("cannot create temporary file {}: {e}", tmp.display()),
                )
            })?;
        let guard = TempFile {
            tmp,
            dest: dest.to_path_buf(),
            persisted: false,
        };
        let mut w = BufWriter::new(file);
        fill(&mut w)
            .and_then(|()| w.into_inner().map_err(|e| e.into_error()))
            .and_then(|f| f.sync_all())
            .map_err(|e| Error::io(&origin, format!("cannot write: {e}")))?;
        Ok(guard)
    }

    /// Renames the temporary file onto its destination.
    fn persist(mut self) -> Result<()> {
        fs::rename(&self.tmp, &self.dest).map_err(|e| {
            Error::io(
                self.dest.display(),
                format!("cannot move {} into place: {e}", self.tmp.display()),
            )
        })?;
        self.persisted = true;
        Ok(())
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.persisted {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

// ---------------------------------------------------------------------------------------
// A small strict JSON parser (RFC 8259) with exact number conversion and locations.
// ---------------------------------------------------------------------------------------

mod json {
    use super::MAX_JSON_DEPTH;

    /// A JSON value with the 1-based line and column where it starts.
    pub(super) struct Node {
        pub v: Val,
        pub line: usize,
        pub col: usize,
    }

    pub(super) enum Val {
        Null,
        Bool(bool),
        /// `int` is set for literals without fraction or exponent that fit in i128.
        Num {
            value: f64,
            int: Option<i128>,
        },
        Str(String),
        Arr(Vec<Node>),
        /// Keys in document order (duplicates are rejected while parsing).
        Obj(Vec<(String, Node)>),
    }

    impl Val {
        /// "null", "a number", "an array", …
        pub fn describe(&self) -> &'static str {
            match self {
                Val::Null => "null",
                Val::Bool(_) => "a boolean",
                Val::Num { .. } => "a number",
                Val::Str(_) => "a string",
                Val::Arr(_) => "an array",
                Val::Obj(_) => "an object",
            }
        }
    }

    impl Node {
        /// Converts to a `serde_json::Value` (integers stay integers where they fit).
        pub fn to_value(&self) -> serde_json::Value {
            use serde_json::{Number, Value};
            match &self.v {
                Val::Null => Value::Null,
                Val::Bool(b) => Value::Bool(*b),
                Val::Num { value, int } => {
                    let exact = int.and_then(|i| {
                        u64::try_from(i)
                            .map(Number::from)
                            .or_else(|_| i64::try_from(i).map(Number::from))
                            .ok()
                    });
                    exact
                        .or_else(|| Number::from_f64(*value))
                        .map_or(Value::Null, Value::Number)
                }
                Val::Str(s) => Value::String(s.clone()),
                Val::Arr(items) => Value::Array(items.iter().map(Node::to_value).collect()),
                Val::Obj(fields) => Value::Object(
                    fields
                        .iter()
                        .map(|(k, v)| (k.clone(), v.to_value()))
                        .collect(),
                ),
            }
        }
    }

    /// The value of `key` in an object's fields.
    pub(super) fn get<'a>(fields: &'a [(String, Node)], key: &str) -> Option<&'a Node> {
        fields.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    /// A string quoted for a message, shortened if long.
    pub(super) fn quote_short(s: &str) -> String {
        let shown = super::clip(s);
        serde_json::to_string(&shown).unwrap_or(shown)
    }

    pub(super) struct ParseError {
        pub line: usize,
        pub col: usize,
        pub msg: String,
    }

    struct Parser<'a> {
        s: &'a str,
        b: &'a [u8],
        i: usize,
        line: usize,
        line_start: usize,
        /// (byte position, column) of the last column computed: columns are counted
        /// incrementally, so long one-line arrays cost O(length), not O(length²).
        col_cache: std::cell::Cell<(usize, usize)>,
    }

    type PResult<T> = Result<T, ParseError>;

    /// Parses a complete JSON document (a leading UTF-8 BOM is skipped).
    pub(super) fn parse(text: &str) -> PResult<Node> {
        let s = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut p = Parser {
            s,
            b: s.as_bytes(),
            i: 0,
            line: 1,
            line_start: 0,
            col_cache: std::cell::Cell::new((0, 0)),
        };
        p.ws();
        if p.i == p.b.len() {
            return Err(p.err("the file is empty (expected a JSON object)"));
        }
        let v = p.value(0)?;
        p.ws();
        if p.i != p.b.len() {
            return Err(p.err(format!(
                "unexpected {} after the end of the JSON value",
                p.found()
            )));
        }
        Ok(v)
    }

    impl Parser<'_> {
        fn col(&self) -> usize {
            let (pos, col) = self.col_cache.get();
            let (from, base) = if pos >= self.line_start && pos <= self.i {
                (pos, col)
            } else {
                (self.line_start, 0)
            };
            let c = base
                + self
                    .s
                    .get(from..self.i)
                    .map_or(self.i - from, |t| t.chars().count());
            self.col_cache.set((self.i, c));
            c + 1
        }

        fn err(&self, msg: impl Into<String>) -> ParseError {
            ParseError {
                line: self.line,
                col: self.col(),
                msg: msg.into(),
            }
        }

        /// Describes the character at the cursor.
        fn found(&self) -> String {
            match self.s.get(self.i..).and_then(|t| t.chars().next()) {
                None => "end of file".into(),
                Some(c) if c.is_control() => format!("character U+{:04X}", c as u32),
                Some(c) => format!("'{c}'"),
            }
        }

        fn peek(&self) -> Option<u8> {
            self.b.get(self.i).copied()
        }

        fn ws(&mut self) {
            while let Some(c) = self.peek() {
                match c {
                    b' ' | b'\t' | b'\r' => self.i += 1,
                    b'\n' => {
                        self.i += 1;
                        self.line += 1;
                        self.line_start = self.i;
                    }
                    _ => break,
                }
            }
        }

        fn value(&mut self, depth: usize) -> PResult<Node> {
            let (line, col) = (self.line, self.col());
            let v =
                match self.peek() {
                    Some(b'{') => self.object(depth)?,
                    Some(b'[') => self.array(depth)?,
                    Some(b'"') => Val::Str(self.string()?),
                    Some(b'-' | b'0'..=b'9') => self.number()?,
                    Some(b't') => self.literal("true", Val::Bool(true))?,
                    Some(b'f') => self.literal("false", Val::Bool(false))?,
                    Some(b'n') => self.literal("null", Val::Null)?,
                    Some(b'N' | b'I') => return Err(self.err(
                        "NaN and Infinity are not valid JSON numbers (all values must be finite)",
                    )),
                    Some(b']' | b'}') => {
                        return Err(self.err(format!(
                            "expected a value, found {} (trailing comma?)",
                            self.found()
                        )))
                    }
                    _ => return Err(self.err(format!("expected a value, found {}", self.found()))),
                };
            Ok(Node { v, line, col })
        }

        fn literal(&mut self, word: &str, v: Val) -> PResult<Val> {
            if self.b[self.i..].starts_with(word.as_bytes()) {
                self.i += word.len();
                Ok(v)
            } else {
                Err(self.err(format!(
                    "invalid literal (expected true, false or null), found {}",
                    self.found()
                )))
            }
        }

        fn enter(&self, depth: usize) -> PResult<usize> {
            if depth >= MAX_JSON_DEPTH {
                Err(self.err(format!(
                    "nesting deeper than {MAX_JSON_DEPTH} levels is not supported"
                )))
            } else {
                Ok(depth + 1)
            }
        }

        fn array(&mut self, depth: usize) -> PResult<Val> {
            let depth = self.enter(depth)?;
            self.i += 1; // '['
            let mut items = Vec::new();
            self.ws();
            if self.peek() == Some(b']') {
                self.i += 1;
                return Ok(Val::Arr(items));
            }
            loop {
                self.ws();
                items.push(self.value(depth)?);
                self.ws();
                match self.peek() {
                    Some(b',') => self.i += 1,
                    Some(b']') => {
                        self.i += 1;
                        return Ok(Val::Arr(items));
                    }
                    _ => {
                        return Err(self.err(format!(
                            "expected ',' or ']' in array, found {}",
                            self.found()
                        )))
                    }
                }
            }
        }

        fn object(&mut self, depth: usize) -> PResult<Val> {
            let depth = self.enter(depth)?;
            self.i += 1; // '{'
            let mut fields: Vec<(String, Node)> = Vec::new();
            let mut keys = std::collections::HashSet::new();
            self.ws();
            if self.peek() == Some(b'}') {
                self.i += 1;
                return Ok(Val::Obj(fields));
            }
            loop {
                self.ws();
                if self.peek() != Some(b'"') {
                    return Err(self.err(format!(
                        "expected a quoted key in object, found {}{}",
                        self.found(),
                        if self.peek() == Some(b'}') {
                            " (trailing comma?)"
                        } else {
                            ""
                        }
                    )));
                }
                let key_err = self.err("");
                let key = self.string()?;
                if !keys.insert(key.clone()) {
                    return Err(ParseError {
                        msg: format!("duplicate key {}", quote_short(&key)),
                        ..key_err
                    });
                }
                self.ws();
                if self.peek() != Some(b':') {
                    return Err(self.err(format!(
                        "expected ':' after object key, found {}",
                        self.found()
                    )));
                }
                self.i += 1;
                self.ws();
                let v = self.value(depth)?;
                fields.push((key, v));
                self.ws();
                match self.peek() {
                    Some(b',') => self.i += 1,
                    Some(b'}') => {
                        self.i += 1;
                        return Ok(Val::Obj(fields));
                    }
                    _ => {
                        return Err(self.err(format!(
                            "expected ',' or '}}' in object, found {}",
                            self.found()
                        )))
                    }
                }
            }
        }

        fn string(&mut self) -> PResult<String> {
            self.i += 1; // opening quote
            let mut out = String::new();
            loop {
                let Some(c) = self.s.get(self.i..).and_then(|t| t.chars().next()) else {
                    return Err(self.err("unterminated string"));
                };
                match c {
                    '"' => {
                        self.i += 1;
                        return Ok(out);
                    }
                    '\\' => {
                        self.i += 1;
                        let Some(e) = self.peek() else {
                            return Err(self.err("unterminated string"));
                        };
                        self.i += 1;
                        match e {
                            b'"' => out.push('"'),
                            b'\\' => out.push('\\'),
                            b'/' => out.push('/'),
                            b'b' => out.push('\u{8}'),
                            b'f' => out.push('\u{c}'),
                            b'n' => out.push('\n'),
                            b'r' => out.push('\r'),
                            b't' => out.push('\t'),
                            b'u' => out.push(self.unicode_escape()?),
                            _ => {
                                self.i -= 1;
                                return Err(self.err(format!(
                                    "invalid escape sequence '\\{}' in string",
                                    self.found().trim_matches('\'')
                                )));
                            }
                        }
                    }
                    c if (c as u32) < 0x20 => {
                        return Err(self.err(
                            "control character (e.g. a line break) inside a string; escape it",
                        ))
                    }
                    c => {
                        out.push(c);
                        self.i += c.len_utf8();
                    }
                }
            }
        }

        fn hex4(&mut self) -> PResult<u32> {
            let digits = self
                .s
                .get(self.i..self.i + 4)
                .filter(|t| t.bytes().all(|b| b.is_ascii_hexdigit()))
                .ok_or_else(|| self.err("invalid \\u escape (expected 4 hex digits)"))?;
            let v = u32::from_str_radix(digits, 16)
                .map_err(|_| self.err("invalid \\u escape (expected 4 hex digits)"))?;
            self.i += 4;
            Ok(v)
        }

        fn unicode_escape(&mut self) -> PResult<char> {
            let hi = self.hex4()?;
            let code = if (0xD800..0xDC00).contains(&hi) {
                if !self.b[self.i..].starts_with(b"\\u") {
                    return Err(self.err("unpaired UTF-16 surrogate in \\u escape"));
                }
                self.i += 2;
                let lo = self.hex4()?;
                if !(0xDC00..0xE000).contains(&lo) {
                    return Err(self.err("unpaired UTF-16 surrogate in \\u escape"));
                }
                0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00)
            } else {
                hi
            };
            char::from_u32(code).ok_or_else(|| self.err("unpaired UTF-16 surrogate in \\u escape"))
        }

        fn digits(&mut self) -> usize {
            let start = self.i;
            while matches!(self.peek(), Some(b'0'..=b'9')) {
                self.i += 1;
            }
            self.i - start
        }

        fn number(&mut self) -> PResult<Val> {
            let start = self.i;
            let start_err = self.err("");
            if self.peek() == Some(b'-') {
                self.i += 1;
                if matches!(self.peek(), Some(b'I' | b'N')) {
                    return Err(self.err(
                        "NaN and Infinity are not valid JSON numbers (all values must be finite)",
                    ));
                }
            }
            match self.peek() {
                Some(b'0') => {
                    self.i += 1;
                    if matches!(self.peek(), Some(b'0'..=b'9')) {
                        return Err(self.err("invalid number: leading zeros are not allowed"));
                    }
                }
                Some(b'1'..=b'9') => {
                    self.digits();
                }
                _ => {
                    return Err(self.err(format!(
                        "invalid number: expected a digit, found {}",
                        self.found()
                    )))
                }
            }
            let mut integer = true;
            if self.peek() == Some(b'.') {
                integer = false;
                self.i += 1;
                if self.digits() == 0 {
                    return Err(self.err(format!(
                        "invalid number: expected a digit after '.', found {}",
                        self.found()
                    )));
                }
            }
            if matches!(self.peek(), Some(b'e' | b'E')) {
                integer = false;
                self.i += 1;
                if matches!(self.peek(), Some(b'+' | b'-')) {
                    self.i += 1;
                }
                if self.digits() == 0 {
                    return Err(self.err(format!(
                        "invalid number: expected a digit in the exponent, found {}",
                        self.found()
                    )));
                }
            }
            let text = &self.s[start..self.i];
            // Correctly rounded (unlike serde_json's default float parser).
            let value: f64 = text.parse().map_err(|_| ParseError {
                msg: format!("invalid number {}", super::clip(text)),
                ..self.err("")
            })?;
            if !value.is_finite() {
                return Err(ParseError {
                    msg: format!(
                        "number {} is not finite: it overflows f64 (|x| must be at most 1.7976931348623157e308)",
                        super::clip(text)
                    ),
                    ..start_err
                });
            }
            let int = if integer {
                text.parse::<i128>().ok()
            } else {
                None
            };
            Ok(Val::Num { value, int })
        }
    }
}
