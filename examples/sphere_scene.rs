//! Writes the `hertz-3d` scene of `solver_cost` (+ `.mtx`, `.B.mtx`): the quarter block of
//! trilinear hexahedra of [`penalty_lab::model::solid`] under the rigid sphere, at element
//! size h/a at the contact and base lift a²/R, with the rigid-body modes of its free nodes in
//! slots (a symmetry plane's prescribed component is a slot without a DOF). Arguments: output
//! path, h/a.
//!
//! ```sh
//! cargo run --release --example sphere_scene -- scenes/hertz-3d.scene.json 0.25
//! cargo run --release --bin solve -- scenes/hertz-3d.scene.json --method constant --eps 1e6
//! ```

use penalty_lab::error::Error;
use penalty_lab::scene::write_scene;
use penalty_lab::study::solver_cost::cases::{sphere_grid, sphere_scene, HERTZ};
use std::path::PathBuf;

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let [path, h] = args.as_slice() else {
            return Err(Error::input("usage: sphere_scene PATH H_OVER_A"));
        };
        let h: f64 = h
            .parse()
            .map_err(|_| Error::input(format!("h/a: not a number: {h}")))?;
        let grid = sphere_grid(h)?;
        let lift = HERTZ.a_target * HERTZ.a_target / HERTZ.radius;
        let scene = sphere_scene(&grid, lift)?;
        let meta = serde_json::json!({
            "generator": "model::solid (solver_cost hertz-3d)", "h_over_a": h, "lift": lift,
        });
        let path = PathBuf::from(path);
        let p = &scene.problem;
        write_scene(&path, &format!("hertz-3d-{h}"), p, Some(&meta), 0)?;
        println!("wrote {} (N = {}, m = {})", path.display(), p.n(), p.m());
        Ok(())
    })
}
