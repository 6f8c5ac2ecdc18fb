//! Fuzzing the two readers ("stability stress"): `parse_scene_str`,
//! `parse_matrix_market_str`, `read_scene` and `read_matrix_market` on arbitrary bytes,
//! arbitrary strings, token soups and byte-level mutations of files written by
//! `write_scene` / `write_matrix_market`.
//!
//! The contract checked on every input: no panic; either `Ok` with a problem that satisfies
//! `Problem::new`'s invariants (square K, `q.len() = N`, all finite, DOFs in range) or an
//! `Err` whose message is one non-empty line that starts with the name of the file it is
//! about. Unmutated files written by the writers must read back bit for bit.
//!
//! Case counts are chosen so the whole file runs in a few seconds with `--release`.

use crate::common;
use crate::common::matrices::constraint_bits;
use penalty_lab::scene::{
    parse_matrix_market_str, parse_scene_str, read_matrix_market, read_scene, write_matrix_market,
    write_scene, Scene,
};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use proptest::prelude::*;
use std::fs;
use std::path::Path;

// ----------------------------------------------------------------------------------------
// Helpers
// ----------------------------------------------------------------------------------------

/// The invariants every successfully read scene must satisfy.
fn check_scene(s: &Scene) -> Result<(), TestCaseError> {
    check_problem(&s.problem)
}

fn check_problem(p: &Problem) -> Result<(), TestCaseError> {
    let n = p.n();
    prop_assert!(n >= 1);
    prop_assert_eq!(p.q.len(), n);
    prop_assert!(p.k.all_finite());
    prop_assert!(p.q.iter().all(|v| v.is_finite()));
    let mut seen = vec![false; n];
    for c in &p.constraints {
        prop_assert!(c.single_dof().unwrap() < n);
        prop_assert!(c.limit.is_finite());
        prop_assert!(!std::mem::replace(&mut seen[c.single_dof().unwrap()], true));
    }
    Ok(())
}

fn check_matrix(k: &Stiffness) -> Result<(), TestCaseError> {
    prop_assert!(k.n() >= 1);
    prop_assert!(k.is_sparse());
    prop_assert!(k.all_finite());
    let n = k.n();
    let mut ok = true;
    k.for_each_entry(|i, j, _| ok &= i < n && j < n);
    prop_assert!(ok);
    Ok(())
}

/// A clean error: one non-empty line naming `origin` first.
fn check_err(e: &penalty_lab::Error, origin: &str) -> Result<(), TestCaseError> {
    let msg = e.to_string();
    prop_assert!(!msg.contains('\n'), "multi-line message: {:?}", msg);
    prop_assert!(
        msg.starts_with(&format!("{origin}: ")),
        "message does not start with {:?}: {:?}",
        origin,
        msg
    );
    prop_assert!(msg.len() > origin.len() + 2 + 3, "empty message: {:?}", msg);
    // Error messages clip echoed tokens: a hostile input must not be echoed in full.
    prop_assert!(
        msg.chars().count() < 2000,
        "message too long: {} chars",
        msg.len()
    );
    Ok(())
}

fn check_scene_result(r: &penalty_lab::Result<Scene>, origin: &str) -> Result<(), TestCaseError> {
    match r {
        Ok(s) => check_scene(s),
        Err(e) => check_err(e, origin),
    }
}

fn check_mm_result(r: &penalty_lab::Result<Stiffness>, origin: &str) -> Result<(), TestCaseError> {
    match r {
        Ok(k) => check_matrix(k),
        Err(e) => check_err(e, origin),
    }
}

/// Stored entries as (row, col, bits), sorted.
fn entries(k: &Stiffness) -> Vec<(usize, usize, u64)> {
    let mut v = Vec::new();
    k.for_each_entry(|i, j, x| {
        if !(k.is_sparse() || x.to_bits() != 0) {
            return;
        }
        v.push((i, j, x.to_bits()))
    });
    v.sort_unstable();
    v
}

// ----------------------------------------------------------------------------------------
// Generators
// ----------------------------------------------------------------------------------------

fn finite_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<u64>()
            .prop_map(f64::from_bits)
            .prop_filter("finite", |x| x.is_finite()),
        -1e3..1e3f64,
        (-50i32..50).prop_map(f64::from),
        Just(0.0),
        Just(-0.0),
        Just(5e-324),
        Just(f64::MAX),
    ]
}

