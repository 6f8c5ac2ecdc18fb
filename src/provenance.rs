//! Provenance for result files: git commit, crate versions, atomic writes.

use crate::error::{Error, Result};
use std::path::Path;

/// `--version` of every binary: the crate version and the git commit it was built from
/// (`-dirty` when tracked files differed from it).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("PENALTY_LAB_GIT_COMMIT"),
    ")"
);

/// The git commit this binary was built from (captured at build time by `build.rs`), with a
/// `-dirty` suffix when tracked files differed from it; `"unknown"` when built outside a git
/// checkout. Independent of the directory the binary runs in.
pub fn git_commit() -> String {
    env!("PENALTY_LAB_GIT_COMMIT").to_string()
}

/// Versions of penalty-lab and its main dependencies, read from Cargo.lock at build time.
pub fn crate_versions() -> serde_json::Value {
    let mut m = serde_json::Map::new();
    m.insert("penalty-lab".into(), env!("CARGO_PKG_VERSION").into());
    for line in env!("PENALTY_LAB_DEP_VERSIONS").split(';') {
        if let Some((k, v)) = line.split_once('=') {
            m.insert(k.into(), v.into());
        }
    }
    serde_json::Value::Object(m)
}

/// Writes `bytes` to `path` through a uniquely named temporary file in the same folder
/// (`tempfile`) and a rename, so a reader never sees a half-written file, two writers never
/// share a temporary file, and a failed write leaves nothing behind. The file gets the
/// permissions an ordinary write would (0666 less the umask on Unix), not the temporary
/// file's owner-only 0600.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(|e| {
        Error::io(
            path.display(),
            format!("cannot create temporary file in {}: {e}", dir.display()),
        )
    })?;
    tmp.write_all(bytes)
        .map_err(|e| Error::io(path.display(), e))?;
    tmp.persist(path)
        .map_err(|e| Error::io(path.display(), e.error))?;
    Ok(())
}

/// Removes the file `path`; a file that is not there is not an error (any other failure is,
/// naming the file).
pub fn remove_if_present(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(Error::io(path.display(), e)),
        _ => Ok(()),
    }
}

/// `value` as pretty-printed JSON (what every binary's `--json` prints and every record holds);
/// a value JSON cannot hold (e.g. a map with non-string keys) is an error naming `what`.
pub fn json_text(what: &str, value: &impl serde::Serialize) -> Result<String> {
    serde_json::to_string_pretty(value)
        .map_err(|e| Error::Numerical(format!("cannot write {what} as JSON: {e}")))
}

/// Reads the JSON file `path` as a `T` (the one JSON reader of the saved records): a missing
/// file is an I/O error naming it, malformed JSON a parse error ([`Error::Parse`]) naming it,
/// the line and the column.
pub fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
    serde_json::from_str(&text).map_err(|e| Error::json(path.display(), &e))
}

/// Reads the TOML file `path` as a `T` (the one reader of the configuration files): a missing
/// file is an I/O error naming it, malformed TOML a parse error ([`Error::Parse`]) naming it
/// and the line ([`Error::toml`]).
pub fn read_toml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    read_toml_with_text(path).map(|(value, _)| value)
}

/// [`read_toml`], with the file's text (for a caller that places its own errors in it).
pub fn read_toml_with_text<T: serde::de::DeserializeOwned>(path: &Path) -> Result<(T, String)> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
    let value = toml::from_str(&text).map_err(|e| Error::toml(path.display(), Some(&text), &e))?;
    Ok((value, text))
}

/// The 1-based line of `key` in TOML `text`: at the top level (`table` None: before the first
/// header) or in `[table]` (up to the next header), a line `key = …` (bare or quoted key);
/// comments and lines inside multi-line strings are skipped. None where the key is written
/// otherwise (dotted, in an inline table): the message then goes without a line.
pub fn toml_key_line(text: &str, table: Option<&str>, key: &str) -> Option<usize> {
    let mut current: Option<&str> = None;
    let mut in_string: Option<&str> = None;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim_start_matches('\u{feff}');
        // Multi-line strings: an odd count of a delimiter opens (or closes) one.
        if let Some(d) = in_string {
            if line.matches(d).count() % 2 == 1 {
                in_string = None;
            }
            continue;
        }
        let code = without_comment(line);
        if let Some(d) = ["\"\"\"", "'''"].into_iter().find(|d| code.contains(d)) {
            if code.matches(d).count() % 2 == 1 {
                in_string = Some(d);
            }
        }
        let t = code.trim();
        if let Some(h) = t.strip_prefix('[') {
            current = h.split(']').next().map(str::trim);
            continue;
        }
        let Some((k, _)) = t.split_once('=') else {
            continue;
        };
        let k = k.trim().trim_matches(|c| c == '"' || c == '\'');
        if current == table && k == key {
            return Some(i + 1);
        }
    }
    None
}

/// A TOML line up to its comment: the first `#` outside a quoted string (basic strings with
/// their backslash escapes, literal strings as they stand).
fn without_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for (i, c) in line.char_indices() {
        match quote {
            Some('"') if escaped => escaped = false,
            Some('"') if c == '\\' => escaped = true,
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '#' => return &line[..i],
            None if c == '"' || c == '\'' => quote = Some(c),
            None => {}
        }
    }
    line
}

