//! Writing scene files: the JSON of [`write_scene`] (K inline or in a sibling Matrix Market
//! file), numbers in shortest round-trip form, written atomically.

use super::matrix_market::{self, fmt_f64};
use crate::error::{Error, Result};
use crate::provenance::write_atomic;
use crate::system::{ConstraintKind, Problem};
use std::io::Write;
use std::path::Path;

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
    crate::system::check_constraints(&p.constraints, n).map_err(|e| e.bare_message())?;
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

/// How [`write_scene_as`] stores the stiffness.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    /// Matrix Market (sibling `.mtx`) when K is sparse or `N > mtx_threshold`, else inline
    /// dense rows.
    Auto {
        /// Largest N of a dense K written inline.
        mtx_threshold: usize,
    },
    /// Inline dense rows whatever K's storage (every entry written, zeros included).
    Dense,
}

/// The `"constraints"` member (without a trailing comma or newline).
fn write_constraints(w: &mut impl Write, problem: &Problem) -> std::io::Result<()> {
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
            match con.single_dof() {
                Some(d) => write!(w, "    {{\"dof\": {d}")?,
                None => {
                    w.write_all(b"    {\"terms\": [")?;
                    for (t, &(d, a)) in con.terms.iter().enumerate() {
                        let sep = if t > 0 { ", " } else { "" };
                        write!(w, "{sep}[{d}, {}]", fmt_f64(a))?;
                    }
                    w.write_all(b"]")?;
                }
            }
            writeln!(
                w,
                ", \"limit\": {}, \"kind\": \"{kind}\"}}{}",
                fmt_f64(con.limit),
                if c + 1 < m { "," } else { "" }
            )?;
        }
        write!(w, "  ]")?;
    }
    Ok(())
}

/// Writes a scene file: [`write_scene_as`] with [`Storage::Auto`].
pub fn write_scene(
    path: &Path,
    scene_name: &str,
    problem: &Problem,
    meta: Option<&serde_json::Value>,
    mtx_threshold: usize,
) -> Result<()> {
    write_scene_as(
        path,
        scene_name,
        problem,
        meta,
        Storage::Auto { mtx_threshold },
    )
}

/// Writes a scene file.
///
/// With [`Storage::Auto`] the stiffness goes to a sibling Matrix Market file `<stem>.mtx`
/// (where `path` is `<stem>.scene.json`, or `<stem>.json`) when it is sparse or
/// `N > mtx_threshold`, and is referenced as `{"matrix_market": "<stem>.mtx"}`; otherwise
/// (and always with [`Storage::Dense`]) it is written inline as dense rows. `meta`, if given, is written as the `"meta"` object. Numbers are written in
/// shortest round-trip form: [`read_scene`](super::read_scene) gives back K, q and the constraints bit for bit
/// (a dense K written to Matrix Market reads back as sparse storage with identical values;
/// its exact `+0.0` entries are not stored). Both files are written with
/// [`write_atomic`] (the `.mtx` first), so an error
/// never leaves a half-written file. A problem with a near-null space writes B to
/// `<stem>.B.mtx` (dense array) and names it with its `block_size`.
pub fn write_scene_as(
    path: &Path,
    scene_name: &str,
    problem: &Problem,
    meta: Option<&serde_json::Value>,
    storage: Storage,
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
    let b_name = format!("{stem}.B.mtx");
    let use_mtx = match storage {
        Storage::Auto { mtx_threshold } => problem.k.is_sparse() || problem.n() > mtx_threshold,
        Storage::Dense => false,
    };

    let to_io = |e: serde_json::Error| std::io::Error::other(e.to_string());
    let body = |w: &mut Vec<u8>| -> std::io::Result<()> {
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
        write_constraints(w, problem)?;
        if let Some(nn) = &problem.near_null {
            write!(
                w,
                ",\n  \"near_null_space\": {{\"matrix_market\": {}",
                serde_json::to_string(&b_name).map_err(to_io)?
            )?;
            if let Some(slots) = &nn.slots {
                write!(w, ", \"slots\": ")?;
                let s = serde_json::to_string(slots).map_err(to_io)?;
                w.write_all(s.as_bytes())?;
            }
            write!(w, "}}")?;
            let bs = problem.near_null.as_ref().map_or(1, |nn| nn.block_size);
            write!(w, ",\n  \"block_size\": {bs}")?;
        }
        if let Some(meta) = meta {
            let text = serde_json::to_string_pretty(meta).map_err(to_io)?;
            write!(w, ",\n  \"meta\": {}", text.replace('\n', "\n  "))?;
        }
        writeln!(w, "\n}}")
    };

    // Both files are formatted in memory first, so nothing is written unless both are
    // complete; the `.mtx` is moved into place before the scene that names it.
    let mut text = Vec::new();
    body(&mut text).map_err(|e| Error::io(&origin, format!("cannot write: {e}")))?;
    if use_mtx {
        let mtx_path = path.with_file_name(&mtx_name);
        write_atomic(&mtx_path, &matrix_market::matrix_market_bytes(&problem.k))?;
    }
    if let Some(nn) = &problem.near_null {
        matrix_market::write_matrix_market_dense(
            &path.with_file_name(&b_name),
            nn.padded_n(),
            nn.k,
            &nn.b,
        )?;
    }
    write_atomic(path, &text)
}
