//! Exact power-of-two prescaling for [`super::cond2_warm`]: cond₂ is scale-free, the routes'
//! margins (Lanczos usability tests, certificate margins) are not, so a matrix whose entries
//! sit near the ends of the double range is brought near 1 first and its report scaled back.

use super::CondReport;
use crate::system::Stiffness;

/// Largest entries outside `[PRESCALE_MIN, PRESCALE_MAX]` make [`super::cond2_warm`] rescale.
const PRESCALE_MAX: f64 = 1.2676506002282294e30; // 2¹⁰⁰
/// See [`PRESCALE_MAX`].
const PRESCALE_MIN: f64 = 7.888609052210118e-31; // 2⁻¹⁰⁰

/// `(2ᵏ·A, k)` with k even and `2ᵏ·max|a_ij|` in [1/2, 2), where `max|a_ij|` lies outside
/// [2⁻¹⁰⁰, 2¹⁰⁰] and every nonzero entry stays a normal number (so the product is exact);
/// `None` otherwise (including a zero matrix).
pub fn prescale(a: &Stiffness) -> Option<(Stiffness, i32)> {
    let (mut big, mut small) = (0.0f64, f64::INFINITY);
    a.for_each_entry(|_, _, v| {
        if v != 0.0 {
            big = big.max(v.abs());
            small = small.min(v.abs());
        }
    });
    if !(big.is_finite() && big > 0.0) || (PRESCALE_MIN..=PRESCALE_MAX).contains(&big) {
        return None;
    }
    let k = -2 * (big.log2() / 2.0).round() as i32;
    // Exact only where the smallest entry stays normal and the largest finite.
    let lands = |x: f64, k: i32| {
        let y = x * 2f64.powi(k / 2) * 2f64.powi(k / 2);
        y.is_normal()
    };
    if !(lands(small, k) && lands(big, k)) {
        return None;
    }
    let half = vec![2f64.powi(k / 2); a.n()];
    Some((a.scaled(&half), k))
}

impl CondReport {
    /// The report of 2ᵏ·A as the report of A (n = dim A): cond₂ and its bounds as they are,
    /// σ's, eigenvalue brackets and the asymmetry's absolute sizes times 2⁻ᵏ (bounds rounded
    /// outwards where that leaves the normal range), log10|det| less n·k·log10 2.
    pub(super) fn unscaled(mut self, k: i32, n: usize) -> CondReport {
        let back = |x: f64| x * 2f64.powi(-k / 2) * 2f64.powi(-k / 2);
        let down = |x: f64| {
            let y = back(x);
            if y != 0.0 && !y.is_normal() {
                y.next_down().max(0.0)
            } else {
                y
            }
        };
        let up = |x: f64| {
            let y = back(x);
            if y.is_normal() || y == 0.0 {
                y
            } else {
                y.next_up()
            }
        };
        self.sigma_max = back(self.sigma_max);
        self.sigma_min = back(self.sigma_min);
        if let Some(c) = &mut self.certificate {
            c.lambda_max_lo = down(c.lambda_max_lo);
            c.lambda_max_hi = up(c.lambda_max_hi);
            c.lambda_min_lo = down(c.lambda_min_lo);
            c.lambda_min_hi = up(c.lambda_min_hi);
        }
        if let Some(a) = &mut self.asymmetry {
            a.max_abs = back(a.max_abs);
            a.max_entry = back(a.max_entry);
            a.skew_norm_bound = up(a.skew_norm_bound);
        }
        self.log10_det = self
            .log10_det
            .map(|d| d - n as f64 * k as f64 * std::f64::consts::LOG10_2);
        self
    }
}
