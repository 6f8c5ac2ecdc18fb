//! The 2-node axisymmetric "linear bending" shell element (velocity form).
//!
//! Nodal unknowns `(v_r, v_z, β)`: velocities and the rotation rate of the normal. On an element
//! of length L with meridian direction `(c, s) = (cos φ, sin φ)` and mid radius `r_m`, the
//! tangential and normal velocities are `u = c v_r + s v_z`, `w = −s v_r + c v_z`, all fields are
//! interpolated linearly and every term is integrated at the single mid-point (reduced
//! integration, which also removes transverse-shear locking):
//!
//! | rate | formula |
//! |---|---|
//! | meridional membrane | `ε̇_s = (u_b − u_a) / L` |
//! | hoop membrane | `ε̇_θ = v̄_r / r_m` |
//! | meridional curvature | `κ̇_s = (β_b − β_a) / L` |
//! | hoop curvature | `κ̇_θ = c β̄ / r_m` |
//! | transverse shear | `γ̇ = (w_b − w_a) / L − β̄` |
//!
//! (bars are mid-point averages). Through the thickness `ε̇(ζ) = ε̇ + ζ κ̇`, `ζ ∈ [−t/2, t/2]`,
//! integrated with Gauss layers, each with its own μ*. Plane stress + incompressibility
//! (`ε̇₃₃ = −(ε̇_s + ε̇_θ)`) give `σ_s = 2μ*(2ε̇_s + ε̇_θ)`, `σ_θ = 2μ*(ε̇_s + 2ε̇_θ)` and
//! `ε̄̇ = (2/√3) sqrt(ε̇_s² + ε̇_s ε̇_θ + ε̇_θ²)`; the shear stress is `τ = μ* γ̇` with the
//! correction factor 5/6. Volumes are full revolutions: `dV = 2π r_m L t`.

/// Geometry of one element on the current meridian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementGeom {
    /// Length L.
    pub l: f64,
    /// cos φ (meridian direction, r component).
    pub c: f64,
    /// sin φ (meridian direction, z component).
    pub s: f64,
    /// Mid-point radius r_m.
    pub r_m: f64,
}

impl ElementGeom {
    /// Geometry of the element from node `a = (r, z)` to node `b`.
    pub fn new(a: [f64; 2], b: [f64; 2]) -> Self {
        let (dr, dz) = (b[0] - a[0], b[1] - a[1]);
        let l = (dr * dr + dz * dz).sqrt();
        ElementGeom {
            l,
            c: dr / l,
            s: dz / l,
            r_m: 0.5 * (a[0] + b[0]),
        }
    }

    /// Mid-surface area of the full revolution `2π r_m L`.
    pub fn area(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.r_m * self.l
    }
}

/// Rows of the strain-rate operator, each acting on `(v_ra, v_za, β_a, v_rb, v_zb, β_b)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BRows {
    /// `[ε̇_s, ε̇_θ]` rows.
    pub membrane: [[f64; 6]; 2],
    /// `[κ̇_s, κ̇_θ]` rows.
    pub bending: [[f64; 6]; 2],
    /// `γ̇` row.
    pub shear: [f64; 6],
}

/// The strain-rate operator of the element (table in the module docs).
pub fn b_rows(g: &ElementGeom) -> BRows {
    let (c, s, l, h) = (g.c, g.s, g.l, 0.5 / g.r_m);
    BRows {
        membrane: [
            [-c / l, -s / l, 0.0, c / l, s / l, 0.0],
            [h, 0.0, 0.0, h, 0.0, 0.0],
        ],
        bending: [
            [0.0, 0.0, -1.0 / l, 0.0, 0.0, 1.0 / l],
            [0.0, 0.0, c * h, 0.0, 0.0, c * h],
        ],
        shear: [s / l, -c / l, -0.5, -s / l, c / l, -0.5],
    }
}

/// Generalized strain rates at the element mid-point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrainRates {
    /// ε̇_s (s⁻¹).
    pub eps_s: f64,
    /// ε̇_θ (s⁻¹).
    pub eps_theta: f64,
    /// κ̇_s (in⁻¹ s⁻¹).
    pub kappa_s: f64,
    /// κ̇_θ (in⁻¹ s⁻¹).
    pub kappa_theta: f64,
    /// γ̇ (s⁻¹).
    pub gamma: f64,
}

impl StrainRates {
    /// Thickness strain rate `ε̇₃₃ = −(ε̇_s + ε̇_θ)` (incompressibility).
    pub fn thickness_rate(&self) -> f64 {
        -(self.eps_s + self.eps_theta)
    }

