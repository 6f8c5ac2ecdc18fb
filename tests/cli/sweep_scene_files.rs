//! Scene files: `--scenes-dir` reproduces the generated rows (small and large dense scenes),
//! and a malformed scene file keeps the scenes before it and resumes once repaired.

use crate::sweep_support::{
    generated_and_file_runs, manifest, rows_of, s, stderr, sweep_in, sweep_ok, with, work_dir,
    write_toml, FILE_RUN_KNOBS,
};

#[test]
fn scenes_dir_reproduces_the_generated_rows() {
    let (_tmp, gen, files, _) = generated_and_file_runs("scenes_dir");
    assert_eq!(gen.len(), files.len());
    assert!(!gen.is_empty());
    // Scene names come from the files' "name", the family from meta.generator: the rows are
    // identical, naming included (scene file order = generated order here).
    for (g, f) in gen.iter().zip(&files) {
        assert_eq!(
            g, f,
            "row of {} differs when run from the scene file",
            g.scene
        );
    }
}

/// A malformed scene file stops the run with exit 2 and a message naming it; rows.csv then
/// holds exactly the complete scenes before it (whatever the thread count), the
/// manifest still says `running`, and once the file is repaired `--resume` completes the rows.
#[test]
fn a_malformed_scene_file_keeps_the_scenes_before_it_and_resumes() {
    let (_tmp, _, files, scenes) = generated_and_file_runs("malformed_scene");
    let d = scenes.parent().unwrap().to_path_buf();
    let per_scene = files.len() / 4;
    let broken = scenes.join("spectrum-0000.scene.json");
    let good = std::fs::read(&broken).unwrap();
    std::fs::write(&broken, &good[..good.len() / 2]).unwrap();
    let out = d.join("broken");
    let args = with(
        &FILE_RUN_KNOBS,
        &[
            "--threads",
            "2",
            "--scenes-dir",
            s(&scenes),
            "--out",
            s(&out),
        ],
    );
    let o = sweep_in(&d, &args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("spectrum-0000.scene.json"),
        "{}",
        stderr(&o)
    );
    // The scenes before it, each written as it completed (in either order).
    let mut kept = rows_of(&out);
    kept.sort_by_key(|r| files.iter().position(|f| f.scene == r.scene));
    assert_eq!(kept, files[..2 * per_scene]);
    assert_eq!(manifest(&out)["status"], "running");
    std::fs::write(&broken, &good).unwrap();
    sweep_ok(&d, &with(&args, &["--resume"]));
    assert_eq!(rows_of(&out), files);
    assert_eq!(manifest(&out)["resumed_scenes"], 2);
}
/// A dense K with N > 400 (beams of 140–150 elements: N ≈ 430) is written by `--write-scenes`
/// as a Matrix Market file (`scene::write_scene(.., 400)` in `sweep::run`) and reads back as
/// *sparse* storage, so the file run takes other numerical routes (sparse factorization,
/// `densified_symmetric_eigen`) and its rows are no longer those of the generated run.
/// Every rule but `optimal`, which takes 80 s per solve on this beam and whose file runs
/// [`generated_and_file_runs`] covers.
#[test]
fn scenes_dir_reproduces_large_dense_scenes() {
    let (_tmp, d) = work_dir("large_dense");
    let (gen, files, scenes) = (d.join("gen"), d.join("files"), d.join("scenes"));
    let cfg = write_toml(
        &d,
        "large",
        "families = [\"beam\"]\ncount = 1\nseed = 2011\n[generator]\nbeam_elements = [140, 150]\n",
    );
    let knobs: Vec<&str> = FILE_RUN_KNOBS
        .iter()
        .copied()
        .chain([
            "--methods",
            "constant,scaled,spring,paper,condensed,augmented",
        ])
        .collect();
    sweep_ok(
        &d,
        &with(
            &knobs,
            &[
                "--config",
                s(&cfg),
                "--out",
                s(&gen),
                "--write-scenes",
                s(&scenes),
            ],
        ),
    );
    sweep_ok(
        &d,
        &with(&knobs, &["--scenes-dir", s(&scenes), "--out", s(&files)]),
    );
    let (g, f) = (rows_of(&gen), rows_of(&files));
    assert!(
        g[0].n > 400,
        "N = {} (want a dense K above the threshold)",
        g[0].n
    );
    assert_eq!(g.len(), f.len());
    let differing: Vec<String> = g
        .iter()
        .zip(&f)
        .filter(|(a, b)| a != b)
        .map(|(a, b)| {
            format!(
                "{} {}: cond_route {:?} vs {:?}, max_penetration {:?} vs {:?}",
                a.scene, a.method, a.cond_route, b.cond_route, a.max_penetration, b.max_penetration
            )
        })
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {} rows differ when re-run from the written scene file:\n{}",
        differing.len(),
        g.len(),
        differing.join("\n")
    );
}
