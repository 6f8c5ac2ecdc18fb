//! Helpers shared by the tests: the CLI contract of the experiment binaries, and independent
//! dense helpers ([`dense`]). Each test crate uses part of them.
#![allow(dead_code)]

pub mod dense;

use std::path::Path;
use std::process::Command;

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
    let o = Command::new(bin)
        .arg("--render-only")
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .expect("binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
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
