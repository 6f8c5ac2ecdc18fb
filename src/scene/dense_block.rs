//! Fast path for the `"dense"` block of a scene file: `stiffness.dense`, N rows of N numbers,
//! read straight from the bytes.
//!
//! **Why hand-written.** A dense scene of the sweep's folder is ≈ 98 % `0, ` tokens, and
//! its reading was ≈ 17 % of the busy time of a folder sweep. On the 20 dense scenes of
//! `scripts/folder.toml` this module reads the block 5–6× faster than `serde_json` (even
//! skipping the block as a `RawValue` alone takes 3× its time), and `sonic-rs` and
//! `simd-json` were slower than `serde_json` (the table: docs/history/performance-log.md).
//!
//! **What it does.** [`find`] walks the top-level object to the key `"stiffness"` and, in
//! its object, to the key `"dense"` (other values are skipped, strings with their escapes
//! and nesting respected), then reads the array of rows of numbers by the JSON number
//! grammar `-?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?` and converts each token with
//! `str::parse::<f64>` — correctly rounded, as `serde_json` with `float_roundtrip`
//! converts (and `u64`/`i64` → f64 `as` casts round to nearest too), so every value
//! carries the same bits; a bare `0` followed by a comma takes a shortcut. The scene reader
//! then lets `serde_json` parse the rest of the file with the block replaced by `[]` and
//! puts the rows in.
//!
//! **Never a different answer.** Anything the fast path does not expect — a key spelled
//! with escapes, a quoted number, `null`, a nested array, a number that overflows, any
//! syntax error — makes [`find`] return `None`, and the file is read by `serde_json`
//! alone, errors and their messages included; so does a file whose patched text
//! `serde_json` refuses. The module's tests compare both paths on seeded random spellings
//! (exponents, `-0`, 20-digit integers, subnormals, whitespace, key order, decoy keys in
//! strings) and malformed inputs.

use super::DenseRows;

/// The `stiffness.dense` value of a scene's text: its byte span and its rows.
pub(super) struct DenseBlock {
    /// Offset of the block's `[`.
    pub start: usize,
    /// Offset just past its `]`.
    pub end: usize,
    /// The rows, as the `serde` path would read them.
    pub rows: DenseRows,
}

/// Locates and reads `stiffness.dense` of the top-level object (see the module docs), or
/// `None` where the fast path does not apply.
pub(super) fn find(text: &str) -> Option<DenseBlock> {
    let mut c = Cursor {
        text,
        b: text.as_bytes(),
        i: 0,
    };
    c.ws();
    c.expect(b'{')?;
    // The top-level object's members, up to `"stiffness"`.
    loop {
        let key = c.key()?;
        if key == b"stiffness" {
            break;
        }
        c.skip_value()?;
        c.next_member()?;
    }
    c.expect(b'{')?;
    loop {
        let key = c.key()?;
        if key == b"dense" {
            let start = c.i;
            let rows = c.dense()?;
            return Some(DenseBlock {
                start,
                end: c.i,
                rows,
            });
        }
        c.skip_value()?;
        c.next_member()?;
    }
}

struct Cursor<'a> {
    /// The text (its tokens are sliced from it without a second UTF-8 check).
    text: &'a str,
    b: &'a [u8],
    i: usize,
}

/// Eight zero entries of a row as our writer spells them (`0, ` each, the last one's comma
/// included: another element follows).
const ZERO_RUN: &[u8] = b"0, 0, 0, 0, 0, 0, 0, 0, ";

