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

/// The axisymmetric quadrilateral (strains εr, εz, γrz, εθ = u_r/r; per radian, weight r):
/// on a rectangle off the axis it is the rectangle element; on a distorted quad the axial
/// translation carries no force, and u = (a r, d z) — exact in the bilinear space, so
/// εθ = a exactly — stores ½·(εᵀCε)·∫ r dA with ∫ r dA by the polygon's first moment
/// (r·det J is at most quadratic in ξ and η: 2×2 Gauss is exact).
fn axisymmetric_quad_passes_its_checks(m: &Material) {
    use penalty_lab::model::elasticity::{element_stiffness, quad_stiffness};
    let g = Geometry::Axisymmetric;
    let c = m.c_matrix(g);
    let rect = quad_stiffness(g, &c, [(0.5, 1.0), (2.0, 1.0), (2.0, 1.75), (0.5, 1.75)]).unwrap();
    let want = element_stiffness(g, &c, (0.5, 2.0), (1.0, 1.75));
    let scale = want.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    for (r, w) in rect.iter().flatten().zip(want.iter().flatten()) {
        assert!((r - w).abs() <= 16.0 * f64::EPSILON * scale, "{r} vs {w}");
    }
    let xy = [(0.4, 0.0), (2.0, 0.3), (2.4, 1.9), (0.3, 1.4)];
    let ke = quad_stiffness(g, &c, xy).unwrap();
    let scale = ke.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    let field = |f: &dyn Fn(f64, f64) -> (f64, f64)| -> [f64; 8] {
        let mut u = [0.0; 8];
        for (k, &(x, y)) in xy.iter().enumerate() {
            (u[2 * k], u[2 * k + 1]) = f(x, y);
        }
        u
    };
    let apply = |u: &[f64; 8]| -> [f64; 8] {
        let mut f = [0.0; 8];
        for (fi, row) in f.iter_mut().zip(&ke) {
            *fi = row.iter().zip(u).map(|(k, x)| k * x).sum();
        }
        f
    };
    for f in apply(&field(&|_, _| (0.0, 1.0))) {
        assert!(
            f.abs() <= 64.0 * f64::EPSILON * scale,
            "axial translation force {f:e}"
        );
    }
    let (a, d) = (1e-3, -6e-4);
    let u = field(&|x, y| (a * x, d * y));
    let energy: f64 = 0.5 * u.iter().zip(apply(&u)).map(|(x, f)| x * f).sum::<f64>();
    // ∫ r dA over the polygon: Σ (x_k y_{k+1} − x_{k+1} y_k)(x_k + x_{k+1}) / 6.
    let moment = (0..4)
        .map(|k| {
            let (p, q) = (xy[k], xy[(k + 1) % 4]);
            (p.0 * q.1 - q.0 * p.1) * (p.0 + q.0) / 6.0
        })
        .sum::<f64>();
    let eps = [a, d, 0.0, a];
    let mut want = 0.0;
    for r in 0..4 {
        for s in 0..4 {
            want += 0.5 * moment * eps[r] * c[r][s] * eps[s];
        }
    }
    assert!(
        (energy / want - 1.0).abs() <= 1e-12,
        "{energy:e} vs {want:e}"
    );
}

/// The isoparametric quadrilateral (`quad_stiffness`): on a rectangle it is the rectangle
/// element (to rounding); on a distorted quad, rigid motions carry no force and a linear field
/// u = (a x + b y, c x + d y) stores the energy ½·A·εᵀCε exactly (bilinear elements hold
/// linear fields; the area A by the shoelace formula): the patch test of one element.
#[test]
fn isoparametric_quad_passes_its_checks() {
    use penalty_lab::model::elasticity::{element_stiffness, quad_stiffness};
    let m = Material {
        young: 70e3,
        poisson: 0.33,
    };
    let c = m.c_matrix(Geometry::PlaneStrain);
    let rect = quad_stiffness(
        Geometry::PlaneStrain,
        &c,
        [(0.5, 1.0), (2.0, 1.0), (2.0, 1.75), (0.5, 1.75)],
    )
    .unwrap();
    let want = element_stiffness(Geometry::PlaneStrain, &c, (0.5, 2.0), (1.0, 1.75));
    let scale = want.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    for (r, w) in rect.iter().flatten().zip(want.iter().flatten()) {
        assert!((r - w).abs() <= 16.0 * f64::EPSILON * scale, "{r} vs {w}");
    }
    let xy = [(0.0, 0.0), (2.0, 0.3), (2.4, 1.9), (-0.2, 1.4)];
    let ke = quad_stiffness(Geometry::PlaneStrain, &c, xy).unwrap();
    let scale = ke.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
    let apply = |u: &[f64; 8]| -> [f64; 8] {
        let mut f = [0.0; 8];
        for (fi, row) in f.iter_mut().zip(&ke) {
            *fi = row.iter().zip(u).map(|(k, x)| k * x).sum();
        }
        f
    };
    let field = |f: &dyn Fn(f64, f64) -> (f64, f64)| -> [f64; 8] {
        let mut u = [0.0; 8];
        for (k, &(x, y)) in xy.iter().enumerate() {
            (u[2 * k], u[2 * k + 1]) = f(x, y);
        }
        u
    };
    for rigid in [
        field(&|_, _| (1.0, 0.0)),
        field(&|_, _| (0.0, 1.0)),
        field(&|x, y| (-y, x)),
    ] {
        for f in apply(&rigid) {
            assert!(
                f.abs() <= 64.0 * f64::EPSILON * scale,
                "rigid motion force {f:e}"
            );
        }
    }
    let (a, b, cc, d) = (1e-3, -4e-4, 2.5e-4, -7e-4);
    let u = field(&|x, y| (a * x + b * y, cc * x + d * y));
    let energy: f64 = 0.5 * u.iter().zip(apply(&u)).map(|(x, f)| x * f).sum::<f64>();
    let area = 0.5
        * (0..4)
            .map(|k| {
                let (p, q) = (xy[k], xy[(k + 1) % 4]);
                p.0 * q.1 - q.0 * p.1
            })
            .sum::<f64>();
    let eps = [a, d, b + cc];
    let mut want = 0.0;
    for r in 0..3 {
        for s in 0..3 {
            want += 0.5 * area * eps[r] * c[r][s] * eps[s];
        }
    }
    assert!(
        (energy / want - 1.0).abs() <= 1e-12,
        "{energy:e} vs {want:e}"
    );
    axisymmetric_quad_passes_its_checks(&m);
    // A clockwise element is refused.
    let mut cw = xy;
    cw.reverse();
    assert!(quad_stiffness(Geometry::PlaneStrain, &c, cw).is_err());
}
