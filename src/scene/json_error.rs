//! serde_json errors as one-line messages in the scene module's wording.

use serde_json::error::Category;

/// Hints for the required top-level fields, appended to "missing required field".
const REQUIRED: [(&str, &str); 4] = [
    ("name", "a string"),
    (
        "stiffness",
        r#"{"dense": [[...], ...]} or {"matrix_market": "K.mtx"}"#,
    ),
    ("load", "an array of N numbers"),
    (
        "constraints",
        r#"an array of {"dof", "limit", "kind"} objects; use [] for none"#,
    ),
];

/// `line L, column C: <path>: <what was wrong>` for a `serde_json` error at JSON path
/// `path` (`None` for errors after the value, e.g. trailing characters). Columns count
/// characters (`serde_json` counts bytes). The message is one line, clipped.
pub(super) fn describe(e: &serde_json::Error, path: Option<&str>, text: &str) -> String {
    let (line, byte_col) = (e.line(), e.column());
    let full = e.to_string();
    let msg = full
        .strip_suffix(&format!(" at line {line} column {byte_col}"))
        .unwrap_or(&full);
    // The line's text and the byte offset of the character the error points at.
    let line_text = text.split('\n').nth(line.wrapping_sub(1)).unwrap_or("");
    let at = byte_col.saturating_sub(1);
    let col = line_text
        .get(..at)
        .map_or(byte_col, |t| t.chars().count() + 1);
    let place = if line == 0 {
        String::new()
    } else {
        format!("line {line}, column {col}: ")
    };
    let what = match e.classify() {
        Category::Syntax | Category::Eof => {
            format!("malformed JSON: {}", syntax(msg, line_text, at))
        }
        Category::Data | Category::Io => {
            let path = match path {
                None | Some(".") => "scene",
                // "unknown field `x`" is about the object, not the path ending in `.x`.
                Some(p) if msg.starts_with("unknown field `") => {
                    p.rsplit_once('.').map_or(p, |(parent, _)| parent)
                }
                Some(p) => p,
            };
            format!("{path}: {}", data(msg, path))
        }
    };
    format!("{place}{}", clip_message(&what))
}

/// Shortens a whole message (echoed keys and strings can be long) and keeps it on one
/// line.
fn clip_message(m: &str) -> String {
    const MAX: usize = 400;
    let m = m.replace(['\n', '\r'], " ");
    if m.chars().count() <= MAX {
        m
    } else {
        let mut t: String = m.chars().take(MAX).collect();
        t.push('…');
        t
    }
}

/// The character at byte offset `at` of `line`, for "found …".
fn found(line: &str, at: usize) -> String {
    match line.get(at..).and_then(|t| t.chars().next()) {
        None => "the end of the line or file".into(),
        Some(c) if c.is_control() => format!("character U+{:04X}", c as u32),
        Some(c) => format!("'{c}'"),
    }
}

fn syntax(msg: &str, line: &str, at: usize) -> String {
    let rest = line.get(at..).unwrap_or("");
    match msg {
        "number out of range" => {
            // The error points into the number: widen to the whole literal.
            let is_num = |c: char| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-');
            let start = line
                .get(..at.min(line.len()))
                .map_or(at, |t| t.trim_end_matches(is_num).len());
            let end = at + rest.find(|c: char| !is_num(c)).unwrap_or(rest.len());
            let literal = line.get(start..end).unwrap_or("");
            format!(
                "number {} is not finite: it overflows f64 (|x| must be at most 1.7976931348623157e308)",
                clip(literal)
            )
        }
        "recursion limit exceeded" => "nesting deeper than 128 levels is not supported".into(),
        "trailing characters" => format!(
            "unexpected {} after the end of the JSON value",
            found(line, at)
        ),
        _ if msg.starts_with("control character") => {
            "control character (e.g. a line break) inside a string; escape it".into()
        }
        _ => {
            let msg = msg
                .replace('`', "'")
                .replace("EOF", "end of file")
                .replace("expected value", "expected a value");
            if ["NaN", "Infinity", "-Infinity", "-NaN"]
                .iter()
                .any(|w| rest.starts_with(w))
            {
                "NaN and Infinity are not valid JSON numbers (all values must be finite)".into()
            } else if msg.starts_with("end of file") {
                msg
            } else {
                format!("{msg}, found {}", found(line, at))
            }
        }
    }
}

/// Rewords serde's data errors ("invalid type: map, expected a string", "missing field
/// `name`", …) as "expected a string, found an object", "missing required field
/// \"name\" (a string)", ….
fn data(msg: &str, path: &str) -> String {
    if let Some(rest) = msg.strip_prefix("invalid type: ") {
        if let Some((unexpected, expected)) = rest.rsplit_once(", expected ") {
            let expected = expected.replace("a sequence", "an array");
            let hint = if expected == "a number" && unexpected.starts_with("string ") {
                " (write numbers without quotes)"
            } else {
                ""
            };
            return format!(
                "expected {expected}, found {}{hint}",
                found_value(unexpected)
            );
        }
    }
    if let Some(field) = backticked(msg, "missing field `") {
        let hint = REQUIRED
            .iter()
            .find(|(k, _)| path == "scene" && *k == field)
            .map_or(String::new(), |(_, h)| format!(" ({h})"));
        return format!("missing required field {}{hint}", quote_short(field));
    }
    if let Some(field) = backticked(msg, "duplicate field `") {
        return format!("duplicate key {}", quote_short(field));
    }
    if let Some(field) = backticked(msg, "unknown field `") {
        let hint = if path == "constraints" {
            r#"the rows of D are {"matrix_market": "D.mtx", "limits": [...], "kind": k} (or "kinds": [...])"#
        } else {
            r#"give exactly one of "dense" (rows of numbers) or "matrix_market" (a file path)"#
        };
        return format!("unknown key {}; {hint}", quote_short(field));
    }
    msg.to_owned()
}

/// The text between `prefix` and the next backtick.
fn backticked<'m>(msg: &'m str, prefix: &str) -> Option<&'m str> {
    msg.strip_prefix(prefix)?.split('`').next()
}

/// serde's description of a JSON value ("integer `5`", "map", …) in plain words.
fn found_value(u: &str) -> String {
    let ticked = |p: &str| u.strip_prefix(p).map(|v| v.trim_matches('`'));
    match u {
        "sequence" => "an array".into(),
        "map" => "an object".into(),
        "null" | "unit value" => "null".into(),
        _ => {
            if let Some(v) = ticked("integer ").or_else(|| ticked("floating point ")) {
                format!("a number ({})", clip(v))
            } else if let Some(v) = ticked("boolean ") {
                format!("a boolean ({v})")
            } else if let Some(s) = u.strip_prefix("string ") {
                format!("the string {}", clip(s))
            } else {
                u.to_owned()
            }
        }
    }
}

/// A string quoted for a message, shortened if long.
pub(super) fn quote_short(s: &str) -> String {
    let shown = clip(s);
    serde_json::to_string(&shown).unwrap_or(shown)
}

/// Shortens a token for an error message.
pub(super) fn clip(s: &str) -> String {
    const MAX: usize = 40;
    if s.chars().count() <= MAX {
        s.to_owned()
    } else {
        let mut t: String = s.chars().take(MAX).collect();
        t.push('…');
        t
    }
}
