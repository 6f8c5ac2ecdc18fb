//! Bad `sweep` configuration (flags and TOML): exit status 2, one line naming the problem,
//! nothing written.

use crate::common;
use crate::sweep_support::{s, stderr, sweep_in, with, work_dir, write_toml};
use std::path::Path;

/// Runs a bad config; requires exit 2, one stderr line starting with "error:" that contains
/// every `needle`, and no rows.csv written.
fn assert_rejected(d: &Path, tag: &str, args: &[&str], needles: &[&str]) {
    let out = d.join(format!("out_{tag}"));
    let all = with(args, &["--out", s(&out)]);
    let o = sweep_in(d, &all);
    let e = stderr(&o);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{all:?}: status {:?}, stderr {e}",
        o.status
    );
    assert!(e.starts_with("error:"), "{all:?}: {e}");
    assert_eq!(
        e.trim_end().lines().count(),
        1,
        "{all:?}: stderr is not one line:\n{e}"
    );
    for n in needles {
        assert!(e.contains(n), "{all:?}: message lacks '{n}': {e}");
    }
    assert!(
        !out.join("rows.csv").exists(),
        "{all:?}: rows.csv written before validation"
    );
    assert!(
        !out.join("manifest.json").exists(),
        "{all:?}: manifest written"
    );
}

#[test]
fn bad_configuration_exits_2_with_one_line_and_writes_nothing() {
    let (_tmp, d) = work_dir("bad");
    let methods = common::METHODS;
    assert_rejected(
        &d,
        "method",
        &["--methods", "constant,penalty"],
        &[&["'penalty'"][..], &methods[..]].concat(),
    );
    assert_rejected(
        &d,
        "family",
        &["--families", "beam,shell"],
        &["'shell'", "beam", "membrane", "spectrum"],
    );
    assert_rejected(&d, "eps2", &["--eps", "1:2"], &["'1:2'", "LO:HI:N"]);
    assert_rejected(&d, "eps0", &["--eps", "0:1:3"], &["'0:1:3'", "LO:HI:N"]);
    assert_rejected(&d, "epsabc", &["--eps", "a:b:c"], &["'a:b:c'", "LO:HI:N"]);
    assert_rejected(&d, "epsrev", &["--eps", "1e3:1e1:3"], &["LO:HI:N"]);
    assert_rejected(&d, "eps1", &["--eps", "1:2:1"], &["LO:HI:N"]);
    assert_rejected(&d, "deltaneg", &["--deltas", "-1"], &["--deltas", "> 0"]);
    assert_rejected(&d, "delta0", &["--deltas", "0"], &["--deltas", "> 0"]);
    assert_rejected(&d, "deltarel", &["--deltas-rel", "0"], &["--deltas-rel"]);
    assert_rejected(&d, "factor", &["--factors", "-3"], &["factor"]);
    assert_rejected(&d, "shard32", &["--shard", "3/2"], &["'3/2'", "K/N"]);
    assert_rejected(&d, "shardx", &["--shard", "x"], &["'x'", "K/N"]);
    assert_rejected(&d, "shard0", &["--shard", "0/2"], &["K/N"]);
    assert_rejected(
        &d,
        "scenesdir",
        &["--scenes-dir", s(&d.join("no_such_dir"))],
        &["no_such_dir"],
    );
    let empty = d.join("empty_scenes");
    std::fs::create_dir_all(&empty).unwrap();
    assert_rejected(
        &d,
        "scenesempty",
        &["--scenes-dir", s(&empty)],
        &["empty_scenes", "scene.json"],
    );
    assert_rejected(
        &d,
        "metric",
        &["--metrics", "cond,flops"],
        &["'flops'", "cond", "det"],
    );
    assert_rejected(&d, "count0", &["--count", "0"], &["--count"]);
    assert_rejected(
        &d,
        "kerr0",
        &["--krylov-err", "0"],
        &["--krylov-err", "(0, 1)"],
    );
    assert_rejected(
        &d,
        "kerr1",
        &["--krylov-err", "1.5"],
        &["--krylov-err", "(0, 1)"],
    );
    assert_rejected(&d, "threads0", &["--threads", "0"], &["--threads"]);
    let nodelta = write_toml(&d, "nodelta", "deltas_rel = []\n");
    assert_rejected(
        &d,
        "nodelta",
        &["--methods", "condensed", "--config", s(&nodelta)],
        &["δ", "--deltas"],
    );
    assert_rejected(
        &d,
        "generator",
        &[
            "--config",
            s(&write_toml(
                &d,
                "gen",
                "[generator]\nbeam_elements = [2, 10]\n",
            )),
        ],
        &["beam_elements", "3 ≤ min"],
    );
    assert_rejected(
        &d,
        "noconfig",
        &["--config", s(&d.join("missing.toml"))],
        &["missing.toml"],
    );
}
#[test]
fn toml_config_with_unknown_field_is_a_one_line_error() {
    let (_tmp, d) = work_dir("bad_toml");
    let p = write_toml(&d, "typo", "famlies = [\"beam\"]\ncount = 2\n");
    assert_rejected(&d, "typo", &["--config", s(&p)], &["famlies", "families"]);
    let p = write_toml(&d, "gentypo", "[generator]\nbeam_elems = [3, 5]\n");
    assert_rejected(&d, "gentypo", &["--config", s(&p)], &["beam_elems"]);
}

