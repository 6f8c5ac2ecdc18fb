//! Double-double arithmetic (Dekker 1971; Hida, Li & Bailey's QD library): about 106
//! significant bits from pairs of f64, for the extended-precision reference of the stress
//! study (`stability`) and the rigorous quadratic forms of the cond₂ certificates
//! (`conditioning::certify`).
//!
//! Why hand-written: faer ships a double-double type (`faer::fx128`, the `qd` crate), but
//! faer 0.24.4's LU on it panics inside its SIMD matrix product on the stress study's 28- and
//! 40-unknown systems. Its arithmetic serves as the independent check instead:
//! `tests/verification/dd_vs_faer_fx128.rs` solves the same exactly formed systems in `fx128` and agrees
//! with `study::stress::dd` to f64 rounding where a plain f64 solve misses by orders of magnitude.
//!
//! Error bounds (Joldes, Muller & Popescu, "Tight and rigorous error bounds for basic building
//! blocks of double-word arithmetic", ACM TOMS 44, 2017; u = ε_mach/2): the accurate sum of two
//! double-doubles has relative error ≤ 3u²/(1 − 4u), a double-double times an f64 ≤ 2u².

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

/// Defines `fn $name(args) -> R` that calls the `#[inline(always)]` kernel `$kernel(args)`
/// compiled with the `fma` target feature where the CPU has it (detected at run time), else
/// as built. Without the feature at compile time each [`two_prod`] is a call into
/// compiler-builtins' `fma` (no vectorization); the FMA build gets the hardware instruction.
/// Both builds compute the same bits: two_prod's error term is exact either way.
macro_rules! fma_dispatch {
    ($(#[$doc:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty => $kernel:path) => {
        $(#[$doc])*
        $vis fn $name($($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "fma")]
                fn fma_build($($arg: $ty),*) -> $ret {
                    $kernel($($arg),*)
                }
                if std::arch::is_x86_feature_detected!("fma") {
                    // SAFETY: the CPU supports FMA (checked just above).
                    return unsafe { fma_build($($arg),*) };
                }
            }
            $kernel($($arg),*)
        }
    };
}
pub(crate) use fma_dispatch;

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
    #[inline]
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
    #[inline]
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
