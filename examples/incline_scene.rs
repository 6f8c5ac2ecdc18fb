//! Writes an inclined-block scene (+ `.mtx`): the axis-aligned elastic block of
//! [`penalty_lab::model::incline_block`] pressed on a rigid plane inclined at θ, one two-term
//! row `sinθ·u_x + cosθ·u_y ≥ −g₀` per bottom node — the rows a diagonal preconditioner cannot
//! absorb. Arguments: output path, θ in degrees, elements along x (y: half).
//!
//! ```sh
//! cargo run --release --example incline_scene -- scenes/incline-30.scene.json 30 16
//! cargo run --release --bin solve -- scenes/incline-30.scene.json --method constant --eps 1e6
//! ```

use penalty_lab::error::Error;
use penalty_lab::model::incline_block;
use penalty_lab::scene::write_scene;
use std::path::PathBuf;

fn main() -> std::process::ExitCode {
    penalty_lab::error::run_main(|| {
        let args: Vec<String> = std::env::args().skip(1).collect();
        let [path, theta, nx] = args.as_slice() else {
            return Err(Error::input("usage: incline_scene PATH THETA_DEGREES NX"));
        };
        let theta: f64 = theta
            .parse()
            .map_err(|_| Error::input(format!("θ: not a number: {theta}")))?;
        let nx: usize = nx
            .parse()
            .map_err(|_| Error::input(format!("NX: not a whole number: {nx}")))?;
        let p = incline_block::problem(theta, nx, nx / 2)?;
        let meta = serde_json::json!({
            "generator": "model::incline_block",
            "theta_deg": theta, "nx": nx, "ny": nx / 2,
        });
        let path = PathBuf::from(path);
        write_scene(&path, &format!("incline-{theta}-{nx}"), &p, Some(&meta), 0)?;
        println!("wrote {} (N = {}, m = {})", path.display(), p.n(), p.m());
        Ok(())
    })
}
