//! `sweep --shard K/N`: shards concatenate into the unsharded rows, `sweep merge` joins them
//! (and refuses missing, duplicated, foreign and incomplete shards), the shard ranges cover
//! every scene once, and an empty shard is not a failed run.

use crate::sweep_support::{
    manifest, rows_of, s, stderr, sweep_in, sweep_ok, with, work_dir, SMALL,
};
use penalty_lab::study::sweep;
use std::path::{Path, PathBuf};

#[test]
fn shards_concatenate_into_the_unsharded_rows() {
    let (_tmp, d) = work_dir("shards");
    let (all, a, b) = (d.join("all"), d.join("s1"), d.join("s2"));
    sweep_ok(&d, &with(&SMALL, &["--no-figures", "--out", s(&all)]));
    sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--shard", "1/2", "--out", s(&a)]),
    );
    sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--shard", "2/2", "--out", s(&b)]),
    );
    let mut cat = rows_of(&a);
    let second = rows_of(&b);
    assert!(!cat.is_empty() && !second.is_empty());
    cat.extend(second);
    assert_eq!(cat, rows_of(&all), "shard 1/2 ++ shard 2/2 ≠ unsharded");

    // A 3-way split of the same 6 scenes, too.
    let mut cat3 = Vec::new();
    for k in 1..=3 {
        let o = d.join(format!("t{k}"));
        let shard = format!("{k}/3");
        sweep_ok(
            &d,
            &with(&SMALL, &["--no-figures", "--shard", &shard, "--out", s(&o)]),
        );
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(o.join("manifest.json")).unwrap())
                .unwrap();
        assert_eq!(m["shard"], serde_json::json!([k, 3]));
        assert_eq!(m["scenes"], 2);
        cat3.extend(rows_of(&o));
    }
    assert_eq!(cat3, rows_of(&all), "shards 1..3 of 3 ≠ unsharded");

    // `sweep merge` of 4 shards given in any order: the unsharded rows and a complete
    // manifest that --resume accepts and --render-only draws from.
    let shards = four_shards(&d);
    let merged = d.join("merged");
    let mut args = vec!["merge", s(&merged)];
    args.extend([3, 1, 4, 2].map(|k| s(&shards[k - 1])));
    sweep_ok(&d, &args);
    assert_eq!(
        rows_of(&merged),
        rows_of(&all),
        "merged 4 shards ≠ unsharded"
    );
    let m = manifest(&merged);
    assert_eq!(m["status"], "complete");
    assert_eq!(m["shard"], serde_json::json!([1, 1]));
    assert_eq!(m["merged_from"].as_array().unwrap().len(), 4);
    let o = sweep_ok(
        &d,
        &with(&SMALL, &["--no-figures", "--resume", "--out", s(&merged)]),
    );
    assert_eq!(rows_of(&merged), rows_of(&all), "{}", stderr(&o));
    sweep_ok(&d, &["--render-only", "--out", s(&merged)]);
    assert!(merged.join("figures").read_dir().unwrap().count() > 0);
}

/// Shards 1..4 of 4 of the SMALL run, in `d/q1` … `d/q4`.
fn four_shards(d: &Path) -> Vec<PathBuf> {
    (1..=4)
        .map(|k| {
            let o = d.join(format!("q{k}"));
            let shard = format!("{k}/4");
            sweep_ok(
                d,
                &with(&SMALL, &["--no-figures", "--shard", &shard, "--out", s(&o)]),
            );
            o
        })
        .collect()
}