/// A valid problem: N in 1..=6, dense or sparse K, symmetric or not, 0..N constraints.
fn valid_problem() -> impl Strategy<Value = Problem> {
    (1usize..=6).prop_flat_map(|n| {
        (
            prop::collection::vec(finite_f64(), n * n),
            prop::collection::vec(any::<bool>(), n * n),
            prop::collection::vec(finite_f64(), n),
            prop::collection::vec(0u8..4, n),
            prop::collection::vec(finite_f64(), n),
            any::<bool>(),
            any::<bool>(),
        )
            .prop_map(move |(vals, mask, q, codes, limits, sparse, sym)| {
                let at = |i: usize, j: usize| {
                    if sym && i < j {
                        vals[j * n + i]
                    } else {
                        vals[i * n + j]
                    }
                };
                let keep = |i: usize, j: usize| {
                    if sym && i < j {
                        mask[j * n + i]
                    } else {
                        mask[i * n + j]
                    }
                };
                let k = if sparse {
                    let t: Vec<_> = (0..n)
                        .flat_map(|i| (0..n).map(move |j| (i, j)))
                        .filter(|&(i, j)| keep(i, j))
                        .map(|(i, j)| (i, j, at(i, j)))
                        .collect();
                    Stiffness::from_triplets(n, &t).unwrap()
                } else {
                    let rows: Vec<Vec<f64>> =
                        (0..n).map(|i| (0..n).map(|j| at(i, j)).collect()).collect();
                    Stiffness::from_rows(&rows).unwrap()
                };
                let cons: Vec<Constraint> = codes
                    .iter()
                    .enumerate()
                    .filter(|(_, &c)| c > 0)
                    .map(|(d, &c)| {
                        Constraint::on_dof(
                            d,
                            limits[d],
                            [
                                ConstraintKind::Bilateral,
                                ConstraintKind::Upper,
                                ConstraintKind::Lower,
                            ][usize::from(c - 1)],
                        )
                    })
                    .collect();
                Problem::new(k, q, cons).unwrap()
            })
    })
}

/// Bytes that are meaningful to one of the two grammars (or to UTF-8 decoding).
const DICT: &[&[u8]] = &[
    b"{",
    b"}",
    b"[",
    b"]",
    b"\"",
    b":",
    b",",
    b"\\",
    b"\\u",
    b"\\ud800",
    b"-",
    b"+",
    b"0",
    b"1e999",
    b"-1e400",
    b"1e-400",
    b"NaN",
    b"Infinity",
    b"nan",
    b"inf",
    b"null",
    b"true",
    b"18446744073709551616",
    b"340282366920938463463374607431768211456",
    b"-9223372036854775809",
    b"4.0",
    b"4e0",
    b"0x10",
    b"1.5D+03",
    b"%",
    b"%%MatrixMarket",
    b"matrix",
    b"coordinate",
    b"array",
    b"symmetric",
    b"general",
    b"pattern",
    b"complex",
    b"integer",
    b"16777216",
    b"16777217",
    b"\n",
    b"\r\n",
    b"\r",
    b"\t",
    b" ",
    b"\0",
    b"\xef\xbb\xbf",
    b"\xff",
    b"\xc3",
    b"\xe2\x82",
    b"\xf0\x9f\x98\x80",
    b"\"dense\"",
    b"\"matrix_market\"",
    b"\"constraints\"",
    b"\"dof\"",
    b"\"limit\"",
    b"\"kind\"",
    b"\"upper\"",
    b"\"bilateral\"",
];

/// One byte-level edit of a file.
#[derive(Clone, Debug)]
enum Edit {
    /// Flip one bit of the byte at (relative) position.
    Flip(prop::sample::Index, u8),
    /// Replace one byte.
    Set(prop::sample::Index, u8),
    /// Insert a dictionary token.
    Insert(prop::sample::Index, prop::sample::Index),
    /// Delete a range.
    Delete(prop::sample::Index, usize),
    /// Duplicate a range in place.
    Duplicate(prop::sample::Index, usize),
    /// Cut the file.
    Truncate(prop::sample::Index),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<prop::sample::Index>(), 0u8..8).prop_map(|(i, b)| Edit::Flip(i, b)),
        (any::<prop::sample::Index>(), any::<u8>()).prop_map(|(i, b)| Edit::Set(i, b)),
        (any::<prop::sample::Index>(), any::<prop::sample::Index>())
            .prop_map(|(i, t)| Edit::Insert(i, t)),
        (any::<prop::sample::Index>(), 1usize..16).prop_map(|(i, l)| Edit::Delete(i, l)),
        (any::<prop::sample::Index>(), 1usize..64).prop_map(|(i, l)| Edit::Duplicate(i, l)),
        any::<prop::sample::Index>().prop_map(Edit::Truncate),
    ]
}