impl<'a> Cursor<'a> {
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    /// Skips JSON whitespace.
    fn ws(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\n' | b'\r' | b'\t')) {
            self.i += 1;
        }
    }

    fn expect(&mut self, byte: u8) -> Option<()> {
        self.ws();
        (self.peek()? == byte).then(|| self.i += 1)
    }

    /// A member's key and its `:` (whitespace skipped before the value); the raw bytes
    /// between the quotes, escapes not decoded.
    fn key(&mut self) -> Option<&'a [u8]> {
        self.ws();
        let key = self.string()?;
        self.expect(b':')?;
        self.ws();
        Some(key)
    }

    /// After a member's value: `,` (another member follows) or `None` (the object ends or
    /// something else follows: the fast path gives up).
    fn next_member(&mut self) -> Option<()> {
        self.expect(b',')
    }

    /// A string at the cursor; returns its raw content.
    fn string(&mut self) -> Option<&'a [u8]> {
        if self.peek()? != b'"' {
            return None;
        }
        let start = self.i + 1;
        let mut j = start;
        loop {
            match *self.b.get(j)? {
                b'"' => break,
                b'\\' => j += 2,
                _ => j += 1,
            }
        }
        self.i = j + 1;
        Some(&self.b[start..j])
    }

    /// Skips one value (not validated: `serde_json` parses it afterwards), without
    /// recursion.
    fn skip_value(&mut self) -> Option<()> {
        match self.peek()? {
            b'"' => self.string().map(|_| ()),
            b'{' | b'[' => {
                let mut depth = 0usize;
                loop {
                    match self.peek()? {
                        b'"' => {
                            self.string()?;
                            continue;
                        }
                        b'{' | b'[' => depth += 1,
                        b'}' | b']' => {
                            depth -= 1;
                            if depth == 0 {
                                self.i += 1;
                                return Some(());
                            }
                        }
                        _ => {}
                    }
                    self.i += 1;
                }
            }
            _ => {
                let start = self.i;
                while !matches!(
                    self.peek(),
                    None | Some(b',' | b'}' | b']' | b' ' | b'\n' | b'\r' | b'\t')
                ) {
                    self.i += 1;
                }
                (self.i > start).then_some(())
            }
        }
    }

    /// A JSON number token at the cursor, converted correctly rounded; `None` if it does
    /// not follow the grammar or overflows.
    fn number(&mut self) -> Option<f64> {
        let start = self.i;
        if self.peek() == Some(b'-') {
            self.i += 1;
        }
        match self.peek()? {
            b'0' => self.i += 1,
            b'1'..=b'9' => self.digits(),
            _ => return None,
        }
        if self.peek() == Some(b'.') {
            self.i += 1;
            let d = self.i;
            self.digits();
            if self.i == d {
                return None;
            }
        }
        if matches!(self.peek(), Some(b'e' | b'E')) {
            self.i += 1;
            if matches!(self.peek(), Some(b'+' | b'-')) {
                self.i += 1;
            }
            let d = self.i;
            self.digits();
            if self.i == d {
                return None;
            }
        }
        // The token is ASCII by the grammar, so both ends are character boundaries.
        let x: f64 = self.text.get(start..self.i)?.parse().ok()?;
        x.is_finite().then_some(x)
    }

    fn digits(&mut self) {
        while matches!(self.peek(), Some(b'0'..=b'9')) {
            self.i += 1;
        }
    }

    /// `[[n, …], …]`: the rows, nonzero entries kept as `DenseRows` keeps them.
    fn dense(&mut self) -> Option<DenseRows> {
        let mut out = DenseRows {
            row_lens: Vec::new(),
            entries: Vec::new(),
        };
        if self.open_array()? {
            return Some(out);
        }
        loop {
            let row = out.row_lens.len();
            let len = self.row(row, &mut out.entries)?;
            out.row_lens.push(len);
            if self.after_element()? {
                return Some(out);
            }
        }
    }

    /// `[` (whitespace first): `Some(true)` past `[]` (an empty array), `Some(false)` past
    /// the `[` of one with elements, `None` if no array starts here.
    fn open_array(&mut self) -> Option<bool> {
        self.expect(b'[')?;
        self.ws();
        let empty = self.peek()? == b']';
        if empty {
            self.i += 1;
        }
        Some(empty)
    }

    /// After an array element: `Some(false)` past a `,` (another element follows),
    /// `Some(true)` past the closing `]`, `None` otherwise.
    fn after_element(&mut self) -> Option<bool> {
        self.ws();
        let closed = match self.peek()? {
            b',' => false,
            b']' => true,
            _ => return None,
        };
        self.i += 1;
        Some(closed)
    }

    /// One row `[n, …]`: its entries other than +0.0 appended, its length returned.
    fn row(&mut self, row: usize, entries: &mut Vec<(usize, usize, f64)>) -> Option<usize> {
        if self.open_array()? {
            return Some(0);
        }
        let mut len = 0;
        loop {
            self.ws();
            // Shortcuts (most of a dense scene is zeros): runs as `--dense-scenes` writes
            // them, eight at a time (the benchmark folder's read 4.6 → 3.4 ms), then a bare
            // `0` followed by a comma.
            while self.b.get(self.i..self.i + ZERO_RUN.len()) == Some(ZERO_RUN) {
                self.i += ZERO_RUN.len();
                len += ZERO_RUN.len() / 3;
            }
            if self.b.get(self.i..self.i + 2) == Some(b"0,") {
                self.i += 2;
                len += 1;
                continue;
            }
            let x = self.number()?;
            // +0.0 only: −0.0 is kept, so the round trip stays bit for bit.
            if x.to_bits() != 0 {
                entries.push((row, len, x));
            }
            len += 1;
            if self.after_element()? {
                return Some(len);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{read_fast, Obj, RawScene};
    use rand::seq::SliceRandom;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Everything a parse keeps, numbers by their bits.
    fn project(raw: &RawScene) -> String {
        let bits = |x: f64| format!("{:016x}", x.to_bits());
        let dense = raw.stiffness.0.dense.as_ref().map(|d| {
            let e: Vec<String> = d
                .entries
                .iter()
                .map(|&(i, j, x)| format!("{i},{j},{}", bits(x)))
                .collect();
            format!("{:?} {}", d.row_lens, e.join(" "))
        });
        let load: Vec<String> = raw.load.iter().map(|x| bits(x.0)).collect();
        let list = match &raw.constraints {
            crate::scene::RawConstraints::List(l) => l.as_slice(),
            crate::scene::RawConstraints::Matrix(_) => &[],
        };
        let cons: Vec<String> = list
            .iter()
            .map(|c| {
                format!(
                    "{} {} {:?}",
                    c.0.dof.as_ref().map_or(usize::MAX, |d| d.0),
                    bits(c.0.limit.0),
                    c.0.kind.0
                )
            })
            .collect();
        format!(
            "{:?} | {:?} | {:?} | {:?} | {:?} | {:?} | {:?}",
            raw.name,
            raw.description,
            raw.meta.as_ref().map(|m| m.0.to_string()),
            dense,
            raw.stiffness.0.matrix_market,
            load,
            cons
        )
    }

    /// The fast path answers only where `serde_json` alone gives the same scene.
    fn check(json: &str) -> bool {
        let fast = read_fast(json);
        if let Some(fast) = &fast {
            let slow: Obj<RawScene> = serde_json::from_str(json)
                .unwrap_or_else(|e| panic!("fast path read a file serde refuses ({e}): {json}"));
            assert_eq!(project(&fast.0), project(&slow.0), "{json}");
        }
        fast.is_some()
    }

    const SPELLINGS: [&str; 22] = [
        "0",
        "-0",
        "0.0",
        "-0.0",
        "1e5",
        "1E+05",
        "2.5e-3",
        "-17",
        "123456789012345678901",
        "18446744073709551615",
        "18446744073709551616",
        "9007199254740993",
        "-9223372036854775808",
        "-9223372036854775809",
        "5e-324",
        "2.4703282292062328e-324",
        "1e-400",
        "-1e-400",
        "1.7976931348623157e308",
        "0.1000000000000000055511151231257827",
        "4.35",
        "1e0",
    ];

    fn ws(rng: &mut ChaCha8Rng) -> &'static str {
        ["", "", " ", "\n", "\t", "\r\n  "][rng.random_range(0..6)]
    }

    fn number(rng: &mut ChaCha8Rng) -> String {
        match rng.random_range(0..4) {
            0 => "0".into(),
            1 => SPELLINGS[rng.random_range(0..SPELLINGS.len())].into(),
            2 => format!("{:?}", rng.random_range(-1e3..1e3f64)),
            _ => format!("{:e}", f64::from_bits(rng.random::<u64>() >> 2)),
        }
    }

    /// A scene text with random spellings, whitespace, key order and decoys.
    fn scene(rng: &mut ChaCha8Rng) -> String {
        let n = rng.random_range(1..6usize);
        let mut rows = Vec::new();
        for _ in 0..n {
            let len = if rng.random_bool(0.1) {
                rng.random_range(0..n + 2)
            } else {
                n
            };
            let nums: Vec<String> = (0..len)
                .map(|_| format!("{}{}{}", ws(rng), number(rng), ws(rng)))
                .collect();
            rows.push(format!("{}[{}]{}", ws(rng), nums.join(","), ws(rng)));
        }
        let dense = format!("[{}]", rows.join(","));
        let mut stiffness = vec![format!("\"dense\"{}:{}{dense}", ws(rng), ws(rng))];
        if rng.random_bool(0.1) {
            stiffness.push("\"matrix_market\": \"K.mtx\"".into());
        }
        stiffness.shuffle(rng);
        let mut members = vec![
            "\"name\": \"s \\\"stiffness\\\": {\\\"dense\\\": [[9]]} \\\\\"".to_string(),
            format!(
                "\"stiffness\"{}:{}{{{}}}",
                ws(rng),
                ws(rng),
                stiffness.join(",")
            ),
            format!(
                "\"load\": [{}]",
                (0..n).map(|_| number(rng)).collect::<Vec<_>>().join(",")
            ),
            "\"constraints\": [{\"dof\": 0, \"limit\": -0.5, \"kind\": \"upper\"}]".into(),
        ];
        if rng.random_bool(0.5) {
            members
                .push(r#""meta": {"stiffness": {"dense": [[7]]}, "x": [1, {"y": "]}"}]}"#.into());
        }
        if rng.random_bool(0.5) {
            members.push(r#""other": [[[]], {"a": "\"{["}, true, null, -1.5e3]"#.into());
        }
        if rng.random_bool(0.3) {
            members.push(r#""description": "dense"#.to_string() + "\"");
        }
        members.shuffle(rng);
        format!("{}{{{}{}}}{}", ws(rng), ws(rng), members.join(","), ws(rng))
    }

    /// Seeded random scenes: the fast path applies to (nearly) all of them and always agrees
    /// with `serde_json`.
    #[test]
    fn agrees_with_serde_on_random_spellings() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut fast = 0;
        let total = 400;
        for _ in 0..total {
            fast += check(&scene(&mut rng)) as usize;
        }
        // Only decoy-free spellings it cannot take fall back: none are generated.
        assert_eq!(fast, total);
    }

    /// Long rows of mostly `0, ` (as `--dense-scenes` writes them, the eight-zero shortcut)
    /// with numbers, other whitespace and row ends at every offset agree with `serde_json`.
    #[test]
    fn zero_runs_agree_with_serde() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for _ in 0..300 {
            let n = rng.random_range(1..40usize);
            let row = |rng: &mut ChaCha8Rng| {
                let nums: Vec<String> = (0..n)
                    .map(|_| {
                        if rng.random_bool(0.85) {
                            "0".into()
                        } else {
                            number(rng)
                        }
                    })
                    .collect();
                let sep = [", ", ", ", ", ", ",", ",  ", ",\n", " , "][rng.random_range(0..7)];
                format!("[{}]", nums.join(sep))
            };
            let rows: Vec<String> = (0..n).map(|_| row(&mut rng)).collect();
            let load = vec!["0"; n].join(", ");
            let json = format!(
                r#"{{"name": "z", "stiffness": {{"dense": [{}]}}, "load": [{load}], "constraints": []}}"#,
                rows.join(", ")
            );
            assert!(check(&json), "{json}");
        }
    }

    /// Malformed blocks and spellings the fast path does not take fall back, or agree.
    #[test]
    fn malformed_or_unusual_input_falls_back_or_agrees() {
        let base = r#"{"name": "x", "stiffness": {"dense": [[1, 0], [0, 2]]}, "load": [0, 0], "constraints": []}"#;
        assert!(check(base));
        for (from, to) in [
            ("[1, 0]", r#"["1", 0]"#),
            ("[1, 0]", "[null, 0]"),
            ("[1, 0]", "[[1], 0]"),
            ("[1, 0]", "[01, 0]"),
            ("[1, 0]", "[1., 0]"),
            ("[1, 0]", "[.5, 0]"),
            ("[1, 0]", "[+1, 0]"),
            ("[1, 0]", "[1e, 0]"),
            ("[1, 0]", "[NaN, 0]"),
            ("[1, 0]", "[Infinity, 0]"),
            ("[1, 0]", "[1e999, 0]"),
            ("[1, 0]", "[1 0]"),
            ("[1, 0]", "[1, 0,]"),
            ("[1, 0]", "[0,]"),
            ("[1, 0]", "[00, 1]"),
            ("[1, 0]", "[1, 0"),
            ("[0, 2]]", "[0, 2],]"),
            ("[0, 2]]", "[0, 2]"),
            ("\"stiffness\"", "\"st\\u0069ffness\""),
            ("\"dense\"", "\"d\\u0065nse\""),
            ("\"dense\": [[1, 0], [0, 2]]", "\"dense\": null"),
            (
                "\"dense\": [[1, 0], [0, 2]]",
                "\"dense\": [[1, 0], [0, 2]], \"dense\": [[3]]",
            ),
            ("{\"dense\"", "{\"matrix_market\": 1, \"dense\""),
            (
                "\"constraints\": []",
                "\"constraints\": [], \"stiffness\": 1",
            ),
            ("\"constraints\": []}", "\"constraints\": []} x"),
            ("\"load\": [0, 0]", "\"load\": [0, 0"),
            ("{\"name\"", "[{\"name\""),
        ] {
            assert!(base.contains(from), "{from}");
            check(&base.replacen(from, to, 1));
        }
        // Every truncation.
        for end in 0..base.len() {
            check(&base[..end]);
        }
    }
}
