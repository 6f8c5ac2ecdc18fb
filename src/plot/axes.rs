//! Axis ranges, scales and ticks.

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

use super::*;
use crate::{Error, Result};

// ---------------------------------------------------------------------------------------------
// Data preparation
// ---------------------------------------------------------------------------------------------

/// Whether `v` can be drawn on an axis with scale `s`.
pub(super) fn ok(s: Scale, v: f64) -> bool {
    v.is_finite() && (s == Scale::Linear || v > 0.0)
}

/// Value in the axis' linear (transformed) space.
pub(super) fn tr(s: Scale, v: f64) -> f64 {
    match s {
        Scale::Linear => v,
        Scale::Log10 => v.log10(),
    }
}

/// Figure data after validation: axis ranges in data space and in transformed space.
#[derive(Clone, Copy)]
pub(super) struct Prepared {
    pub(super) x: (f64, f64),
    pub(super) y: (f64, f64),
    pub(super) xt: (f64, f64),
    pub(super) yt: (f64, f64),
}

pub(super) fn prepare(fig: &Figure) -> Result<Prepared> {
    let name = if fig.title.is_empty() {
        "figure".to_string()
    } else {
        format!("figure '{}'", fig.title)
    };
    for s in &fig.series {
        if s.x.len() != s.y.len() {
            return Err(Error::length_mismatch(
                format!("{name}: series '{}': y values (one per x value)", s.label),
                s.y.len(),
                s.x.len(),
            ));
        }
    }
    for b in &fig.bands {
        for (what, v) in [("lo", &b.lo), ("hi", &b.hi)] {
            if v.len() != b.x.len() {
                return Err(Error::length_mismatch(
                    format!(
                        "{name}: band '{}': {what} values (one per x value)",
                        b.label
                    ),
                    v.len(),
                    b.x.len(),
                ));
            }
        }
    }
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let mut xv: Vec<f64> = Vec::new();
    let mut yv: Vec<f64> = Vec::new();
    let mut push = |x: f64, y: f64| {
        if ok(xs, x) && ok(ys, y) {
            xv.push(tr(xs, x));
            yv.push(tr(ys, y));
        }
    };
    for s in &fig.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            push(x, y);
        }
    }
    for b in &fig.bands {
        for ((&x, &lo), &hi) in b.x.iter().zip(&b.lo).zip(&b.hi) {
            if ok(ys, lo) && ok(ys, hi) {
                push(x, lo);
                push(x, hi);
            }
        }
    }
    for m in &fig.markers {
        push(m.x, m.y);
    }
    for &(a, b, _) in &fig.segments {
        if ok(xs, a.0) && ok(ys, a.1) && ok(xs, b.0) && ok(ys, b.1) {
            push(a.0, a.1);
            push(b.0, b.1);
        }
    }
    xv.extend(
        fig.vlines
            .iter()
            .filter(|l| ok(xs, l.0))
            .map(|l| tr(xs, l.0)),
    );
    yv.extend(
        fig.hlines
            .iter()
            .filter(|l| ok(ys, l.0))
            .map(|l| tr(ys, l.0)),
    );

    let no_data = |axis: &str, s: Scale| {
        let extra = if s == Scale::Log10 {
            " (log axis: only finite values > 0 count)"
        } else {
            ""
        };
        Error::none_given(
            format!("{name}: finite data for the {axis} axis (nothing to plot)"),
            extra,
        )
    };
    let xt = axis_range(&xv, xs).ok_or_else(|| no_data("x", xs))?;
    let yt = axis_range(&yv, ys).ok_or_else(|| no_data("y", ys))?;
    let back = |s: Scale, (a, b): (f64, f64)| match s {
        Scale::Linear => (a, b),
        Scale::Log10 => (10f64.powf(a), 10f64.powf(b)),
    };
    let x = back(xs, xt);
    let y = back(ys, yt);
    if !(x.0.is_finite() && x.1.is_finite() && x.0 < x.1 && y.0.is_finite() && y.1.is_finite())
        || y.0 >= y.1
    {
        return Err(Error::Numerical(format!(
            "{name}: data range too wide to plot (x {:e}..{:e}, y {:e}..{:e})",
            x.0, x.1, y.0, y.1
        )));
    }
    Ok(Prepared { x, y, xt, yt })
}

/// Axis range (transformed space) covering `vals` with a 5 % margin.
pub(super) fn axis_range(vals: &[f64], s: Scale) -> Option<(f64, f64)> {
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let span = hi - lo;
    let mag = lo.abs().max(hi.abs());
    let (mut a, mut b) = if span <= 1e-9 * mag || span == 0.0 {
        let pad = match s {
            Scale::Log10 => 0.5,
            Scale::Linear if mag == 0.0 => 1.0,
            Scale::Linear => 0.1 * mag,
        };
        (lo - pad, hi + pad)
    } else {
        (lo - 0.05 * span, hi + 0.05 * span)
    };
    if s == Scale::Log10 {
        // Keep 10^a and 10^b representable.
        a = a.max(-307.0);
        b = b.min(307.0);
    }
    Some((a, b))
}

// ---------------------------------------------------------------------------------------------
// Tick labels
// ---------------------------------------------------------------------------------------------

/// How tick values are printed.
#[derive(Clone, Copy, Debug)]
pub(super) enum TickFmt {
    /// `1e3`, `2e-2`.
    Log,
    /// Shortest decimal (`0.02`, `5`, `200`).
    Plain,
    /// Fixed-point with `decimals`.
    Fixed { decimals: usize, step: f64 },
    /// Scientific with `decimals` in the mantissa.
    Sci { decimals: usize, step: f64 },
}