fn apply(bytes: &mut Vec<u8>, edits: &[Edit]) {
    for e in edits {
        let len = bytes.len();
        match e {
            Edit::Flip(i, b) if len > 0 => {
                let at = i.index(len);
                bytes[at] ^= 1 << b;
            }
            Edit::Set(i, b) if len > 0 => {
                let at = i.index(len);
                bytes[at] = *b;
            }
            Edit::Insert(i, t) => {
                let at = i.index(len + 1);
                let tok = DICT[t.index(DICT.len())];
                bytes.splice(at..at, tok.iter().copied());
            }
            Edit::Delete(i, l) if len > 0 => {
                let at = i.index(len);
                let end = (at + l).min(len);
                bytes.drain(at..end);
            }
            Edit::Duplicate(i, l) if len > 0 => {
                let at = i.index(len);
                let end = (at + l).min(len);
                let piece: Vec<u8> = bytes[at..end].to_vec();
                bytes.splice(end..end, piece);
            }
            Edit::Truncate(i) => {
                let at = i.index(len + 1);
                bytes.truncate(at);
            }
            _ => {}
        }
    }
}

/// A sequence of dictionary tokens and random printable runs.
fn token_soup() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(
        prop_oneof![
            3 => any::<prop::sample::Index>().prop_map(|i| DICT[i.index(DICT.len())].to_vec()),
            1 => "[ -~]{0,6}".prop_map(String::into_bytes),
            1 => "[0-9]{1,4}".prop_map(String::into_bytes),
        ],
        0..60,
    )
    .prop_map(|parts| parts.concat())
}

/// Matrix Market text with a real header, a size line and entry lines built from a token
/// dictionary (indices near the bounds, hostile numbers, extra/missing fields).
fn mm_structured() -> impl Strategy<Value = String> {
    let header = prop_oneof![
        Just("%%MatrixMarket matrix coordinate real general".to_string()),
        Just("%%MatrixMarket matrix coordinate real symmetric".to_string()),
        Just("%%MatrixMarket matrix coordinate integer symmetric".to_string()),
        Just("%%MatrixMarket matrix array real general".to_string()),
        Just("%%MatrixMarket matrix array real symmetric".to_string()),
        Just("%%matrixmarket MATRIX Coordinate Double General".to_string()),
        "%%MatrixMarket matrix [a-z]{0,12} [a-z]{0,8} [a-z-]{0,14}",
    ];
    let num = prop_oneof![
        (0usize..6).prop_map(|i| i.to_string()),
        Just("16777216".to_string()),
        Just("16777217".to_string()),
        Just("18446744073709551615".to_string()),
        Just("18446744073709551616".to_string()),
        Just("-1".to_string()),
        Just("+2".to_string()),
        Just("1.0".to_string()),
    ];
    let val = prop_oneof![
        finite_f64().prop_map(|v| format!("{v:?}")),
        Just("1e999".to_string()),
        Just("NaN".to_string()),
        Just("-inf".to_string()),
        Just("1.5D+03".to_string()),
        Just("1.5d".to_string()),
        Just("0x1p3".to_string()),
        Just("170141183460469231731687303715884105728".to_string()),
        "[-+.eE0-9]{1,8}",
    ];
    let size = prop_oneof![
        (num.clone(), num.clone(), num.clone()).prop_map(|(a, b, c)| format!("{a} {b} {c}")),
        (num.clone(), num.clone()).prop_map(|(a, b)| format!("{a} {b}")),
        (1usize..5, 0usize..30).prop_map(|(n, k)| format!("{n} {n} {k}")),
        (1usize..5).prop_map(|n| format!("{n} {n}")),
    ];
    let line = prop_oneof![
        (num.clone(), num, val.clone()).prop_map(|(r, c, v)| format!("{r} {c} {v}")),
        (1usize..5, 1usize..5, val.clone()).prop_map(|(r, c, v)| format!("{r} {c} {v}")),
        val.clone(),
        (val.clone(), val).prop_map(|(a, b)| format!("{a} {b}")),
        "%[ -~]{0,12}",
        Just(String::new()),
        "[ -~]{0,16}",
    ];
    let nl = prop_oneof![Just("\n"), Just("\r\n")];
    (
        header,
        prop::collection::vec("%[ -~]{0,10}", 0..3),
        size,
        prop::collection::vec(line, 0..24),
        nl,
    )
        .prop_map(|(h, comments, s, lines, nl)| {
            let mut t = h;
            t.push_str(nl);
            for c in comments {
                t.push_str(&c);
                t.push_str(nl);
            }
            t.push_str(&s);
            t.push_str(nl);
            for l in lines {
                t.push_str(&l);
                t.push_str(nl);
            }
            t
        })
}

