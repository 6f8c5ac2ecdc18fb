//! Matrix Market stiffness files: the reader behind a scene's `"matrix_market"` stiffness
//! and the writer behind [`super::write_scene`].
//!
//! # Why a hand-written reader
//!
//! The alternatives do not meet the scene contract: `nalgebra_sparse::io`'s pest-based
//! reader panics on some malformed input (e.g. an index too large for `usize`) and gives
//! errors without line numbers. This line-based reader never panics and names the file and
//! the line in every error, e.g. `K.mtx: line 7: expected 3 fields "row col value", found 2`.
//!
//! It returns [`Stiffness::Sparse`] (never densified), expands `symmetric` storage (one
//! triangle stored; the lower one by convention, an upper-only file is accepted, a file with
//! entries on both sides of the diagonal is rejected), sums duplicate entries, and rejects
//! `complex`, `pattern`, `skew-symmetric` and `hermitian` files, non-square or empty
//! matrices, truncated files, indices out of range and NaN/Inf values. `array` files are
//! supported; their exact `+0.0` entries are not stored. Dimensions above [`MAX_DIM`] are
//! refused (the sparse structure allocates O(N) memory up front).
//!
//! # Writing
//!
//! [`write_matrix_market`] writes `coordinate real symmetric` (lower triangle) or
//! `coordinate real general` with values in shortest round-trip form, so
//! [`read_matrix_market`] gives back identical bits.

use super::bare_message;
use super::json_error::clip;
use crate::error::{Error, Result};
use crate::provenance::write_atomic;
use crate::system::Stiffness;
use std::fs;
use std::io::Write;
use std::path::Path;

/// Largest accepted matrix dimension N in a Matrix Market file (2²⁴ ≈ 16.8 million).
///
/// A guard against a corrupt or hostile size line: the sparse structure allocates O(N)
/// memory before any entry is read.
pub const MAX_DIM: usize = 1 << 24;

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
    let (n, _, triplets) = parse_entries(text, origin, true)?;
    Stiffness::from_triplets(n, &triplets).map_err(|e| Error::io(origin, bare_message(e)))
}

/// Reads a Matrix Market file of any shape (`rows × cols`, e.g. the constraint matrix of a
/// scene: one row per constraint) as its entries `(row, column, value)`, 0-based, in file
/// order (symmetric storage expanded; an `array` file's exact `+0.0` skipped; duplicates
/// kept for the caller to judge). The same header, size and entry checks as
/// [`read_matrix_market`], errors naming the file and the line.
pub fn read_matrix_market_entries(path: &Path) -> Result<MatrixEntries> {
    let origin = path.display().to_string();
    let bytes = fs::read(path).map_err(|e| Error::io(&origin, format!("cannot read file: {e}")))?;
    let text = String::from_utf8_lossy(&bytes);
    parse_entries(&text, &origin, false)
}

/// A matrix as `(rows, columns, entries (row, column, value))`.
pub type MatrixEntries = (usize, usize, Vec<(usize, usize, f64)>);

/// The entries of Matrix Market text, square where `square`.
fn parse_entries(text: &str, origin: &str, square: bool) -> Result<MatrixEntries> {
    let src = Src { origin };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let number: fn((usize, &str)) -> (usize, &str) = |(i, l)| (i + 1, l);
    let mut lines: Lines = text.lines().enumerate().map(number);
    let h = parse_header(src, &mut lines)?;
    if !square && h.symmetric {
        return Err(Error::io(
            origin,
            "line 1: a constraint matrix D must be `general` (a `symmetric` header would mirror \
             entries into other constraints' rows)",
        ));
    }
    let (sl, nr, nc, declared) = parse_size(src, &mut lines, h, square)?;
    let body = Body {
        h,
        nr,
        nc,
        declared,
        sl,
    };
    let mut triplets: Vec<(usize, usize, f64)> =
        Vec::with_capacity(declared.min(1 << 16) * if h.symmetric { 2 } else { 1 });
    let count = match h.format {
        MmFormat::Coordinate => read_coordinate(src, lines, body, &mut triplets)?,
        MmFormat::Array => read_array(src, lines, body, &mut triplets)?,
    };
    if count < declared {
        return Err(Error::io(
            origin,
            format!(
                "truncated: the size line (line {sl}) declares {declared} entries but the file ends after {count}"
            ),
        ));
    }
    Ok((nr, nc, triplets))
}

