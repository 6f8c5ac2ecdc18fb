//! Writes `scenes/bed_cantilever.scene.json` (+ `.mtx`): a 93-element clamped cantilever
//! (279 DOFs) on a wavy rigid bed with one `lower` constraint per node
//! ([`penalty_lab::model::beam::bed`]) — the scene on which the plain active-set loop of the
//! classical penalty cycles for ε near the beam's stiffness at the contact DOFs.
//!
//! ```sh
//! cargo run --release --example bed_scene
//! cargo run --release --bin solve -- scenes/bed_cantilever.scene.json --method constant --eps 3.378e5
//! ```

use penalty_lab::model::beam::bed::{self, Bed};
use penalty_lab::scene::write_scene;
use std::path::Path;

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let b = Bed {
            n_el: 93,
            load: -1.0,
            amp: 0.1,
            waves: 10.0,
        };
        let p = bed::problem(b)?;
        let meta = serde_json::json!({
            "generator": "model::beam::bed",
            "n_el": b.n_el, "load": b.load, "amp": b.amp, "waves": b.waves,
        });
        let path = Path::new("scenes/bed_cantilever.scene.json");
        write_scene(path, "bed-cantilever", &p, Some(&meta), 0)?;
        println!("wrote {} (N = {}, m = {})", path.display(), p.n(), p.m());
        Ok(())
    })
}
