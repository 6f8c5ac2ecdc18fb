//! `sweep`: ε and δ over randomized contact configurations — the harness's main job.
//!
//! ```text
//! cargo run --release --bin sweep                       # built-in default (< 1 min, 2 cores)
//! cargo run --release --bin sweep -- --families beam --count 50 --eps 1e0:1e10:21 --threads 2
//! cargo run --release --bin sweep -- --scenes-dir scenes/ --out results/files
//! cargo run --release --bin sweep -- --render-only --out results/sweep
//! cargo run --release --bin sweep -- merge results/all results/shard-1 results/shard-2
//! ```
//!
//! Writes `OUT/rows.csv`, `OUT/manifest.json` and `OUT/figures/*.{png,svg}`. Bad configuration
//! exits with status 2 and a message naming the problem and the valid choices.

use penalty_lab::study::{self, sweep::Sweep};
use std::process::ExitCode;

fn main() -> ExitCode {
    pad_the_heap();
    study::main::<Sweep>()
}

/// Asks glibc's malloc to grow its heaps 16 MiB at a time and to keep 16 MiB free at their top
/// when it trims them (`M_TOP_PAD`; the default is 128 KiB): a sweep allocates and frees the
/// same few vectors and factors scene after scene, and each time the heap shrank they came
/// back as fresh pages, a page fault each. On the 20-scene folder of `scripts/folder.toml`
/// that was 1.5 % of the run (docs/performance.md); the memory it may keep is 16 MiB per
/// thread's heap. Other C libraries are left as they are.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn pad_the_heap() {
    // SAFETY: mallopt only sets a tuning parameter of malloc; it runs before any other thread
    // exists, and a refused value (return 0) leaves the default in place.
    unsafe {
        libc::mallopt(libc::M_TOP_PAD, 16 << 20);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn pad_the_heap() {}