/// The header line's format, field and symmetry.
#[derive(Clone, Copy)]
struct Header {
    format: MmFormat,
    field: MmField,
    symmetric: bool,
}

/// The source of the text being parsed, for error messages.
#[derive(Clone, Copy)]
struct Src<'a> {
    origin: &'a str,
}

impl Src<'_> {
    /// An error at `line` of the source.
    fn at(self, line: usize, msg: String) -> Error {
        Error::parse(self.origin, line, msg)
    }
}

/// A numbered line iterator over the text (1-based line numbers).
type Lines<'t> = std::iter::Map<
    std::iter::Enumerate<std::str::Lines<'t>>,
    fn((usize, &'t str)) -> (usize, &'t str),
>;

/// Parses the header line (`%%MatrixMarket matrix <format> <field> <symmetry>`).
fn parse_header(src: Src, lines: &mut Lines) -> Result<Header> {
    let origin = src.origin;
    let at = |line: usize, msg: String| src.at(line, msg);
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
    let unknown = |i: usize, what: &str, expected: &str| {
        at(
            hl,
            format!("unknown {what} \"{}\" (expected {expected})", clip(toks[i])),
        )
    };
    let format = match lower[2].as_str() {
        "coordinate" => MmFormat::Coordinate,
        "array" => MmFormat::Array,
        _ => return Err(unknown(2, "format", "coordinate or array")),
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
        _ => return Err(unknown(3, "field", "real or integer")),
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
        _ => return Err(unknown(4, "symmetry", "general or symmetric")),
    };

    Ok(Header {
        format,
        field,
        symmetric,
    })
}

/// Parses the size line (after comments and blank lines): returns its line number, the rows
/// and columns (equal where `square`, and for symmetric storage) and the number of entries
/// the file declares (all stored ones for `array`).
fn parse_size(
    src: Src,
    lines: &mut Lines,
    h: Header,
    square: bool,
) -> Result<(usize, usize, usize, usize)> {
    let (origin, format, symmetric) = (src.origin, h.format, h.symmetric);
    let at = |line: usize, msg: String| src.at(line, msg);
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
    if square && nr != nc {
        return Err(at(
            sl,
            format!("matrix is not square: {nr} rows × {nc} columns (K must be N×N)"),
        ));
    }
    if symmetric && nr != nc {
        return Err(at(
            sl,
            format!("a symmetric matrix must be square, not {nr} rows × {nc} columns"),
        ));
    }
    if nr == 0 || nc == 0 {
        return Err(at(sl, format!("matrix is empty ({nr}×{nc})")));
    }
    if let Some(big) = [nr, nc].into_iter().find(|&d| d > MAX_DIM) {
        return Err(at(
            sl,
            format!("matrix dimension N = {big} exceeds the supported maximum {MAX_DIM}"),
        ));
    }
    let (r128, c128) = (nr as u128, nc as u128);
    let capacity = if symmetric {
        r128 * (r128 + 1) / 2
    } else {
        r128 * c128
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
                "size line declares {declared} entries but a {nr}×{nc} {storage} matrix stores at most {capacity}"
            ),
        ));
    }

    // ≤ capacity ≤ MAX_DIM², fits in 64-bit usize
    Ok((sl, nr, nc, declared as usize))
}

/// One value token as f64 (integer or real field, Fortran `D` exponents accepted); errors on
/// non-numbers and non-finite values.
fn parse_value(src: Src, field: MmField, ln: usize, tok: &str) -> Result<f64> {
    let at = |line: usize, msg: String| src.at(line, msg);
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
}

/// What a body reader needs: the header, N, the declared entry count and the size line's
/// number (for messages).
#[derive(Clone, Copy)]
struct Body {
    h: Header,
    nr: usize,
    nc: usize,
    declared: usize,
    sl: usize,
}

/// Reads the `coordinate` body into `triplets` (symmetric storage expanded); returns the
/// number of entries read.
fn read_coordinate(
    src: Src,
    lines: Lines,
    body: Body,
    triplets: &mut Vec<(usize, usize, f64)>,
) -> Result<usize> {
    let Body {
        h,
        nr,
        nc,
        declared,
        sl,
    } = body;
    let symmetric = h.symmetric;
    let at = |line: usize, msg: String| src.at(line, msg);
    let mut count = 0usize;
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
                format!("more entries than the {declared} declared on the size line (line {sl})"),
            ));
        }
        let r = parse_index(f[0], nr, "row").map_err(|m| at(ln, m))?;
        let c = parse_index(f[1], nc, "column").map_err(|m| at(ln, m))?;
        let v = parse_value(src, h.field, ln, f[2])?;
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
    Ok(count)
}

