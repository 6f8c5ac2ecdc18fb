//! Dense LU with partial pivoting in double-double ([`crate::dd`]): the extended-precision
//! reference of the stress study.

use crate::dd::Dd;
use crate::error::{Error, Result};

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