    /// In-plane rates `(ε̇_s, ε̇_θ)` at distance ζ from the mid-surface.
    pub fn at(&self, zeta: f64) -> (f64, f64) {
        (
            self.eps_s + zeta * self.kappa_s,
            self.eps_theta + zeta * self.kappa_theta,
        )
    }
}

fn dot6(a: &[f64; 6], v: &[f64; 6]) -> f64 {
    a.iter().zip(v).map(|(x, y)| x * y).sum()
}

/// Strain rates of the element for nodal values `v = (v_ra, v_za, β_a, v_rb, v_zb, β_b)`.
pub fn strain_rates(g: &ElementGeom, v: &[f64; 6]) -> StrainRates {
    let b = b_rows(g);
    StrainRates {
        eps_s: dot6(&b.membrane[0], v),
        eps_theta: dot6(&b.membrane[1], v),
        kappa_s: dot6(&b.bending[0], v),
        kappa_theta: dot6(&b.bending[1], v),
        gamma: dot6(&b.shear, v),
    }
}

/// Equivalent strain rate for plane stress + incompressibility:
/// `ε̄̇ = sqrt(2/3 ε̇:ε̇) = (2/√3) sqrt(ε̇_s² + ε̇_s ε̇_θ + ε̇_θ²)`.
pub fn effective_rate(eps_s: f64, eps_theta: f64) -> f64 {
    2.0 / 3f64.sqrt() * (eps_s * eps_s + eps_s * eps_theta + eps_theta * eps_theta).sqrt()
}

/// Gauss–Legendre points ξ and weights w on [−1, 1] for 1–5 layers.
pub fn gauss_layers(n: usize) -> (Vec<f64>, Vec<f64>) {
    match n {
        1 => (vec![0.0], vec![2.0]),
        2 => {
            let a = 1.0 / 3f64.sqrt();
            (vec![-a, a], vec![1.0, 1.0])
        }
        3 => {
            let a = (0.6f64).sqrt();
            (vec![-a, 0.0, a], vec![5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0])
        }
        4 => {
            let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let wa = (18.0 + 30f64.sqrt()) / 36.0;
            let wb = (18.0 - 30f64.sqrt()) / 36.0;
            (vec![-b, -a, a, b], vec![wb, wa, wa, wb])
        }
        _ => {
            let a = (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
            let b = (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
            let wa = (322.0 + 13.0 * 70f64.sqrt()) / 900.0;
            let wb = (322.0 - 13.0 * 70f64.sqrt()) / 900.0;
            (vec![-b, -a, 0.0, a, b], vec![wb, wa, 128.0 / 225.0, wa, wb])
        }
    }
}

/// Shear correction factor.
pub const SHEAR_FACTOR: f64 = 5.0 / 6.0;

/// Element "viscosity" matrix `k_e` (6×6, ton-force·s/in):
///
/// `k_e = 2π r_m L [ Σ_l (w_l/2) t 2μ*_l B(ζ_l)ᵀ P B(ζ_l) + (5/6) t μ̄* b_γᵀ b_γ ]`,
/// `P = [[2, 1], [1, 2]]`, `B(ζ) = B_m + ζ B_b`, `ζ_l = ξ_l t/2`, μ̄* the layer average.
/// So that `vᵀ k_e v = ∫ σ̄ ε̄̇ dV` (+ shear), the internal power.
pub fn element_matrix(
    g: &ElementGeom,
    t: f64,
    mu_layers: &[f64],
    xi: &[f64],
    w: &[f64],
) -> [[f64; 6]; 6] {
    let b = b_rows(g);
    let vol = g.area();
    let mut k = [[0.0; 6]; 6];
    let mut mu_avg = 0.0;
    for ((&mu, &x), &wl) in mu_layers.iter().zip(xi).zip(w) {
        let zeta = 0.5 * x * t;
        let mut bz = [[0.0; 6]; 2];
        for r in 0..2 {
            for j in 0..6 {
                bz[r][j] = b.membrane[r][j] + zeta * b.bending[r][j];
            }
        }
        let f = vol * 0.5 * wl * t * 2.0 * mu;
        for i in 0..6 {
            // (P B)_i columns: P = [[2,1],[1,2]]
            let p0 = 2.0 * bz[0][i] + bz[1][i];
            let p1 = bz[0][i] + 2.0 * bz[1][i];
            for j in 0..6 {
                k[i][j] += f * (p0 * bz[0][j] + p1 * bz[1][j]);
            }
        }
        mu_avg += 0.5 * wl * mu;
    }
    let fs = vol * SHEAR_FACTOR * t * mu_avg;
    for i in 0..6 {
        for j in 0..6 {
            k[i][j] += fs * b.shear[i] * b.shear[j];
        }
    }
    k
}