#[test]
fn merge_refuses_missing_duplicated_foreign_and_incomplete_shards() {
    let (_tmp, d) = work_dir("merge_refuses");
    let q = four_shards(&d);
    let foreign = d.join("foreign");
    let other_seed: Vec<&str> = SMALL
        .iter()
        .map(|&a| if a == "77" { "78" } else { a })
        .collect();
    sweep_ok(
        &d,
        &with(
            &other_seed,
            &["--no-figures", "--shard", "4/4", "--out", s(&foreign)],
        ),
    );
    let incomplete = d.join("incomplete");
    std::fs::create_dir_all(&incomplete).unwrap();
    std::fs::copy(q[3].join("rows.csv"), incomplete.join("rows.csv")).unwrap();
    let mut m = manifest(&q[3]);
    m["status"] = "running".into();
    std::fs::write(incomplete.join("manifest.json"), m.to_string()).unwrap();
    let out = d.join("out");
    let cases: [(Vec<&Path>, &str); 5] = [
        (
            vec![&q[0], &q[1], &q[3]],
            "shard 3/4: none given (got 3 of 4 shards",
        ),
        (vec![&q[0], &q[1], &q[1], &q[2], &q[3]], "given twice"),
        (
            vec![&q[0], &q[1], &q[2], &foreign],
            "belongs to another run (config differs",
        ),
        (vec![&q[0], &q[1], &q[2], &incomplete], "is not complete"),
        (
            vec![&q[0], &q[1], &q[2], &q[3], &d],
            "no readable manifest.json",
        ),
    ];
    for (dirs, needle) in cases {
        let mut args = vec!["merge", s(&out)];
        args.extend(dirs.iter().map(|p| s(p)));
        let o = sweep_in(&d, &args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(
            e.starts_with("error:") && e.trim_end().lines().count() == 1,
            "{e}"
        );
        assert!(e.contains(needle), "{needle:?} not in {e}");
        assert!(!out.exists(), "a refused merge wrote {}", out.display());
    }
    // OUT may not be one of the shards.
    let mut args = vec!["merge", s(&q[0])];
    args.extend(q.iter().map(|p| s(p)));
    let o = sweep_in(&d, &args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is one of the shard folders"),
        "{}",
        stderr(&o)
    );
}
#[test]
fn shard_ranges_cover_every_scene_exactly_once() {
    // The example of the brief: shard 3/3 of 5 scenes.
    assert_eq!(sweep::shard_range(5, 1, 3), 0..1);
    assert_eq!(sweep::shard_range(5, 2, 3), 1..3);
    assert_eq!(sweep::shard_range(5, 3, 3), 3..5);
    for total in 0..80usize {
        for n in 1..=17usize {
            let mut next = 0;
            for k in 1..=n {
                let r = sweep::shard_range(total, k, n);
                assert_eq!(
                    r.start, next,
                    "total {total}, shard {k}/{n}: gap or overlap"
                );
                assert!(r.end >= r.start);
                // Balanced: sizes differ by at most one.
                assert!(
                    r.len() == total / n || r.len() == total / n + 1,
                    "total {total}, shard {k}/{n}: size {}",
                    r.len()
                );
                next = r.end;
            }
            assert_eq!(next, total, "total {total}, n {n}: not all covered");
        }
    }
    // Large totals do not overflow for realistic sizes.
    let r = sweep::shard_range(1_000_000_007, 1000, 1000);
    assert_eq!(r.end, 1_000_000_007);

    assert_eq!(sweep::parse_shard("3/3").unwrap(), (3, 3));
    assert_eq!(sweep::parse_shard(" 1 / 4 ").unwrap(), (1, 4));
    for bad in ["3/2", "0/2", "1/0", "x", "1/", "/2", "1/2/3", "-1/2", ""] {
        assert!(sweep::parse_shard(bad).is_err(), "'{bad}' accepted");
    }
}

#[test]
fn shard_with_no_scenes_is_not_a_failed_run() {
    // 2 scenes in 8 shards: shard 3/8 is empty. Either that is fine (exit 0, empty rows.csv)
    // or it is a configuration error reported before anything is written — not a run that
    // writes a "complete" manifest and then exits 2 because there is nothing to plot.
    let (_tmp, d) = work_dir("empty_shard");
    let out = d.join("o");
    let o = sweep_in(
        &d,
        &[
            "--families",
            "beam",
            "--count",
            "2",
            "--eps",
            "1e0:1e8:3",
            "--deltas-rel",
            "1e-2",
            "--shard",
            "3/8",
            "--out",
            s(&out),
        ],
    );
    if o.status.success() {
        assert!(rows_of(&out).is_empty());
    } else {
        assert_eq!(o.status.code(), Some(2));
        assert!(
            !out.join("rows.csv").exists(),
            "exit 2 after writing rows.csv/manifest.json (stderr: {})",
            stderr(&o)
        );
    }
}
