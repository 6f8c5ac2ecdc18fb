//! Knob grids shared by the studies: [`LogGrid`], a log-spaced range given as `LO:HI:N`, and
//! [`KnobGrid`], the levels of every knob on one scene with the one expansion of a strategy's
//! [`Knob`] into the methods a study runs ([`KnobGrid::points`]); [`parse_ratio`], a mesh
//! ratio given as `A:B`.

use crate::error::{Error, Result};
use crate::strategy::{Knob, Knobs, Method, Strategy};
use serde::{Deserialize, Serialize};

/// `A:B` → (A, B), whole numbers (a mesh ratio flag; the study checks the range).
pub fn parse_ratio(s: &str) -> std::result::Result<(usize, usize), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("'{s}' is not A:B"))?;
    let n = |t: &str| {
        t.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{t}' is not a whole number"))
    };
    Ok((n(a)?, n(b)?))
}

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
    /// Most points of a grid (every point is a solve per scene: a larger N is a typo).
    pub const MAX_N: usize = 10_000;

    /// Parses `LO:HI:N`.
    pub fn parse(s: &str) -> Result<Self> {
        let parts: Vec<&str> = s.split(':').collect();
        let bad = || {
            Error::out_of_range(
                "ε range",
                format!("'{s}'"),
                "LO:HI:N with 0 < LO ≤ HI and 1 ≤ N ≤ 10000 (e.g. 1e-2:1e12:15)",
            )
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

    /// Checks `0 < lo ≤ hi`, finite, `1 ≤ n ≤` [`LogGrid::MAX_N`] (and `lo = hi` when
    /// `n = 1`).
    pub fn validate(&self) -> Result<()> {
        if !(self.lo.is_finite() && self.hi.is_finite() && self.lo > 0.0 && self.lo <= self.hi)
            || self.n == 0
            || self.n > Self::MAX_N
            || (self.n == 1 && self.lo != self.hi)
        {
            return Err(Error::out_of_range(
                "ε grid",
                format!("{}:{}:{}", self.lo, self.hi, self.n),
                "LO:HI:N with 0 < LO ≤ HI, 1 ≤ N ≤ 10000",
            ));
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

/// One value of a knob grid: the absolute value a method runs at and, where it was given
/// relative to a scale of the scene, that relative value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Level {
    /// The knob's value (units of the knob: ε force/length, f none, δ and tolerances units
    /// of u).
    pub value: f64,
    /// The relative value it came from (`None`: given absolute).
    pub rel: Option<f64>,
}

impl Level {
    /// A value given absolute.
    pub fn absolute(value: f64) -> Level {
        Level { value, rel: None }
    }

    /// The relative value `rel` times `scale`.
    pub fn relative(rel: f64, scale: f64) -> Level {
        Level {
            value: rel * scale,
            rel: Some(rel),
        }
    }

    /// [`Level::relative`] of each of `rels`.
    pub fn relatives(rels: &[f64], scale: f64) -> Vec<Level> {
        rels.iter().map(|&r| Level::relative(r, scale)).collect()
    }
}

/// How an ε-and-tolerance rule (`augmented`) runs at each tolerance of the grid: its ε, whether
/// its penalty update is adaptive, and the knob's name in the rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Augmented {
    /// ε.
    pub eps: f64,
    /// The adaptive per-constraint update.
    pub adaptive: bool,
    /// The knob's name in the rows (`tol`, `adaptive-tol`).
    pub name: &'static str,
}

/// One point of a grid: a method built with its knob, the knob's name (`eps`, `factor`,
/// `delta`, an [`Augmented::name`], `""` for an exact method) and its level.
#[derive(Clone, Copy, Debug)]
pub struct Point {
    /// The method.
    pub method: Method,
    /// The knob's name.
    pub knob: &'static str,
    /// Its level.
    pub level: Level,
}

/// The levels a study runs each knob at on one scene, absolute (with the relative values they
/// came from): the one place a [`Knob`] becomes the jobs of a scene ([`KnobGrid::points`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KnobGrid {
    /// ε ([`Knob::Eps`]).
    pub eps: Vec<Level>,
    /// Factors f ([`Knob::Factor`]).
    pub factors: Vec<Level>,
    /// δ ([`Knob::Delta`]).
    pub deltas: Vec<Level>,
    /// Tolerances ([`Knob::EpsTol`], run at every [`Augmented`] variant).
    pub tols: Vec<Level>,
    /// The variants of the ε-and-tolerance rules, in order.
    pub augmented: Vec<Augmented>,
    /// The exact methods ([`Knob::None`]) run once at this level; `None`: not at all.
    pub exact: Option<Level>,
}

impl KnobGrid {
    /// The levels of `knob`.
    pub fn levels(&self, knob: Knob) -> &[Level] {
        match knob {
            Knob::Eps => &self.eps,
            Knob::Factor => &self.factors,
            Knob::Delta => &self.deltas,
            Knob::EpsTol => &self.tols,
            Knob::None => self.exact.as_slice(),
        }
    }

    /// The number of points of `strategies` before any refusal: what [`KnobGrid::points`]
    /// gives where every level is valid (a study's row count per scene).
    pub fn count(&self, strategies: &[&'static Strategy]) -> usize {
        strategies
            .iter()
            .map(|s| match s.knob {
                Knob::EpsTol => self.augmented.len() * self.tols.len(),
                knob => self.levels(knob).len(),
            })
            .sum()
    }

    /// Every strategy of `strategies` in order at every level of its knob (the tolerances at
    /// every [`Augmented`] variant, variants outermost); a level the strategy refuses
    /// ([`Method::new`]) drops the point.
    pub fn points(&self, strategies: &[&'static Strategy]) -> Vec<Point> {
        let mut out = Vec::new();
        for &s in strategies {
            let mut push = |knobs: Knobs, knob: &'static str, level: Level| {
                if let Ok(method) = Method::new(s, knobs) {
                    out.push(Point {
                        method,
                        knob,
                        level,
                    });
                }
            };
            match s.knob {
                Knob::EpsTol => {
                    for a in &self.augmented {
                        for &level in &self.tols {
                            let knobs = Knobs {
                                eps: Some(a.eps),
                                tol: Some(level.value),
                                adaptive: a.adaptive,
                                ..Knobs::NONE
                            };
                            push(knobs, a.name, level);
                        }
                    }
                }
                knob => {
                    let name = match knob {
                        Knob::Eps => "eps",
                        Knob::Factor => "factor",
                        Knob::Delta => "delta",
                        _ => "",
                    };
                    for &level in self.levels(knob) {
                        push(Knobs::single(knob, level.value), name, level);
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strategy::{augmented, constant, lagrange, paper, scaled};

    /// The expansion's order (strategies, then variants, then levels), its names and levels,
    /// the exact methods once, and a refused level dropped.
    #[test]
    fn points_expand_each_knob_in_order() {
        let grid = KnobGrid {
            eps: vec![Level::absolute(1.0), Level::absolute(-1.0)],
            factors: vec![Level::absolute(2.0)],
            deltas: vec![Level::relative(0.1, 3.0)],
            tols: vec![Level::relative(0.5, 2.0), Level::relative(0.25, 2.0)],
            augmented: vec![
                Augmented {
                    eps: 7.0,
                    adaptive: false,
                    name: "tol",
                },
                Augmented {
                    eps: 0.07,
                    adaptive: true,
                    name: "adaptive-tol",
                },
            ],
            exact: Some(Level::absolute(0.0)),
        };
        let strategies = [
            &constant::STRATEGY,
            &lagrange::STRATEGY,
            &augmented::STRATEGY,
            &scaled::STRATEGY,
            &paper::STRATEGY,
        ];
        let p = grid.points(&strategies);
        let seen: Vec<(&str, &str, f64)> = p
            .iter()
            .map(|p| (p.method.name(), p.knob, p.level.value))
            .collect();
        assert_eq!(
            seen,
            vec![
                ("constant", "eps", 1.0), // ε = −1 refused
                ("lagrange", "", 0.0),
                ("augmented", "tol", 1.0),
                ("augmented", "tol", 0.5),
                ("augmented", "adaptive-tol", 1.0),
                ("augmented", "adaptive-tol", 0.5),
                ("scaled", "factor", 2.0),
                ("paper", "delta", 0.1 * 3.0),
            ]
        );
        let k = p[4].method.knobs();
        assert_eq!((k.eps, k.tol, k.adaptive), (Some(0.07), Some(1.0), true));
        assert_eq!(p[7].level.rel, Some(0.1));
        assert_eq!(grid.count(&strategies), p.len() + 1); // + the refused ε
        assert!(KnobGrid::default().points(&strategies).is_empty());
    }
}
