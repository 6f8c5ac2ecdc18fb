//! Rigid-viscoplastic material of the flow approach (paper Eq. 3–4, 38).
//!
//! `s = 2μ* ε̇`, `μ* = σ̄ / (3 ε̄̇)`, `σ̄ = σ_y(ε̄) + (ε̄̇/γ)^(1/n)` (Eq. 4), with the equivalent
//! strain rate `ε̄̇ = sqrt(2/3 ε̇:ε̇)` and the equivalent strain `ε̄ = ∫ ε̄̇ dt`.
//!
//! **Cut-off strain rate.** In near-rigid zones `ε̄̇ → 0` and μ* → ∞. We evaluate μ* at
//! `max(ε̄̇, ε̄̇₀)` with a documented cut-off ε̄̇₀ ([`Material::rate_cutoff`], s⁻¹). The ratio
//! between the μ* of rigid and of deforming zones (≈ characteristic rate / ε̄̇₀) is itself a source
//! of ill-conditioning of K, independent of the contact penalty; the solver records it.
//!
//! Stresses are in ton-force/in², rates in s⁻¹, μ* in ton-force·s/in².

use serde::{Deserialize, Serialize};

/// Hardening law σ_y(ε̄) (ton-force/in²).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum Hardening {
    /// Eq. 38 as printed: `5.4 + 27.8 ε̄^0.504` for ε̄ ≤ 0.36, `5.4 + 24.4 ε̄^0.504` above —
    /// note the 9 % drop at ε̄ = 0.36 (22.01 → 19.98 ton/in²).
    Eq38Printed,
    /// Continuous variant of Eq. 38: `5.4 + 27.8 ε̄^0.504` for ε̄ ≤ 0.36 and
    /// `5.4 + 24.4 ε̄^0.504 + (27.8 − 24.4)·0.36^0.504` above (the printed upper branch shifted
    /// up to meet the lower one; same slope as printed).
    Eq38Continuous,
    /// `σ_y = sigma0 + k ε̄^n`.
    Power {
        /// Initial yield stress.
        sigma0: f64,
        /// Hardening modulus.
        k: f64,
        /// Exponent.
        n: f64,
    },
}

impl Hardening {
    /// σ_y(ε̄) in ton-force/in² (ε̄ < 0 is treated as 0).
    pub fn sigma_y(&self, eps_bar: f64) -> f64 {
        let e = eps_bar.max(0.0);
        match *self {
            Hardening::Eq38Printed => {
                if e <= 0.36 {
                    5.4 + 27.8 * e.powf(0.504)
                } else {
                    5.4 + 24.4 * e.powf(0.504)
                }
            }
            Hardening::Eq38Continuous => {
                if e <= 0.36 {
                    5.4 + 27.8 * e.powf(0.504)
                } else {
                    5.4 + 24.4 * e.powf(0.504) + (27.8 - 24.4) * 0.36f64.powf(0.504)
                }
            }
            Hardening::Power { sigma0, k, n } => sigma0 + k * e.powf(n),
        }
    }
}

/// The rigid-viscoplastic material of Eq. 4.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// σ_y(ε̄).
    pub hardening: Hardening,
    /// Viscosity parameter γ (s⁻¹) of Eq. 4; `None` = rigid-plastic (γ → ∞).
    pub gamma: Option<f64>,
    /// Rate-sensitivity exponent n of Eq. 4 (used only with `gamma`).
    pub n: f64,
    /// Cut-off strain rate ε̄̇₀ (s⁻¹): μ* is evaluated at `max(ε̄̇, ε̄̇₀)`.
    pub rate_cutoff: f64,
}

impl Default for Material {
    /// Eq. 38 as printed, rigid-plastic, ε̄̇₀ = 1e-3 s⁻¹ (10⁻³ of the characteristic rate
    /// v_punch / 1 in at the default punch speed 1 in/s).
    fn default() -> Self {
        Material {
            hardening: Hardening::Eq38Printed,
            gamma: None,
            n: 1.0,
            rate_cutoff: 1e-3,
        }
    }
}

impl Material {
    /// Equivalent stress σ̄ = σ_y(ε̄) + (ε̄̇/γ)^(1/n) (Eq. 4).
    pub fn sigma_bar(&self, eps_bar: f64, rate: f64) -> f64 {
        let visc = match self.gamma {
            Some(g) => (rate.max(0.0) / g).powf(1.0 / self.n),
            None => 0.0,
        };
        self.hardening.sigma_y(eps_bar) + visc
    }

    /// μ* = σ̄ / (3 ε̄̇) at the cut-off rate `max(ε̄̇, ε̄̇₀)` (Eq. 4).
    pub fn mu_star(&self, eps_bar: f64, rate: f64) -> f64 {
        let r = rate.max(self.rate_cutoff);
        self.sigma_bar(eps_bar, r) / (3.0 * r)
    }

    /// Checks the parameters (positive cut-off, γ and n).
    pub fn validate(&self) -> crate::Result<()> {
        crate::Error::positive("material.rate_cutoff", self.rate_cutoff)?;
        if let Some(g) = self.gamma {
            crate::Error::positive("material.gamma", g)?;
            crate::Error::positive("material.n (with material.gamma)", self.n)?;
        }
        if let Hardening::Power { sigma0, k, n } = self.hardening {
            crate::Error::positive("material.hardening.sigma0 (power law)", sigma0)?;
            if !(k.is_finite() && k >= 0.0) {
                return Err(crate::Error::out_of_range(
                    "material.hardening.k (power law)",
                    k,
                    "a finite number ≥ 0",
                ));
            }
            if n.is_nan() || n < 0.0 {
                return Err(crate::Error::out_of_range(
                    "material.hardening.n (power law)",
                    n,
                    "≥ 0",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq38_printed_drops_and_continuous_does_not() {
        let below = Hardening::Eq38Printed.sigma_y(0.36);
        let above = Hardening::Eq38Printed.sigma_y(0.36 + 1e-12);
        assert!((below - 22.01).abs() < 0.01 && (above - 19.98).abs() < 0.01);
        let c0 = Hardening::Eq38Continuous.sigma_y(0.36);
        let c1 = Hardening::Eq38Continuous.sigma_y(0.36 + 1e-12);
        assert!((c0 - c1).abs() < 1e-9);
    }
}
