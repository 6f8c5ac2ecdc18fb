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

/// Runs `f` `repeats` times (at least once) and returns the median wall time (s) and the
/// last result; the first error ends it.
pub fn median_time<T, E>(
    repeats: usize,
    mut f: impl FnMut() -> Result<T, E>,
) -> Result<(f64, T), E> {
    let mut times = Vec::with_capacity(repeats.max(1));
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let t0 = std::time::Instant::now();
        last = Some(f()?);
        times.push(t0.elapsed().as_secs_f64());
    }
    let med = median(&times).unwrap_or(f64::NAN);
    Ok((med, last.expect("at least one run")))
}

/// Least-squares slope of ln y against ln x over the points with x, y > 0 (the exponent p of
/// a power law y ∝ xᵖ); `None` with fewer than two such points or no spread in x.
pub fn loglog_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let k = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / k,
        pts.iter().map(|p| p.1).sum::<f64>() / k,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}
