//! No panics on arbitrary input: both readers on arbitrary bytes and strings, Matrix
//! Market-like and JSON-like text, and mutations of a valid scene.

use crate::scene_support::{fixtures, MM_HDR};
use penalty_lab::scene::{parse_matrix_market_str, parse_scene_str};
use proptest::prelude::*;
use std::fs;
use std::path::Path;

fn mm_line() -> impl Strategy<Value = String> {
    prop_oneof![
        "[0-9]{1,2} [0-9]{1,2} [-+.eEinfaD0-9]{1,8}",
        "[0-9]{1,25} [0-9]{1,25} [-0-9.e]{1,25}",
        "[0-9 ]{0,12}",
        "%[ -~]{0,10}",
        "[ -~]{0,20}",
    ]
}

fn mm_text() -> impl Strategy<Value = String> {
    (
        "%%MatrixMarket matrix (coordinate|array|vector) (real|integer|double|pattern|complex|x) (general|symmetric|skew-symmetric|hermitian)",
        prop_oneof!["[0-9]{1,2} [0-9]{1,2}( [0-9]{1,2})?", "[0-9]{1,25} [0-9]{1,25} [0-9]{1,25}", "[ -~]{0,12}"],
        prop::collection::vec(mm_line(), 0..10),
        prop_oneof![Just("\n"), Just("\r\n")],
    )
        .prop_map(|(h, s, lines, nl)| {
            let mut t = format!("{h}{nl}{s}{nl}");
            for l in lines {
                t.push_str(&l);
                t.push_str(nl);
            }
            t
        })
}

/// A valid scene text with a few random edits at random char boundaries.
fn mutated_scene() -> impl Strategy<Value = String> {
    let base = fs::read_to_string(fixtures().join("small.scene.json")).unwrap();
    prop::collection::vec(
        (
            any::<prop::sample::Index>(),
            0usize..4,
            "[\\[\\]{}\":,0-9a-zA-Z .eE+\\\\-]{0,3}",
        ),
        1..5,
    )
    .prop_map(move |edits| {
        let mut chars: Vec<char> = base.chars().collect();
        for (idx, del, ins) in edits {
            let at = idx.index(chars.len() + 1);
            let end = (at + del).min(chars.len());
            chars.splice(at..end, ins.chars());
        }
        chars.into_iter().collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_scene_str(&text, Path::new("."), "fuzz.scene.json");
        let _ = parse_matrix_market_str(&text, "fuzz.mtx");
        let with_header = format!("{MM_HDR}{text}");
        let _ = parse_matrix_market_str(&with_header, "fuzz.mtx");
    }

    #[test]
    fn arbitrary_strings_never_panic(s in "\\PC{0,300}") {
        let _ = parse_scene_str(&s, Path::new("."), "fuzz.scene.json");
        let _ = parse_matrix_market_str(&s, "fuzz.mtx");
    }

    #[test]
    fn matrix_market_like_text_never_panics(text in mm_text()) {
        if let Ok(k) = parse_matrix_market_str(&text, "fuzz.mtx") {
            prop_assert!(k.is_sparse());
            prop_assert!(k.all_finite());
        }
    }

    #[test]
    fn json_like_text_never_panics(s in "[\\[\\]{}\":,0-9a-z .eE+\\\\-]{0,200}") {
        let _ = parse_scene_str(&s, Path::new("."), "fuzz.scene.json");
    }

    #[test]
    fn mutated_scenes_never_panic(text in mutated_scene()) {
        match parse_scene_str(&text, &fixtures(), "fuzz.scene.json") {
            Ok(s) => prop_assert_eq!(s.problem.q.len(), s.problem.n()),
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.starts_with("fuzz.scene.json: "), "{}", msg);
                prop_assert!(!msg.contains('\n'), "{}", msg);
            }
        }
    }
}
