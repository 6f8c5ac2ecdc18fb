//! Element-level checks of the axisymmetric linear bending shell element
//! (`penalty_lab::forming::element`): rigid motion, uniform biaxial stretch, internal power.

use penalty_lab::forming::element::{
    effective_rate, element_matrix, gauss_layers, strain_rates, ElementGeom,
};
use penalty_lab::forming::Material;

/// A few elements in different positions and orientations on the meridian.
fn elements() -> Vec<([f64; 2], [f64; 2])> {
    vec![
        ([0.0, 0.0], [0.05, 0.0]),
        ([1.0, 0.2], [1.04, 0.17]),
        ([0.7, -0.3], [0.72, -0.35]),
        ([2.0, 1.0], [2.0, 1.1]),   // vertical wall
        ([1.5, 0.0], [1.45, 0.03]), // pointing inward
    ]
}

#[test]
fn rigid_translation_along_the_axis_gives_zero_strain_rates_and_zero_force() {
    let (xi, w) = gauss_layers(5);
    for (a, b) in elements() {
        let g = ElementGeom::new(a, b);
        for c in [1.0, -3.5] {
            let v = [0.0, c, 0.0, 0.0, c, 0.0];
            let sr = strain_rates(&g, &v);
            let scale = c.abs() / g.l;
            for x in [sr.eps_s, sr.eps_theta, sr.kappa_s, sr.kappa_theta, sr.gamma] {
                assert!(x.abs() <= 1e-12 * scale, "{a:?}-{b:?}: rate {x}");
            }
            // K v = 0 for the rigid mode.
            let k = element_matrix(&g, 0.035, &[7.0; 5], &xi, &w);
            let kmax = k.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            for row in &k {
                let f: f64 = row.iter().zip(&v).map(|(p, q)| p * q).sum();
                assert!(f.abs() <= 1e-12 * kmax * c.abs(), "force {f}");
            }
        }
    }
}

#[test]
fn a_radial_stretch_on_a_non_flat_element_is_not_rigid() {
    // Sanity for the previous test: the check can fail.
    let g = ElementGeom::new([1.0, 0.2], [1.04, 0.17]);
    let sr = strain_rates(&g, &[0.1, 0.0, 0.0, 0.1, 0.0, 0.0]);
    assert!(sr.eps_theta.abs() > 1e-3);
}

#[test]
fn uniform_biaxial_stretch_gives_the_analytic_rates_and_thickness_rate() {
    for &(r0, r1) in &[(0.0, 0.04), (0.5, 0.55), (1.9, 2.0)] {
        for &rate in &[1.0, 0.37, -2.0] {
            let g = ElementGeom::new([r0, 0.0], [r1, 0.0]);
            // v_r = ε̇ r, v_z = 0, β = 0.
            let v = [rate * r0, 0.0, 0.0, rate * r1, 0.0, 0.0];
            let sr = strain_rates(&g, &v);
            let tol = 1e-12 * rate.abs();
            assert!((sr.eps_s - rate).abs() <= tol, "ε̇_s = {}", sr.eps_s);
            assert!((sr.eps_theta - rate).abs() <= tol, "ε̇_θ = {}", sr.eps_theta);
            assert!((sr.thickness_rate() + 2.0 * rate).abs() <= tol);
            assert!(sr.kappa_s.abs() <= tol && sr.kappa_theta.abs() <= tol);
            assert!(sr.gamma.abs() <= tol);
            // Equal biaxial: ε̄̇ = (2/√3)·sqrt(3 ε̇²) = 2|ε̇|.
            let e = effective_rate(sr.eps_s, sr.eps_theta);
            assert!((e - 2.0 * rate.abs()).abs() <= tol);
        }
    }
}

#[test]
fn internal_power_equals_equivalent_stress_times_rate_times_volume() {
    // vᵀ k v = ∫ σ̄ ε̄̇ dV = 3 μ* ε̄̇² V for a uniform μ* and pure membrane stretching.
    let m = Material::default();
    let (xi, w) = gauss_layers(5);
    let t = 0.035;
    let g = ElementGeom::new([0.8, 0.1], [0.85, 0.08]);
    let v = [0.3, -0.1, 0.0, 0.36, -0.12, 0.0];
    let sr = strain_rates(&g, &v);
    let ebar = effective_rate(sr.eps_s, sr.eps_theta);
    let mu = m.mu_star(0.1, ebar);
    // Remove the shear part of v's power by checking it separately.
    let k = element_matrix(&g, t, &[mu; 5], &xi, &w);
    let p: f64 = (0..6)
        .map(|i| (0..6).map(|j| v[i] * k[i][j] * v[j]).sum::<f64>())
        .sum();
    let vol = g.area() * t;
    let shear = vol * (5.0 / 6.0) * mu * sr.gamma * sr.gamma;
    let expect = 3.0 * mu * ebar * ebar * vol + shear;
    assert!((p - expect).abs() <= 1e-10 * expect, "{p} vs {expect}");
    // σ̄ = 3 μ* ε̄̇ is the yield stress of Eq. 38 (rigid-plastic, rate above the cut-off).
    assert!((3.0 * mu * ebar - m.hardening.sigma_y(0.1)).abs() < 1e-12 * 30.0);
}
