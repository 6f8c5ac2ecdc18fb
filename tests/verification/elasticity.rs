//! The Q4 elasticity assembly (`model::elasticity`) against an outside FE code: scikit-fem
//! 12.0.2's plane-strain bilinear-quad stiffness of the 30×8 block in
//! `tests/data/elasticity/elasticity-quad-block` (copied from `shared/data/elasticity`; E =
//! 210e3, ν = 0.3, top face eliminated, DOFs (u, v) per node, nodes column by column).

use penalty_lab::model::elasticity::{assemble, Geometry, Grid, Material};
use penalty_lab::scene::read_matrix_market;
use std::path::Path;

#[test]
fn plane_strain_q4_matches_scikit_fem() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/elasticity/elasticity-quad-block.mtx");
    let theirs = read_matrix_market(&path).unwrap();
    // Square elements: a Q4 plane-strain K does not depend on the element size.
    let (nx, ny) = (30, 8);
    let grid = Grid::uniform(nx as f64, ny as f64, nx, ny);
    let material = Material {
        young: 210e3,
        poisson: 0.3,
    };
    let t = assemble(&grid, Geometry::PlaneStrain, &material).unwrap();
    // Keep every DOF but those of the top nodes (j = ny), in order.
    let ndof = 2 * grid.nodes();
    let mut map = vec![usize::MAX; ndof];
    let mut n = 0;
    for (d, slot) in map.iter_mut().enumerate() {
        let j = (d / 2) % grid.ny();
        if j != ny {
            *slot = n;
            n += 1;
        }
    }
    assert_eq!(n, theirs.n());
    let mut ours = vec![vec![0.0; n]; n];
    for (r, c, v) in t {
        if map[r] != usize::MAX && map[c] != usize::MAX {
            ours[map[r]][map[c]] += v;
        }
    }
    let scale = theirs.max_abs();
    let mut worst = 0.0f64;
    for (i, row) in ours.iter().enumerate() {
        for (j, &v) in row.iter().enumerate() {
            worst = worst.max((v - theirs.get(i, j)).abs());
        }
    }
    // Both are sums of at most 4 element contributions of 2×2 Gauss points: rounding level.
    assert!(
        worst <= 64.0 * f64::EPSILON * scale,
        "largest entry difference {worst:e} (max |K| = {scale:e})"
    );
}