// ----------------------------------------------------------------------------------------
// Properties
// ----------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// Arbitrary bytes: through the string parsers (lossy UTF-8, and behind a valid
    /// Matrix Market header) and as files on disk (raw bytes, including invalid UTF-8).
    #[test]
    fn arbitrary_bytes_give_clean_errors(bytes in prop::collection::vec(any::<u8>(), 0..768)) {
        let text = String::from_utf8_lossy(&bytes);
        check_scene_result(&parse_scene_str(&text, Path::new("."), "f.scene.json"), "f.scene.json")?;
        check_mm_result(&parse_matrix_market_str(&text, "f.mtx"), "f.mtx")?;
        let hdr = format!("%%MatrixMarket matrix coordinate real general\n{text}");
        check_mm_result(&parse_matrix_market_str(&hdr, "f.mtx"), "f.mtx")?;
        let dir = common::tmp_dir("fuzz-bytes");
        let sp = dir.path().join("x.scene.json");
        fs::write(&sp, &bytes).unwrap();
        let origin = sp.display().to_string();
        check_scene_result(&read_scene(&sp), &origin)?;
        let mp = dir.path().join("x.mtx");
        fs::write(&mp, &bytes).unwrap();
        check_mm_result(&read_matrix_market(&mp), &mp.display().to_string())?;
    }

    /// Arbitrary Unicode strings (any printable character class).
    #[test]
    fn arbitrary_strings_give_clean_errors(s in "\\PC{0,400}") {
        check_scene_result(&parse_scene_str(&s, Path::new("."), "s.scene.json"), "s.scene.json")?;
        check_mm_result(&parse_matrix_market_str(&s, "s.mtx"), "s.mtx")?;
    }

    /// Token soups of both grammars.
    #[test]
    fn token_soups_give_clean_errors(bytes in token_soup()) {
        let text = String::from_utf8_lossy(&bytes);
        check_scene_result(&parse_scene_str(&text, Path::new("."), "t.scene.json"), "t.scene.json")?;
        check_mm_result(&parse_matrix_market_str(&text, "t.mtx"), "t.mtx")?;
    }

    /// Structured Matrix Market text with hostile sizes, indices and values.
    #[test]
    fn structured_matrix_market_gives_clean_errors(text in mm_structured()) {
        check_mm_result(&parse_matrix_market_str(&text, "m.mtx"), "m.mtx")?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// A valid scene (inline dense K) written by `write_scene` reads back bit for bit;
    /// the same file with byte-level edits never panics and errors cleanly.
    #[test]
    fn mutated_inline_scenes_give_clean_errors(
        p in valid_problem(),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let dense_p = Problem::new(
            Stiffness::Dense(p.k.to_dense()),
            p.q.clone(),
            p.constraints.clone(),
        )
        .unwrap();
        let dir = common::tmp_dir("fuzz-inline");
        let path = dir.path().join("a.scene.json");
        write_scene(&path, "a", &dense_p, Some(&serde_json::json!({"seed": 1})), usize::MAX)
            .unwrap();
        let s = read_scene(&path).unwrap();
        prop_assert_eq!(entries(&s.problem.k), entries(&dense_p.k));
        prop_assert_eq!(
            s.problem.q.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            dense_p.q.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        prop_assert_eq!(constraint_bits(&s.problem), constraint_bits(&dense_p));

        let mut bytes = fs::read(&path).unwrap();
        apply(&mut bytes, &edits);
        fs::write(&path, &bytes).unwrap();
        check_scene_result(&read_scene(&path), &path.display().to_string())?;
        let text = String::from_utf8_lossy(&bytes);
        check_scene_result(&parse_scene_str(&text, dir.path(), "a.scene.json"), "a.scene.json")?;
    }

    /// A scene whose K lives in a sibling `.mtx`: mutate the matrix file, the scene file,
    /// or both; `read_scene` resolves the (possibly mangled) reference and errors cleanly.
    #[test]
    fn mutated_matrix_market_scenes_give_clean_errors(
        p in valid_problem(),
        mtx_edits in prop::collection::vec(edit(), 0..5),
        scene_edits in prop::collection::vec(edit(), 0..3),
    ) {
        let dir = common::tmp_dir("fuzz-mtx");
        let path = dir.path().join("b.scene.json");
        write_scene(&path, "b", &p, None, 0).unwrap();
        let mtx = dir.path().join("b.mtx");
        prop_assert!(mtx.exists());
        let s = read_scene(&path).unwrap();
        prop_assert!(s.problem.k.is_sparse());
        prop_assert_eq!(entries(&s.problem.k), entries(&p.k));

        let mut mb = fs::read(&mtx).unwrap();
        apply(&mut mb, &mtx_edits);
        fs::write(&mtx, &mb).unwrap();
        let mut sb = fs::read(&path).unwrap();
        apply(&mut sb, &scene_edits);
        fs::write(&path, &sb).unwrap();
        check_scene_result(&read_scene(&path), &path.display().to_string())?;
        check_mm_result(&read_matrix_market(&mtx), &mtx.display().to_string())?;
    }

    /// `write_matrix_market` output reads back bit for bit; mutated, it errors cleanly.
    #[test]
    fn mutated_matrix_market_files_give_clean_errors(
        p in valid_problem(),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let dir = common::tmp_dir("fuzz-mm");
        let path = dir.path().join("k.mtx");
        write_matrix_market(&path, &p.k).unwrap();
        let k = read_matrix_market(&path).unwrap();
        prop_assert_eq!(entries(&k), entries(&p.k));
        let mut bytes = fs::read(&path).unwrap();
        apply(&mut bytes, &edits);
        fs::write(&path, &bytes).unwrap();
        check_mm_result(&read_matrix_market(&path), &path.display().to_string())?;
        let text = String::from_utf8_lossy(&bytes);
        check_mm_result(&parse_matrix_market_str(&text, "k.mtx"), "k.mtx")?;
    }

    /// Scene JSON with hostile values spliced into each field position.
    #[test]
    fn hostile_field_values_give_clean_errors(
        slot in 0usize..6,
        value in prop_oneof![
            any::<prop::sample::Index>().prop_map(|i| String::from_utf8_lossy(DICT[i.index(DICT.len())]).into_owned()),
            Just("[".repeat(200)),
            Just("{\"a\":".repeat(150)),
            Just(format!("\"{}\"", "x".repeat(5000))),
            Just("[[1e308, 1e308], [1e308, 1e308]]".to_string()),
            Just("[[5e-324]]".to_string()),
            Just("-0".to_string()),
            Just("1.7976931348623159e308".to_string()),
            Just("\"\\u0000\"".to_string()),
            Just("\"../../../../../../../../dev/null\"".to_string()),
            Just("\".\"".to_string()),
            Just("\"a\\u0000b.mtx\"".to_string()),
            Just("{\"matrix_market\": \"/\"}".to_string()),
            Just("{\"matrix_market\": \"a.scene.json\"}".to_string()),
            Just("{\"dense\": []}".to_string()),
            Just("{\"dense\": [[]]}".to_string()),
            Just("[{\"dof\": 1e300, \"limit\": 0, \"kind\": \"upper\"}]".to_string()),
            Just("[{\"dof\": -0.0, \"limit\": 0, \"kind\": \"upper\"}]".to_string()),
            Just("[{\"dof\": 0.5, \"limit\": 0, \"kind\": \"upper\"}]".to_string()),
            Just("[{\"dof\": 0, \"limit\": 0, \"kind\": \"upper\", \"dof\": 1}]".to_string()),
            "[ -~]{0,12}",
        ],
    ) {
        let mut fields = [
            "\"a\"".to_string(),
            "{\"dense\": [[2, -1], [-1, 2]]}".to_string(),
            "[1, 0]".to_string(),
            "[{\"dof\": 0, \"limit\": 0.5, \"kind\": \"upper\"}]".to_string(),
            "\"mm\"".to_string(),
            "{\"seed\": 1}".to_string(),
        ];
        fields[slot] = value;
        let text = format!(
            "{{\"name\": {}, \"stiffness\": {}, \"load\": {}, \"constraints\": {}, \"units\": {}, \"meta\": {}}}",
            fields[0], fields[1], fields[2], fields[3], fields[4], fields[5]
        );
        let dir = common::tmp_dir("fuzz-hostile");
        let path = dir.path().join("a.scene.json");
        fs::write(&path, text.as_bytes()).unwrap();
        check_scene_result(&read_scene(&path), &path.display().to_string())?;
        check_scene_result(&parse_scene_str(&text, dir.path(), "h.scene.json"), "h.scene.json")?;
    }
}

// ----------------------------------------------------------------------------------------
// Fixed hostile inputs (regressions and limits)
// ----------------------------------------------------------------------------------------

fn scene_err(text: &str) -> String {
    let e = parse_scene_str(text, Path::new("."), "x.scene.json").unwrap_err();
    let m = e.to_string();
    assert!(m.starts_with("x.scene.json: ") && !m.contains('\n'), "{m}");
    m
}

fn mm_err(text: &str) -> String {
    let e = parse_matrix_market_str(text, "x.mtx").unwrap_err();
    let m = e.to_string();
    assert!(m.starts_with("x.mtx: ") && !m.contains('\n'), "{m}");
    m
}

#[test]
fn deep_nesting_is_rejected_not_a_stack_overflow() {
    for depth in [129usize, 10_000, 200_000] {
        let text = "[".repeat(depth);
        let m = scene_err(&text);
        assert!(m.contains("line 1"), "{m}");
        let text = format!("{}{}", "{\"a\":".repeat(depth), "1");
        scene_err(&text);
    }
}

#[test]
fn huge_declared_sizes_are_refused_before_allocating() {
    for text in [
        "%%MatrixMarket matrix coordinate real general\n16777217 16777217 1\n1 1 1\n",
        "%%MatrixMarket matrix coordinate real general\n18446744073709551615 18446744073709551615 1\n",
        "%%MatrixMarket matrix coordinate real general\n18446744073709551616 18446744073709551616 1\n",
        "%%MatrixMarket matrix array real general\n16777217 16777217\n1\n",
        "%%MatrixMarket matrix coordinate real general\n2 2 18446744073709551615\n1 1 1\n",
    ] {
        mm_err(text);
    }
    // The largest accepted dimension with a truncated body fails fast (nothing read).
    let t = std::time::Instant::now();
    let m = mm_err("%%MatrixMarket matrix array real general\n16777216 16777216\n1 2 3\n");
    assert!(m.contains("truncated"), "{m}");
    assert!(t.elapsed().as_secs_f64() < 5.0);
}

#[test]
fn indices_and_values_at_the_edges() {
    let h = "%%MatrixMarket matrix coordinate real general\n2 2 1\n";
    for body in [
        "0 1 1\n",
        "3 1 1\n",
        "18446744073709551616 1 1\n",
        "-1 1 1\n",
        "1 1 1e999\n",
        "1 1 NaN\n",
        "1 1 -inf\n",
        "1 1 0x10\n",
        "1 1\n",
        "1 1 1 1\n",
        "1.0 1 1\n",
    ] {
        mm_err(&format!("{h}{body}"));
    }
    // Fortran exponents and a BOM are accepted.
    let k = parse_matrix_market_str(
        "\u{feff}%%MatrixMarket matrix coordinate real general\r\n2 2 2\r\n1 1 1.5D+03\r\n2 2 2\r\n",
        "x.mtx",
    )
    .unwrap();
    assert_eq!(k.get(0, 0), 1500.0);
}

#[test]
fn scene_paths_that_are_not_matrix_files() {
    let dir = common::tmp_dir("fuzz-paths");
    fs::create_dir_all(dir.path().join("sub")).unwrap();
    fs::write(dir.path().join("a.scene.json"), "{}").unwrap();
    for rel in [
        "sub",
        ".",
        "missing.mtx",
        "a.scene.json",
        "a\u{0}b.mtx",
        "/",
    ] {
        let text = format!(
            r#"{{"name": "a", "stiffness": {{"matrix_market": {}}}, "load": [1], "constraints": []}}"#,
            serde_json::to_string(rel).unwrap()
        );
        let e = parse_scene_str(&text, dir.path(), "a.scene.json").unwrap_err();
        let m = e.to_string();
        assert!(
            m.starts_with("a.scene.json: ") && m.contains("matrix_market") && !m.contains('\n'),
            "{rel:?}: {m}"
        );
    }
}

#[test]
fn invalid_utf8_scene_file_names_the_offset() {
    let dir = common::tmp_dir("fuzz-utf8");
    let p = dir.path().join("bad.scene.json");
    fs::write(&p, b"{\"name\": \"\xff\"}").unwrap();
    let m = read_scene(&p).unwrap_err().to_string();
    assert!(m.contains("UTF-8") && m.contains("offset 10"), "{m}");
}