/// Reads the `array` body (column-major; symmetric stores column j from row j down) into
/// `triplets`, skipping exact `+0.0`; returns the number of values read.
fn read_array(
    src: Src,
    lines: Lines,
    body: Body,
    triplets: &mut Vec<(usize, usize, f64)>,
) -> Result<usize> {
    let Body {
        h,
        nr,
        nc,
        declared,
        ..
    } = body;
    let symmetric = h.symmetric;
    let storage = if symmetric { "symmetric" } else { "general" };
    let at = |line: usize, msg: String| src.at(line, msg);
    let mut count = 0usize;
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
                        "more values than the {declared} expected for a {nr}×{nc} {storage} array"
                    ),
                ));
            }
            let v = parse_value(src, h.field, ln, tok)?;
            if v.to_bits() != 0 {
                triplets.push((i, j, v));
                if symmetric && i != j {
                    triplets.push((j, i, v));
                }
            }
            count += 1;
            i += 1;
            if i == nr {
                j += 1;
                i = if symmetric { j } else { 0 };
            }
        }
    }
    Ok(count)
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

/// K in Matrix Market coordinate format (1-based), as the bytes of a file. Dense K: only
/// entries whose bits are not `+0.0` are written.
pub(super) fn matrix_market_bytes(k: &Stiffness) -> Vec<u8> {
    let mut out = Vec::with_capacity(64 + 32 * k.nnz());
    write_mm_body(&mut out, k).expect("writing to a Vec<u8> cannot fail");
    out
}

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
/// written atomically ([`write_atomic`]). Non-finite entries are an error.
pub fn write_matrix_market(path: &Path, k: &Stiffness) -> Result<()> {
    if !k.all_finite() {
        return Err(Error::io(
            path.display(),
            "cannot write: the stiffness matrix contains NaN or Inf",
        ));
    }
    write_atomic(path, &matrix_market_bytes(k))
}

/// Writes a vector as a one-column Matrix Market `array real general` file (values in shortest
/// round-trip form, atomically): the right-hand side beside a matrix written by
/// [`write_matrix_market`]. Non-finite entries are an error.
pub fn write_matrix_market_vector(path: &Path, v: &[f64]) -> Result<()> {
    write_matrix_market_dense(path, v.len(), 1, v)
}

/// Writes a dense `rows × cols` matrix given column-major (`a[c·rows + r]`) as a Matrix
/// Market `array real general` file (shortest round-trip values, atomically), e.g. a
/// near-null space B. Non-finite entries or a length other than rows·cols are an error.
pub fn write_matrix_market_dense(path: &Path, rows: usize, cols: usize, a: &[f64]) -> Result<()> {
    if a.len() != rows * cols {
        return Err(Error::io(
            path.display(),
            format!(
                "cannot write: {} values for a {rows} × {cols} matrix",
                a.len()
            ),
        ));
    }
    if let Some(i) = a.iter().position(|x| !x.is_finite()) {
        return Err(Error::io(
            path.display(),
            format!(
                "cannot write: entry ({}, {}) is {}",
                i % rows.max(1),
                i / rows.max(1),
                a[i]
            ),
        ));
    }
    let mut text = format!("%%MatrixMarket matrix array real general\n{rows} {cols}\n");
    for &x in a {
        text.push_str(&fmt_f64(x));
        text.push('\n');
    }
    write_atomic(path, text.as_bytes())
}

/// Formats an f64 so that Rust's `str::parse::<f64>` and `serde_json` (with `float_roundtrip`) give
/// back the identical bits: integers below 10¹⁵ as integers, everything else in shortest
/// round-trip form (`{:?}`, e.g. `0.1`, `-0.0`, `1e-300`). The value must be finite.
pub(crate) fn fmt_f64(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 && !(v == 0.0 && v.is_sign_negative()) {
        format!("{}", v as i64)
    } else {
        format!("{v:?}")
    }
}
