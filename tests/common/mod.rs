//! Helpers shared by the tests: temporary folders, running the experiment binaries and their
//! CLI contract, independent dense helpers ([`dense`]) and matrices with known structure
//! ([`matrices`]). Each test crate uses part of them.
#![allow(dead_code)]

pub mod dense;
pub mod matrices;

use std::path::Path;
use std::process::{Command, Output};

/// A fresh, empty folder for one test, named after `tag` and unique to the call (parallel
/// tests never share one). It and everything written in it are removed when the returned
/// guard drops: keep it alive for the whole test and use `.path()`.
pub fn tmp_dir(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("penalty-lab-{tag}-"))
        .tempdir()
        .expect("create a temporary folder")
}

/// `o`'s stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Requires each of `names` to be a file in `dir`.
#[track_caller]
pub fn assert_files(dir: &Path, names: &[&str]) {
    for f in names {
        assert!(dir.join(f).is_file(), "{f} missing in {}", dir.display());
    }
}

/// Runs `cmd` to completion and requires exit status 0 (stderr in the failure message);
/// returns its output.
#[track_caller]
pub fn run_ok(cmd: &mut Command) -> Output {
    let o = cmd.output().expect("binary runs");
    assert!(
        o.status.success(),
        "{cmd:?} failed ({:?}):\n{}",
        o.status,
        stderr(&o)
    );
    o
}

/// The bad-input contract of an experiment binary: `bin ARGS EXTRA --out OUT`, for each
/// `ARGS` of `cases` and OUT a folder that does not exist, exits with status 2 and writes
/// nothing (OUT stays absent). Returns each run's output, in the order of `cases`, for the
/// binary's own checks of its message.
#[track_caller]
pub fn assert_bad_input_writes_nothing(
    bin: &str,
    cases: &[Vec<&str>],
    extra: &[&str],
) -> Vec<Output> {
    let tmp = tmp_dir("bad-input");
    let out = tmp.path().join("out");
    cases
        .iter()
        .map(|args| {
            let o = Command::new(bin)
                .args(args)
                .args(extra)
                .arg("--out")
                .arg(&out)
                .output()
                .expect("binary runs");
            assert_eq!(o.status.code(), Some(2), "{args:?}");
            assert!(!out.exists(), "{args:?}: nothing written on bad input");
            o
        })
        .collect()
}

/// The seven contact methods of methods.md, by their strategy names.
pub const METHODS: [&str; 7] = [
    "constant",
    "scaled",
    "spring",
    "paper",
    "condensed",
    "lagrange",
    "augmented",
];

/// The `--render-only` contract of an experiment binary: with `out` holding a finished run,
/// removing `figure` (a path below `out`) and running `bin --render-only --out OUT` redraws
/// it from the saved data alone; on a folder without the data file `data` it exits with
/// status 2 and names that file. Returns the successful run's stdout.
pub fn assert_render_only(
    bin: &str,
    out: &Path,
    figure: &str,
    data: &str,
    extra: &[&str],
) -> Vec<u8> {
    let fig = out.join(figure);
    std::fs::remove_file(&fig).unwrap_or_else(|e| panic!("{}: {e}", fig.display()));
    let o = run_ok(
        Command::new(bin)
            .arg("--render-only")
            .args(extra)
            .arg("--out")
            .arg(out),
    );
    assert!(fig.is_file(), "--render-only did not redraw {figure}");
    let empty = out.join("no-data-here");
    std::fs::create_dir_all(&empty).unwrap();
    let e = Command::new(bin)
        .arg("--render-only")
        .arg("--out")
        .arg(&empty)
        .output()
        .expect("binary runs");
    assert_eq!(e.status.code(), Some(2));
    let err = String::from_utf8_lossy(&e.stderr);
    assert!(err.contains(data), "'{err}' does not name {data}");
    o.stdout
}

/// A `.vtu` file read back with vtkio (the writer's crate, an independent code path from
/// the writer's): the node coordinates and the point arrays by name.
pub fn read_vtu(
    path: &std::path::Path,
) -> (Vec<[f64; 3]>, std::collections::HashMap<String, Vec<f64>>) {
    use vtkio::model::{Attribute, DataSet};
    let vtk = vtkio::Vtk::import(path).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).unwrap();
    let pts: Vec<f64> = piece.points.cast_into().unwrap();
    let points = pts.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut arrays = std::collections::HashMap::new();
    for a in piece.data.point {
        if let Attribute::DataArray(d) = a {
            arrays.insert(d.name.clone(), d.data.cast_into::<f64>().unwrap());
        }
    }
    (points, arrays)
}