/// A value of the TOML file that fails validation is placed in the file: its key and line
/// (after a comment line, in a file that also sets a valid key); the same value from a flag
/// names the flag, and a flag that replaces the file's value clears the error.
#[test]
fn a_bad_value_of_the_config_file_names_its_key_and_line() {
    let (_tmp, d) = work_dir("bad_value");
    // (tag, file, what the message names); the last in the [generator] table, after a
    // comment with a multi-line delimiter.
    let cases = [
        (
            "count0",
            "# one family\nfamilies = [\"beam\"]\ncount = 0\n",
            ["count0.toml: line 3: `count`:", "≥ 1"],
        ),
        (
            "rel",
            "families = [\"beam\"]\ndeltas_rel = [1e-2, -1e-3]\n",
            ["rel.toml: line 2: `deltas_rel`:", "-0.001"],
        ),
        (
            "gen",
            "# strings: \"\"\"\nfamilies = [\"membrane\"]\n[generator]\nmembrane_side = [0, 0]\n",
            ["gen.toml: line 4: `membrane_side`:", "10 ≤ min"],
        ),
    ];
    for (tag, text, needles) in cases {
        let p = write_toml(&d, tag, text);
        assert_rejected(&d, tag, &["--config", s(&p)], &needles);
    }
    // From a flag: the flag, not the file.
    let p = write_toml(&d, "ok", "families = [\"beam\"]\ncount = 2\n");
    let o = sweep_in(
        &d,
        &["--config", s(&p), "--count", "0", "--out", s(&d.join("o1"))],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("--count") && !e.contains("ok.toml"), "{e}");
    // The flag replaces the file's bad value: no error about it.
    let p = write_toml(&d, "fixed", "families = [\"beam\"]\ncount = 0\n");
    let o = sweep_in(
        &d,
        &[
            "--config",
            s(&p),
            "--count",
            "1",
            "--eps",
            "1:10:2",
            "--methods",
            "constant",
            "--metrics",
            "none",
            "--no-figures",
            "--out",
            s(&d.join("o2")),
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// A list entry given twice would run the same rows twice; an ε grid of absurd size is a typo
/// (and would exhaust memory): both are refused before anything is written.
#[test]
fn repeated_entries_and_huge_grids_are_refused() {
    let (_tmp, d) = work_dir("repeats");
    assert_rejected(
        &d,
        "fam2",
        &["--families", "beam,beam"],
        &["families", "'beam'", "twice"],
    );
    assert_rejected(
        &d,
        "meth2",
        &["--methods", "paper,paper"],
        &["methods", "'paper'", "twice"],
    );
    assert_rejected(
        &d,
        "delta2",
        &["--deltas-rel", "0.1,0.1"],
        &["deltas_rel", "twice"],
    );
    assert_rejected(
        &d,
        "epsn",
        &["--eps", "1:10:100000000"],
        &["LO:HI:N", "10000"],
    );
}

/// Flags that shape generated scenes are refused beside `--scenes-dir` (they would be ignored).
#[test]
fn generator_flags_beside_a_scene_folder_are_refused() {
    let (_tmp, d) = work_dir("scenes_and_families");
    let dir = d.join("scenes");
    std::fs::create_dir_all(&dir).unwrap();
    for (tag, flag) in [("fam", "--families"), ("count", "--count")] {
        let value = if flag == "--count" { "2" } else { "beam" };
        assert_rejected(
            &d,
            tag,
            &["--scenes-dir", s(&dir), flag, value],
            &[flag, "--scenes-dir"],
        );
    }
}