impl TickFmt {
    pub(super) fn for_linear(ticks: &[f64], span: f64) -> Self {
        let step = if ticks.len() >= 2 {
            (ticks[1] - ticks[0]).abs()
        } else {
            span / 5.0
        };
        let step = if step > 0.0 && step.is_finite() {
            step
        } else {
            1.0
        };
        let maxabs = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        let close = |txt: &str, t: f64| {
            txt.parse::<f64>()
                .map(|p| (p - t).abs() <= 1e-6 * step)
                .unwrap_or(false)
        };
        if maxabs >= 1e5 || (maxabs > 0.0 && maxabs < 1e-3) {
            let decimals = (0..=8)
                .find(|&d| ticks.iter().all(|&t| close(&format!("{t:.d$e}"), t)))
                .unwrap_or(8);
            TickFmt::Sci { decimals, step }
        } else {
            let decimals = (0..=12)
                .find(|&d| ticks.iter().all(|&t| close(&format!("{t:.d$}"), t)))
                .unwrap_or(12);
            TickFmt::Fixed { decimals, step }
        }
    }

    pub(super) fn format(&self, v: f64) -> String {
        match *self {
            TickFmt::Log => format_log_tick(v),
            TickFmt::Plain => {
                let t = format!("{v:.6}");
                let t = t.trim_end_matches('0').trim_end_matches('.');
                t.to_string()
            }
            TickFmt::Fixed { decimals, step } => {
                let v = if v.abs() < 1e-9 * step { 0.0 } else { v };
                format!("{v:.decimals$}")
            }
            TickFmt::Sci { decimals, step } => {
                if v.abs() < 1e-9 * step {
                    "0".to_string()
                } else {
                    format!("{v:.decimals$e}")
                }
            }
        }
    }
}

/// `1000 → "1e3"`, `0.02 → "2e-2"`, `2500 → "2.5e3"`.
pub(super) fn format_log_tick(v: f64) -> String {
    if !(v > 0.0 && v.is_finite()) {
        return format!("{v}");
    }
    let l = v.log10();
    let k = l.round();
    if (l - k).abs() < 1e-9 {
        return format!("1e{}", k as i64);
    }
    let k = l.floor();
    let m = v / 10f64.powf(k);
    let m = (m * 10.0).round() / 10.0;
    if m >= 10.0 {
        return format!("1e{}", k as i64 + 1);
    }
    format!("{m}e{}", k as i64)
}

/// Tick positions of one axis: labelled (bold) values, minor grid values and the formatter.
pub(super) struct AxisTicks {
    pub(super) bold: Vec<f64>,
    pub(super) light: Vec<f64>,
    pub(super) fmt: TickFmt,
}

/// Ticks for an axis over the data range `r`, at most about `n` labels.
pub(super) fn ticks(s: Scale, r: (f64, f64), n: usize) -> AxisTicks {
    match s {
        Scale::Linear => {
            // Plotters' own choice (same hint as the mesh uses), only the format is ours.
            let c: RangedCoordf64 = (r.0..r.1).into();
            let bold = c.key_points(n);
            let fmt = TickFmt::for_linear(&bold, r.1 - r.0);
            AxisTicks {
                bold,
                light: Vec::new(),
                fmt,
            }
        }
        Scale::Log10 => log_ticks(r, n),
    }
}

/// Log-axis ticks: powers of ten when the range holds at least three (every k-th decade if
/// there are too many), otherwise 1-2-5 or 1…9 × 10^k, otherwise plain linear ticks.
pub(super) fn log_ticks((lo, hi): (f64, f64), n: usize) -> AxisTicks {
    let n = n.max(2);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let kmin = (lo.log10() - 1e-9).ceil() as i32;
    let kmax = (hi.log10() + 1e-9).floor() as i32;
    let decade_set = |mantissas: &[f64]| -> Vec<f64> {
        (kmin - 1..=kmax)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(inside)
            .collect()
    };
    let all_minor = || decade_set(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    let decades = (kmax - kmin + 1).max(0) as usize;
    if decades >= 3 {
        let stride = decades.div_ceil(n) as i32;
        let (bold, light): (Vec<i32>, Vec<i32>) =
            (kmin..=kmax).partition(|k| k.rem_euclid(stride) == 0);
        let p = |k: &i32| 10f64.powi(*k);
        let light = if stride == 1 && decades <= 9 {
            all_minor()
        } else {
            light.iter().map(p).collect()
        };
        return AxisTicks {
            bold: bold.iter().map(p).collect(),
            light,
            fmt: TickFmt::Log,
        };
    }
    let plain_or_log = |t: &[f64]| {
        if t.iter().all(|v| (1e-3..1e5).contains(v)) {
            TickFmt::Plain
        } else {
            TickFmt::Log
        }
    };
    for (mantissas, light) in [
        (&[1.0, 2.0, 5.0][..], true),
        (&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0][..], false),
    ] {
        let bold = decade_set(mantissas);
        if bold.len() >= 3 && bold.len() <= n + 2 {
            let fmt = plain_or_log(&bold);
            let light = if light {
                all_minor()
                    .into_iter()
                    .filter(|v| !bold.contains(v))
                    .collect()
            } else {
                Vec::new()
            };
            return AxisTicks { bold, light, fmt };
        }
    }
    // Less than a decade: evenly spaced ticks read best.
    let c: RangedCoordf64 = (lo..hi).into();
    let bold: Vec<f64> = c.key_points(n).into_iter().filter(|v| *v > 0.0).collect();
    let fmt = TickFmt::for_linear(&bold, hi - lo);
    AxisTicks {
        bold,
        light: Vec::new(),
        fmt,
    }
}
