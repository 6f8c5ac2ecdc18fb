//! Writes a contact benchmark's scene (+ `.mtx`, `.B.mtx`) as `solver_cost` meshes it: one of
//! [`penalty_lab::study::hertz::Case`] (`hertz-plane`, `hertz-normals`,
//! `patch-two-body-nts-1`, …) on its block at element size h/a, at the first lift guess of
//! force control (the half-space indentation a²/R; the patch tests: their uniform pressure's),
//! with the plane rigid-body modes of its nodes in slots where the geometry is plane strain.
//! Arguments: output path, case, h/a.
//!
//! ```sh
//! cargo run --release --example contact_scene -- scenes/nts.scene.json patch-two-body-nts-1 0.125
//! cargo run --release --bin solve -- scenes/nts.scene.json --method constant --eps 1e8
//! ```

use penalty_lab::error::Error;
use penalty_lab::scene::write_scene;
use penalty_lab::study::hertz::Case;
use penalty_lab::study::solver_cost::cases::{HERTZ, HERTZ_BLOCK};
use std::path::PathBuf;

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let [path, case, h] = args.as_slice() else {
            return Err(Error::input("usage: contact_scene PATH CASE H_OVER_A"));
        };
        let case =
            Case::from_name(case).ok_or_else(|| Error::input(format!("unknown case: {case}")))?;
        let h: f64 = h
            .parse()
            .map_err(|_| Error::input(format!("h/a: not a number: {h}")))?;
        let grid = HERTZ.grid(case, h, HERTZ_BLOCK)?;
        let lift = HERTZ.lift_guess(case, &grid);
        let scene = HERTZ.scene(case, &grid, lift)?;
        let meta = serde_json::json!({
            "generator": "study::hertz (solver_cost's meshes)", "case": case.name(),
            "h_over_a": h, "lift": lift,
        });
        let path = PathBuf::from(path);
        let p = &scene.problem;
        write_scene(&path, &format!("{}-{h}", case.name()), p, Some(&meta), 0)?;
        println!("wrote {} (N = {}, m = {})", path.display(), p.n(), p.m());
        Ok(())
    })
}
