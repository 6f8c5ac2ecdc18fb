//! Double-double arithmetic (Dekker 1971; Hida, Li & Bailey's QD library) and a dense
//! double-double LU with partial pivoting: the extended-precision reference of the stress study.
//!
//! Why hand-written: faer ships a double-double type (`faer::fx128`, the `qd` crate), but
//! faer 0.24.4's LU on it panics inside its SIMD matrix product on the stress study's 28- and
//! 40-unknown systems. Its arithmetic serves as the independent check instead:
//! `tests/dd_vs_faer_fx128.rs` solves the same exactly formed systems in `fx128` and agrees
//! with this module to f64 rounding where a plain f64 solve misses by orders of magnitude.

use crate::error::{Error, Result};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number `hi + lo` with `|lo| ≤ ulp(hi)/2` (Dekker 1971; Hida, Li & Bailey's
/// QD library): about 106 significant bits, the exponent range of f64.
///
/// Error-free transformations: `two_sum(a, b) = (s, e)` with `s + e = a + b` exactly (Knuth),
/// `two_prod(a, b) = (p, e)` with `p + e = a·b` exactly (one fused multiply-add).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    /// Leading part (the f64 nearest to the value).
    pub hi: f64,
    /// Trailing part.
    pub lo: f64,
}

/// `(s, e)` with `s = fl(a + b)` and `s + e = a + b` exactly.
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// `(p, e)` with `p = fl(a·b)` and `p + e = a·b` exactly (barring underflow).
#[inline]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

#[inline]
fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd {
        hi: s,
        lo: b - (s - a),
    }
}

impl Dd {
    /// Zero.
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    /// The exact value of an f64.
    pub fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    /// Nearest f64.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// `|x|`.
    pub fn abs(self) -> Dd {
        if self.hi < 0.0 || (self.hi == 0.0 && self.lo < 0.0) {
            -self
        } else {
            self
        }
    }

    /// `true` if both parts are finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// `a·b` for two f64, exactly.
    pub fn prod(a: f64, b: f64) -> Dd {
        let (p, e) = two_prod(a, b);
        Dd { hi: p, lo: e }
    }

    /// `a + b` for two f64, exactly.
    pub fn sum(a: f64, b: f64) -> Dd {
        let (s, e) = two_sum(a, b);
        Dd { hi: s, lo: e }
    }
}

impl From<f64> for Dd {
    fn from(x: f64) -> Dd {
        Dd::from_f64(x)
    }
}

impl Neg for Dd {
    type Output = Dd;
    fn neg(self) -> Dd {
        Dd {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Add for Dd {
    type Output = Dd;
    /// IEEE-style (accurate) double-double addition.
    fn add(self, b: Dd) -> Dd {
        let (s1, s2) = two_sum(self.hi, b.hi);
        let (t1, t2) = two_sum(self.lo, b.lo);
        let s2 = s2 + t1;
        let r = quick_two_sum(s1, s2);
        let s2 = t2 + r.lo;
        quick_two_sum(r.hi, s2)
    }
}

impl Sub for Dd {
    type Output = Dd;
    fn sub(self, b: Dd) -> Dd {
        self + (-b)
    }
}

impl Mul for Dd {
    type Output = Dd;
    fn mul(self, b: Dd) -> Dd {
        let (p1, p2) = two_prod(self.hi, b.hi);
        let p2 = p2 + (self.hi * b.lo + self.lo * b.hi);
        quick_two_sum(p1, p2)
    }
}

impl Div for Dd {
    type Output = Dd;
    /// Long division: three f64 quotient digits.
    fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self - b * Dd::from_f64(q1);
        let q2 = r.hi / b.hi;
        let r = r - b * Dd::from_f64(q2);
        let q3 = r.hi / b.hi;
        let q = quick_two_sum(q1, q2);
        q + Dd::from_f64(q3)
    }
}

/// Dense LU with partial pivoting in double-double (row-major, in place).
pub(crate) struct DdLu {
    a: Vec<Dd>,
    perm: Vec<usize>,
    n: usize,
}

impl DdLu {
    pub(crate) fn factor(mut a: Vec<Dd>, n: usize) -> Result<Self> {
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let (piv, pmax) = (k..n)
                .map(|i| (i, a[i * n + k].abs().hi))
                .fold((k, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
            if pmax <= 0.0 || !pmax.is_finite() {
                return Err(Error::singular(format!(
                    "extended-precision reference: zero pivot in column {k} (matrix exactly singular)"
                )));
            }
            if piv != k {
                for j in 0..n {
                    a.swap(k * n + j, piv * n + j);
                }
                perm.swap(k, piv);
            }
            let akk = a[k * n + k];
            for i in k + 1..n {
                if a[i * n + k].hi == 0.0 {
                    continue;
                }
                let l = a[i * n + k] / akk;
                a[i * n + k] = l;
                for j in k + 1..n {
                    let akj = a[k * n + j];
                    if akj.hi != 0.0 {
                        a[i * n + j] = a[i * n + j] - l * akj;
                    }
                }
            }
        }
        Ok(DdLu { a, perm, n })
    }

    pub(crate) fn solve(&self, b: &[Dd]) -> Vec<Dd> {
        let n = self.n;
        let mut y: Vec<Dd> = self.perm.iter().map(|&p| b[p]).collect();
        for i in 0..n {
            let row = &self.a[i * n..i * n + i];
            let mut s = y[i];
            for (l, yj) in row.iter().zip(&y[..i]) {
                if l.hi != 0.0 {
                    s = s - *l * *yj;
                }
            }
            y[i] = s;
        }
        for i in (0..n).rev() {
            let row = &self.a[i * n + i + 1..(i + 1) * n];
            let mut s = y[i];
            for (u, yj) in row.iter().zip(&y[i + 1..]) {
                if u.hi != 0.0 {
                    s = s - *u * *yj;
                }
            }
            y[i] = s / self.a[i * n + i];
        }
        y
    }
}