/// `e` (a validation error of a configuration read from the TOML file `path`, whose text is
/// `text`) placed in the file where the offending value came from it: the key `key` of
/// `[table]` (`None`: the top level; dotted for a nested table) named, with its line where
/// [`toml_key_line`] finds it (`PATH: line L: `key`: message`), else without. `e` unchanged
/// where the file does not set the key (the value came from a flag or the default).
pub fn in_toml_file(e: Error, path: &Path, text: &str, table: Option<&str>, key: &str) -> Error {
    // The table `a.b` is `[a.b]`, or `b = {…}` inside `[a]`: walked through the parsed file.
    let set = toml::from_str::<toml::Table>(text).ok().is_some_and(|t| {
        let inner = table.map_or(Some(&t), |h| {
            h.split('.')
                .try_fold(&t, |t, part| t.get(part).and_then(|v| v.as_table()))
        });
        inner.is_some_and(|t| t.contains_key(key))
    });
    if !set {
        return e;
    }
    let msg = format!("`{key}`: {}", e.root().bare_message());
    match toml_key_line(text, table, key) {
        Some(line) => Error::parse(path.display(), line, msg),
        None => Error::bad_file(path.display(), msg),
    }
}

/// JSON writes non-finite numbers as `null`; read them back as NaN
/// (`#[serde(deserialize_with = "crate::provenance::null_as_nan")]`).
pub fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Writes `value` as pretty-printed JSON to `path`, atomically.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let text = json_text(&path.display().to_string(), value)?;
    write_atomic(path, text.as_bytes())
}

/// Where a data file comes from: every record (`manifest.json`, `stress.json`, …) carries
/// these four fields beside the study's own (config, seed, summary, timings).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Provenance {
    /// The study (`sweep`, `stress`, …).
    pub experiment: String,
    /// [`git_commit`]: the commit the binary was built from.
    pub git_commit: String,
    /// [`crate_versions`].
    pub crate_versions: serde_json::Value,
    /// The command line that produced the file.
    pub command: String,
}

impl Provenance {
    /// The provenance of the running binary for `experiment`.
    pub fn new(experiment: &str) -> Provenance {
        Provenance {
            experiment: experiment.to_string(),
            git_commit: git_commit(),
            crate_versions: crate_versions(),
            command: std::env::args().collect::<Vec<_>>().join(" "),
        }
    }

    /// A record: the provenance fields and `fields` (a JSON object, whose keys must not be the
    /// provenance's; anything else is stored under `data`).
    pub fn record(&self, fields: serde_json::Value) -> serde_json::Value {
        let mut out = serde_json::Map::new();
        out.insert("experiment".into(), self.experiment.clone().into());
        out.insert("git_commit".into(), self.git_commit.clone().into());
        out.insert("crate_versions".into(), self.crate_versions.clone());
        out.insert("command".into(), self.command.clone().into());
        match fields {
            serde_json::Value::Object(m) => out.extend(m),
            other => {
                out.insert("data".into(), other);
            }
        }
        serde_json::Value::Object(out)
    }
}

/// Writes `rows` as CSV (header from the field names, the `csv` crate's serde mapping) to
/// `path`, atomically.
pub fn write_csv<T: serde::Serialize>(path: &Path, rows: &[T]) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.serialize(r)
            .map_err(|e| Error::Numerical(format!("CSV row for {}: {e}", path.display())))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| Error::Numerical(format!("CSV for {}: {e}", path.display())))?;
    write_atomic(path, &bytes)
}

/// One CSV cell of an optional number: `{:e}` (shortest round-trip scientific form), empty
/// for `None`.
pub fn csv_opt<T: std::fmt::LowerExp>(v: Option<T>) -> String {
    v.map_or(String::new(), |x| format!("{x:e}"))
}

/// One CSV record (no line end) from its fields, quoted by the `csv` crate where a field needs
/// it (delimiter, quote, line break): for tables whose columns are built by hand.
pub fn csv_line(fields: &[String]) -> String {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(fields).expect("writing to memory");
    let bytes = w.into_inner().expect("writing to memory");
    let mut s = String::from_utf8(bytes).expect("fields are UTF-8");
    s.pop(); // the terminator
    s
}

#[cfg(test)]
mod tests {
    use super::toml_key_line;

    /// An atomically written file gets the mode a plain write gives (umask applied), not
    /// the temporary file's 0600.
    #[cfg(unix)]
    #[test]
    fn atomic_writes_get_ordinary_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("atomic.txt"), dir.path().join("plain.txt"));
        super::write_atomic(&a, b"x").unwrap();
        std::fs::write(&b, b"x").unwrap();
        let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&a), mode(&b));
    }

    /// The key's line past comments (one holding a multi-line delimiter), multi-line strings
    /// (one holding the key's text), trailing comments, quoted keys, tables and a byte-order
    /// mark; None for a key the file does not write as `key = …` at that level.
    #[test]
    fn toml_key_line_finds_the_key_where_it_is_written() {
        let text = "\u{feff}count = 1\n\
                    # tip: long strings take \"\"\"\n\
                    factors = [2.0] # \"\"\" here too\n\
                    note = \"\"\"\n\
                    deltas = [1.0]\n\
                    \"\"\"\n\
                    'deltas' = [1e-3]\n\
                    s = \"a # b\" # c\n\
                    [generator]\n\
                    count = 3\n\
                    [generator.sub] # header comment\n\
                    x = 1\n";
        assert_eq!(toml_key_line(text, None, "count"), Some(1));
        assert_eq!(toml_key_line(text, None, "factors"), Some(3));
        assert_eq!(toml_key_line(text, None, "deltas"), Some(7));
        assert_eq!(toml_key_line(text, None, "s"), Some(8));
        assert_eq!(toml_key_line(text, Some("generator"), "count"), Some(10));
        assert_eq!(toml_key_line(text, Some("generator.sub"), "x"), Some(12));
        assert_eq!(toml_key_line(text, None, "x"), None);
        assert_eq!(toml_key_line(text, None, "b"), None);
    }
}
