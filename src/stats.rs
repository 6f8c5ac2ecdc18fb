//! Summary statistics, defined once for every study and figure: the quantile (type 7 of
//! Hyndman & Fan, the default of R and NumPy) and the median as its q = ½ case (the mean of the
//! two middle values for an even count).

/// The `q`-quantile of `v` (0 ≤ q ≤ 1, clamped) with linear interpolation between order
/// statistics: with `v` sorted ascending and `h = q (n − 1)`, the result is
/// `v[⌊h⌋] + (h − ⌊h⌋)(v[⌊h⌋+1] − v[⌊h⌋])` (type 7 of Hyndman & Fan, the default of R and
/// NumPy). `v` is sorted in place. The input must be NaN-free; an empty slice gives NaN.
pub fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let q = if q.is_nan() { 0.5 } else { q.clamp(0.0, 1.0) };
    let h = q * (v.len() - 1) as f64;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(v.len() - 1);
    let frac = h - lo as f64;
    if frac == 0.0 || v[lo] == v[hi] {
        v[lo]
    } else {
        v[lo] + frac * (v[hi] - v[lo])
    }
}

/// The median of `v` (NaN-free): [`quantile`] at ½, `None` for an empty slice.
pub fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    Some(quantile(&mut v.to_vec(), 0.5))
}
