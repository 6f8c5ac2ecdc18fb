//! Knob grids shared by the studies: [`LogGrid`], a log-spaced range given as `LO:HI:N`.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// A log-spaced grid `lo..hi` with `n` points, inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogGrid {
    /// First value (> 0).
    pub lo: f64,
    /// Last value (≥ lo).
    pub hi: f64,
    /// Number of points (≥ 1).
    pub n: usize,
}

impl LogGrid {
    /// Parses `LO:HI:N`.
    pub fn parse(s: &str) -> Result<Self> {
        let parts: Vec<&str> = s.split(':').collect();
        let bad = || {
            Error::input(format!(
                "malformed range '{s}': expected LO:HI:N with 0 < LO ≤ HI and N ≥ 1 (e.g. 1e-2:1e12:15)"
            ))
        };
        if parts.len() != 3 {
            return Err(bad());
        }
        let lo: f64 = parts[0].trim().parse().map_err(|_| bad())?;
        let hi: f64 = parts[1].trim().parse().map_err(|_| bad())?;
        let n: usize = parts[2].trim().parse().map_err(|_| bad())?;
        let g = LogGrid { lo, hi, n };
        g.validate().map_err(|_| bad())?;
        Ok(g)
    }

    /// Checks `0 < lo ≤ hi`, finite, `n ≥ 1` (and `lo = hi` when `n = 1`).
    pub fn validate(&self) -> Result<()> {
        if !(self.lo.is_finite() && self.hi.is_finite() && self.lo > 0.0 && self.lo <= self.hi)
            || self.n == 0
            || (self.n == 1 && self.lo != self.hi)
        {
            return Err(Error::input(format!(
                "bad ε grid {}:{}:{}: need 0 < LO ≤ HI, N ≥ 1",
                self.lo, self.hi, self.n
            )));
        }
        Ok(())
    }

    /// The grid values (inclusive ends, exact end points).
    pub fn values(&self) -> Vec<f64> {
        if self.n == 1 {
            return vec![self.lo];
        }
        let (a, b) = (self.lo.log10(), self.hi.log10());
        (0..self.n)
            .map(|i| {
                if i == 0 {
                    self.lo
                } else if i + 1 == self.n {
                    self.hi
                } else {
                    10f64.powf(a + (b - a) * i as f64 / (self.n - 1) as f64)
                }
            })
            .collect()
    }
}
