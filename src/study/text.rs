//! Plain text for the printed reports of the studies: compact number formats (with the minus
//! sign U+2212), aligned tables and word-wrapped notes.

/// Compact general-purpose number format: `1.234e5`, `123.4`, `1.234`, `0.12345`, `0`;
/// negative numbers with the minus sign U+2212.
pub fn fmt_g(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    let s = if a == 0.0 {
        "0".to_string()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.3e}")
    } else if a >= 100.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.3}")
    } else {
        format!("{v:.5}")
    };
    minus(&s)
}

/// `v` with `sig` significant digits in scientific notation (minus sign U+2212).
pub fn fmt_e(v: f64, sig: usize) -> String {
    minus(&format!("{v:.p$e}", p = sig.saturating_sub(1)))
}

/// `v` in scientific notation with at most `sig` significant digits, trailing zeros dropped
/// (`1e7`, `1.76e3`, `4.64e1`; minus sign U+2212): knob values of a refined grid.
pub fn fmt_e_trim(v: f64, sig: usize) -> String {
    let s = format!("{v:.p$e}", p = sig.saturating_sub(1));
    minus(&match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => s,
    })
}

/// `v` with `decimals` decimals (minus sign U+2212).
pub fn fmt_f(v: f64, decimals: usize) -> String {
    minus(&format!("{v:.decimals$}"))
}

/// `s` with every ASCII hyphen-minus replaced by the minus sign U+2212.
pub fn minus(s: &str) -> String {
    s.replace('-', "\u{2212}")
}

/// Display width of `s` in characters.
fn width(s: &str) -> usize {
    s.chars().count()
}

/// An aligned table: a header line, a rule (at most 160 characters) and one line per row,
/// columns two spaces apart; `right[i]` right-aligns column `i`. Trailing spaces are trimmed.
pub fn table(headers: &[&str], rows: &[Vec<String>], right: &[bool]) -> String {
    let nc = headers.len();
    let mut w: Vec<usize> = headers.iter().map(|h| width(h)).collect();
    for r in rows {
        for (i, c) in r.iter().enumerate().take(nc) {
            w[i] = w[i].max(width(c));
        }
    }
    let fmt_row = |cells: Vec<&str>| {
        let mut line = String::new();
        for (i, c) in cells.iter().enumerate() {
            let pad = w[i] - width(c);
            let last = i + 1 == nc;
            if right[i] {
                line.push_str(&" ".repeat(pad));
                line.push_str(c);
            } else {
                line.push_str(c);
                if !last {
                    line.push_str(&" ".repeat(pad));
                }
            }
            if !last {
                line.push_str("  ");
            }
        }
        line.trim_end().to_string()
    };
    let mut out = String::new();
    out.push_str(&fmt_row(headers.to_vec()));
    out.push('\n');
    let total: usize = w.iter().sum::<usize>() + 2 * (nc - 1);
    out.push_str(&"─".repeat(total.min(160)));
    out.push('\n');
    for r in rows {
        out.push_str(&fmt_row(r.iter().map(String::as_str).collect()));
        out.push('\n');
    }
    out
}

/// `text` wrapped at `cols` characters, continuation lines indented by `indent` spaces.
pub fn wrap(text: &str, cols: usize, indent: usize) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && width(&line) + 1 + width(word) > cols {
            out.push_str(&line);
            out.push('\n');
            line = " ".repeat(indent);
        } else if !line.is_empty() && !line.ends_with(' ') {
            line.push(' ');
        }
        line.push_str(word);
    }
    out.push_str(&line);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Knob labels: three significant digits, trailing zeros dropped, U+2212 minus.
    #[test]
    fn trimmed_labels_have_three_significant_digits() {
        assert_eq!(fmt_e_trim(1.7612e3, 3), "1.76e3");
        assert_eq!(fmt_e_trim(1.45e3, 3), "1.45e3");
        assert_eq!(fmt_e_trim(1e7, 3), "1e7");
        assert_eq!(fmt_e_trim(2.5e-3, 3), "2.5e\u{2212}3");
    }

    #[test]
    fn formats() {
        assert_eq!(fmt_g(-1234.56), "\u{2212}1234.6");
        assert_eq!(fmt_g(0.0), "0");
        assert_eq!(fmt_g(2.5e9), "2.500e9");
        assert_eq!(fmt_e(45720.0, 4), "4.572e4");
    }

    #[test]
    fn table_aligns_and_wrap_indents() {
        let t = table(
            &["a", "bb"],
            &[vec!["xyz".into(), "1".into()]],
            &[false, true],
        );
        assert_eq!(t, "a    bb\n───────\nxyz   1\n");
        assert_eq!(wrap("one two three", 8, 2), "one two\n  three");
    }
}
