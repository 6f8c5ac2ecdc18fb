//! One shared figure style for all experiments: every figure is described as plain data
//! ([`Figure`]) and rendered to both PNG and SVG by [`render`] (or several side by side by
//! [`render_panels`]).
//!
//! Style: embedded DejaVu Sans (no system fonts needed), Okabe–Ito colour-blind-friendly
//! palette ([`PALETTE`]), 2 px lines, light grid, boxed plot area, legend in a white box placed
//! in the corner where it covers the fewest data. The y-axis label is written horizontally
//! above the y axis (rotated text is not rotated in PNG output with the `ab_glyph` font
//! backend). Log axes use plotters' log coordinates with tick labels such as `1e3` / `1e-2`.
//!
//! Non-finite values are skipped (lines are broken there); on a log axis non-positive values are
//! skipped too. A figure without a single drawable point is an [`Error::Input`].
//!
//! ```no_run
//! use penalty_lab::plot::{render, Figure, Mark, Scale, Series};
//! let x: Vec<f64> = (1..=6).map(|k| 10f64.powi(k)).collect();
//! let y: Vec<f64> = x.iter().map(|v| v * v).collect();
//! let fig = Figure::new("Condition number", "penalty ε", "κ(K)")
//!     .scales(Scale::Log10, Scale::Log10)
//!     .with_series(Series::new("κ", x, y, Mark::LinePoints))
//!     .hline(1e8, "limit");
//! render(&fig, std::path::Path::new("figures/cond")).unwrap();
//! ```

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

use crate::{Error, Result};

/// The embedded font (DejaVu Sans, see `assets/DejaVuSans-LICENSE.txt`).
static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
/// Family name under which the embedded font is registered.
const FONT: &str = "sans-serif";

/// Okabe–Ito colour-blind-friendly palette, in the order used for `color: Some(i)` (taken
/// modulo 8) and for default colours (series order): blue, vermillion, bluish green, orange,
/// reddish purple, sky blue, black, yellow.
pub const PALETTE: [(u8, u8, u8); 8] = [
    (0, 114, 178),
    (213, 94, 0),
    (0, 158, 115),
    (230, 159, 0),
    (204, 121, 167),
    (86, 180, 233),
    (0, 0, 0),
    (240, 228, 66),
];

/// Palette index of black (default colour of [`Marker`]s).
pub const BLACK_INDEX: usize = 6;

/// Colour of palette entry `i` (modulo the palette length).
fn pal(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// Grey used for reference lines (`hlines`, `vlines`) and their labels.
const REF_GREY: RGBColor = RGBColor(70, 70, 70);

/// Registers the embedded font once; later calls return the stored outcome.
fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "embedded font assets/DejaVuSans.ttf is not a valid font".to_string())
        })
        .clone()
        .map_err(Error::Numerical)
}

/// Axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Base-10 logarithmic axis; non-positive values are skipped.
    Log10,
}

/// How a [`Series`] is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mark {
    /// Solid line through the points (broken at skipped points).
    #[default]
    Line,
    /// Filled circles only.
    Points,
    /// Solid line with filled circles at the data points.
    LinePoints,
    /// Dashed line.
    Dashed,
}

/// The palette index of a method: its position in
/// [`METHOD_NAMES`](crate::strategy::METHOD_NAMES) (one colour per method in every figure).
/// The forming runs' names map to the rules they use: `classical` → `constant`, `adaptive` →
/// `paper` (Eq. 28). Unknown names get the last palette entry.
pub fn method_color(name: &str) -> usize {
    let name = match name {
        "classical" => "constant",
        "adaptive" => "paper",
        n => n,
    };
    crate::strategy::METHOD_NAMES
        .iter()
        .position(|x| *x == name)
        .unwrap_or(PALETTE.len() - 1)
}

/// The legend name of a method in every figure: the δ-driven rules carry their equation.
pub fn method_label(name: &str) -> &str {
    match name {
        "spring" => "spring (Eq. 17)",
        "paper" => "paper (Eq. 26–29)",
        "condensed" => "condensed (exact δ)",
        n => n,
    }
}

/// A data series: `y` against `x`, drawn with `mark`.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates (same length as `x`).
    pub y: Vec<f64>,
    /// Drawing style.
    pub mark: Mark,
    /// Palette index ([`PALETTE`]); `None`: the series' position in [`Figure::series`].
    pub color: Option<usize>,
}

impl Series {
    /// A series with the default colour.
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, mark: Mark) -> Self {
        Series {
            label: label.into(),
            x,
            y,
            mark,
            color: None,
        }
    }
    /// Sets the palette index.
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
}

/// A shaded spread between `lo` and `hi` over `x` (e.g. min–max or quartiles).
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Lower edge (same length as `x`).
    pub lo: Vec<f64>,
    /// Upper edge (same length as `x`).
    pub hi: Vec<f64>,
    /// Palette index; `None`: the band's position in [`Figure::bands`].
    pub color: Option<usize>,
}

impl Band {
    /// A band with the default colour.
    pub fn new(label: impl Into<String>, x: Vec<f64>, lo: Vec<f64>, hi: Vec<f64>) -> Self {
        Band {
            label: label.into(),
            x,
            lo,
            hi,
            color: None,
        }
    }
    /// Sets the palette index.
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
}

/// A single highlighted point (large diamond) with its own legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// Abscissa.
    pub x: f64,
    /// Ordinate.
    pub y: f64,
    /// Palette index; `None`: black ([`BLACK_INDEX`]).
    pub color: Option<usize>,
}

impl Marker {
    /// A black marker.
    pub fn new(label: impl Into<String>, x: f64, y: f64) -> Self {
        Marker {
            label: label.into(),
            x,
            y,
            color: None,
        }
    }
    /// Sets the palette index.
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
}

/// A straight segment `((x0, y0), (x1, y1), palette index)` in data coordinates.
pub type Segment = ((f64, f64), (f64, f64), usize);

/// A figure described as data. Build with [`Figure::new`] and the builder helpers, or fill
/// the public fields directly.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title above the plot (empty: none).
    pub title: String,
    /// x-axis label (below the axis).
    pub x_label: String,
    /// y-axis label (written horizontally above the y axis).
    pub y_label: String,
    /// x-axis scale.
    pub x_scale: Scale,
    /// y-axis scale.
    pub y_scale: Scale,
    /// Data series, drawn in order on top of bands and segments.
    pub series: Vec<Series>,
    /// Shaded spreads, drawn first.
    pub bands: Vec<Band>,
    /// Highlighted points, drawn last.
    pub markers: Vec<Marker>,
    /// Vertical reference lines `(x, label)`: grey dashed, label written next to the line.
    pub vlines: Vec<(f64, String)>,
    /// Horizontal reference lines `(y, label)`: grey dashed, label written above the line.
    pub hlines: Vec<(f64, String)>,
    /// Straight segments `((x0, y0), (x1, y1), palette index)` in data coordinates, drawn
    /// 3 px wide without legend entry (rigid surfaces, obstacles, schematic drawings).
    pub segments: Vec<Segment>,
    /// Image size in pixels (width, height) for [`render`].
    pub size: (u32, u32),
}

impl Figure {
    /// An empty figure: linear scales, 900×600 px.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Figure {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            series: Vec::new(),
            bands: Vec::new(),
            markers: Vec::new(),
            vlines: Vec::new(),
            hlines: Vec::new(),
            segments: Vec::new(),
            size: (900, 600),
        }
    }
    /// Sets both axis scales.
    pub fn scales(mut self, x: Scale, y: Scale) -> Self {
        self.x_scale = x;
        self.y_scale = y;
        self
    }
    /// Log10 on both axes.
    pub fn log_log(self) -> Self {
        self.scales(Scale::Log10, Scale::Log10)
    }
    /// Sets the image size in pixels.
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }
    /// Adds a series.
    pub fn with_series(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
    /// Adds a solid-line series with the default colour.
    pub fn line(self, label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        self.with_series(Series::new(label, x, y, Mark::Line))
    }
    /// Adds a points-only series with the default colour.
    pub fn points(self, label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        self.with_series(Series::new(label, x, y, Mark::Points))
    }
    /// Adds a band.
    pub fn with_band(mut self, b: Band) -> Self {
        self.bands.push(b);
        self
    }
    /// Adds a marker.
    pub fn with_marker(mut self, m: Marker) -> Self {
        self.markers.push(m);
        self
    }
    /// Adds a horizontal reference line.
    pub fn hline(mut self, y: f64, label: impl Into<String>) -> Self {
        self.hlines.push((y, label.into()));
        self
    }
    /// Adds a vertical reference line.
    pub fn vline(mut self, x: f64, label: impl Into<String>) -> Self {
        self.vlines.push((x, label.into()));
        self
    }
    /// Adds a straight segment from `a` to `b` in palette colour `color`.
    pub fn segment(mut self, a: (f64, f64), b: (f64, f64), color: usize) -> Self {
        self.segments.push((a, b, color));
        self
    }
}

/// Renders `<stem>.png` and `<stem>.svg` (`stem` is a path without extension; missing parent
/// directories are created) and returns the two paths written.
///
/// Errors: [`Error::Input`] for inconsistent lengths, a zero image size or a figure with no
/// finite data; [`Error::Io`] when a file cannot be written.
pub fn render(fig: &Figure, stem: &Path) -> Result<Vec<PathBuf>> {
    render_panels_impl(std::slice::from_ref(fig), 1, stem, fig.size)
}

/// Draws several figures side by side in one image (`cols` per row, rows as needed, equal
/// cells), each with its own title, axes and legend; each figure's `size` is ignored in favour
/// of the total `size`. Writes `<stem>.png` and `<stem>.svg` and returns the paths.
///
/// Errors as for [`render`]; also [`Error::Input`] for no figures or `cols == 0`.
pub fn render_panels(
    figs: &[Figure],
    cols: usize,
    stem: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>> {
    render_panels_impl(figs, cols, stem, size)
}

fn render_panels_impl(
    figs: &[Figure],
    cols: usize,
    stem: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>> {
    if figs.is_empty() {
        return Err(Error::input("plot: no figures to render"));
    }
    if cols == 0 {
        return Err(Error::input("plot: panel columns must be ≥ 1, got 0"));
    }
    if size.0 < 50 || size.1 < 50 {
        return Err(Error::input(format!(
            "plot: image size {}×{} px too small (each side must be ≥ 50)",
            size.0, size.1
        )));
    }
    let preps = figs.iter().map(prepare).collect::<Result<Vec<_>>>()?;
    ensure_font()?;

    let cols = cols.min(figs.len());
    let rows = figs.len().div_ceil(cols);
    let cell = (size.0 as f64 / cols as f64, size.1 as f64 / rows as f64);
    let scale = (cell.0 / 900.0).min(cell.1 / 600.0).clamp(0.95, 2.0);

    if let Some(parent) = stem.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent.display(), e))?;
        }
    }
    // Append the extensions (`with_extension` would cut a dotted stem such as "beam_0.5").
    let with_ext = |ext: &str| {
        let mut p = stem.as_os_str().to_os_string();
        p.push(ext);
        PathBuf::from(p)
    };
    let (png, svg) = (with_ext(".png"), with_ext(".svg"));

    {
        let root = BitMapBackend::new(&png, size).into_drawing_area();
        draw_all(&root, figs, &preps, rows, cols, scale)
            .map_err(|e| Error::io(png.display(), e))?;
        root.present().map_err(|e| Error::io(png.display(), e))?;
    }
    {
        let root = SVGBackend::new(&svg, size).into_drawing_area();
        draw_all(&root, figs, &preps, rows, cols, scale)
            .map_err(|e| Error::io(svg.display(), e))?;
        root.present().map_err(|e| Error::io(svg.display(), e))?;
    }
    Ok(vec![png, svg])
}

fn draw_all<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figs: &[Figure],
    preps: &[Prepared],
    rows: usize,
    cols: usize,
    scale: f64,
) -> std::result::Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let cells = root.split_evenly((rows, cols));
    for ((fig, prep), cell) in figs.iter().zip(preps).zip(cells.iter()) {
        draw_figure(cell, fig, prep, scale)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Data preparation
// ---------------------------------------------------------------------------------------------

/// Whether `v` can be drawn on an axis with scale `s`.
fn ok(s: Scale, v: f64) -> bool {
    v.is_finite() && (s == Scale::Linear || v > 0.0)
}

/// Value in the axis' linear (transformed) space.
fn tr(s: Scale, v: f64) -> f64 {
    match s {
        Scale::Linear => v,
        Scale::Log10 => v.log10(),
    }
}

/// Figure data after validation: axis ranges in data space and in transformed space.
struct Prepared {
    x: (f64, f64),
    y: (f64, f64),
    xt: (f64, f64),
    yt: (f64, f64),
}

fn prepare(fig: &Figure) -> Result<Prepared> {
    let name = if fig.title.is_empty() {
        "figure".to_string()
    } else {
        format!("figure '{}'", fig.title)
    };
    for s in &fig.series {
        if s.x.len() != s.y.len() {
            return Err(Error::input(format!(
                "{name}: series '{}' has {} x values but {} y values",
                s.label,
                s.x.len(),
                s.y.len()
            )));
        }
    }
    for b in &fig.bands {
        if b.x.len() != b.lo.len() || b.x.len() != b.hi.len() {
            return Err(Error::input(format!(
                "{name}: band '{}' has {} x, {} lo and {} hi values (must be equal)",
                b.label,
                b.x.len(),
                b.lo.len(),
                b.hi.len()
            )));
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
        Error::input(format!(
            "{name}: no finite data for the {axis} axis, nothing to plot{extra}"
        ))
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
fn axis_range(vals: &[f64], s: Scale) -> Option<(f64, f64)> {
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
enum TickFmt {
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
    fn for_linear(ticks: &[f64], span: f64) -> Self {
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

    fn format(&self, v: f64) -> String {
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
fn format_log_tick(v: f64) -> String {
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
struct AxisTicks {
    bold: Vec<f64>,
    light: Vec<f64>,
    fmt: TickFmt,
}

/// Ticks for an axis over the data range `r`, at most about `n` labels.
fn ticks(s: Scale, r: (f64, f64), n: usize) -> AxisTicks {
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
fn log_ticks((lo, hi): (f64, f64), n: usize) -> AxisTicks {
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

// ---------------------------------------------------------------------------------------------
// Drawing
// ---------------------------------------------------------------------------------------------

/// Pixel sizes for one figure.
struct Style {
    title: f64,
    label: f64,
    tick: f64,
    legend: f64,
    annot: f64,
    s: f64,
}

impl Style {
    fn new(s: f64) -> Self {
        Style {
            title: 24.0 * s,
            label: 20.0 * s,
            tick: 17.0 * s,
            legend: 17.0 * s,
            annot: 15.0 * s,
            s,
        }
    }
    fn px(&self, v: f64) -> i32 {
        (v * self.s).round() as i32
    }
}

fn font(size: f64) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

/// Approximate rendered width of `text` in pixels at font size `size` (DejaVu Sans).
fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * 0.6 * size
}

fn draw_figure<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fig: &Figure,
    prep: &Prepared,
    scale: f64,
) -> std::result::Result<(), String> {
    let (w, h) = area.dim_in_pixel();
    let st = Style::new(scale);
    let title_h = if fig.title.is_empty() {
        0
    } else {
        (st.title * 1.9) as i32
    };
    let n_x = ((w as f64 / (85.0 * scale)) as usize).clamp(3, 10);
    let n_y = (((h as i32 - title_h) as f64 / (65.0 * scale)) as usize).clamp(3, 10);
    let xt = ticks(fig.x_scale, prep.x, n_x);
    let yt = ticks(fig.y_scale, prep.y, n_y);
    let (x0, x1) = prep.x;
    let (y0, y1) = prep.y;
    let lay = Layout {
        st,
        title_h,
        n_x,
        n_y,
    };
    let log = |r: std::ops::Range<f64>, t: &AxisTicks| {
        r.log_scale()
            .with_key_points(t.bold.clone())
            .with_light_points(t.light.clone())
    };
    match (fig.x_scale, fig.y_scale) {
        (Scale::Linear, Scale::Linear) => {
            draw_chart(area, fig, prep, &lay, &xt, &yt, x0..x1, y0..y1)
        }
        (Scale::Linear, Scale::Log10) => {
            draw_chart(area, fig, prep, &lay, &xt, &yt, x0..x1, log(y0..y1, &yt))
        }
        (Scale::Log10, Scale::Linear) => {
            draw_chart(area, fig, prep, &lay, &xt, &yt, log(x0..x1, &xt), y0..y1)
        }
        (Scale::Log10, Scale::Log10) => draw_chart(
            area,
            fig,
            prep,
            &lay,
            &xt,
            &yt,
            log(x0..x1, &xt),
            log(y0..y1, &yt),
        ),
    }
}

/// Sizes decided before the chart is built.
struct Layout {
    st: Style,
    title_h: i32,
    n_x: usize,
    n_y: usize,
}

/// Splits `(x, y)` pairs into runs of consecutive drawable points.
fn runs(xs: Scale, ys: Scale, pts: impl Iterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for (x, y) in pts {
        if ok(xs, x) && ok(ys, y) {
            cur.push((x, y));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Band runs: consecutive indices where x, lo and hi are all drawable; each as (x, lo, hi).
fn band_runs(fig: &Figure, b: &Band) -> Vec<Vec<(f64, f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for ((&x, &lo), &hi) in b.x.iter().zip(&b.lo).zip(&b.hi) {
        if ok(fig.x_scale, x) && ok(fig.y_scale, lo) && ok(fig.y_scale, hi) {
            cur.push((x, lo, hi));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Corner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

/// Normalised position (0..1 on both axes, y up) of a data point.
fn norm(fig: &Figure, prep: &Prepared, (x, y): (f64, f64)) -> (f64, f64) {
    (
        (tr(fig.x_scale, x) - prep.xt.0) / (prep.xt.1 - prep.xt.0),
        (tr(fig.y_scale, y) - prep.yt.0) / (prep.yt.1 - prep.yt.0),
    )
}

/// Sample points (normalised coordinates) along a polyline, about 100 per unit length.
fn sample_polyline(pts: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
    if let Some(&p) = pts.first() {
        out.push(p);
    }
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let k = ((d * 100.0).ceil() as usize).clamp(1, 200);
        for i in 1..=k {
            let t = i as f64 / k as f64;
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
}

/// Corner whose legend-sized box (normalised size `w`×`h`) contains the fewest data samples.
fn pick_corner(fig: &Figure, prep: &Prepared, w: f64, h: f64) -> Corner {
    let mut pts = Vec::new();
    for s in &fig.series {
        for run in runs(
            fig.x_scale,
            fig.y_scale,
            s.x.iter().copied().zip(s.y.iter().copied()),
        ) {
            let n: Vec<_> = run.iter().map(|&p| norm(fig, prep, p)).collect();
            match s.mark {
                Mark::Points => pts.extend(n),
                _ => sample_polyline(&n, &mut pts),
            }
        }
    }
    for b in &fig.bands {
        for run in band_runs(fig, b) {
            for f in [0.0, 0.25, 0.5, 0.75, 1.0] {
                let n: Vec<_> = run
                    .iter()
                    .map(|&(x, lo, hi)| {
                        let (u, vlo) = norm(fig, prep, (x, lo));
                        let (_, vhi) = norm(fig, prep, (x, hi));
                        (u, vlo + f * (vhi - vlo))
                    })
                    .collect();
                sample_polyline(&n, &mut pts);
            }
        }
    }
    for m in &fig.markers {
        if ok(fig.x_scale, m.x) && ok(fig.y_scale, m.y) {
            // A marker weighs like a short stretch of line.
            let p = norm(fig, prep, (m.x, m.y));
            pts.extend(std::iter::repeat_n(p, 20));
        }
    }
    let count = |c: Corner| {
        pts.iter()
            .filter(|&&(u, v)| {
                let in_x = match c {
                    Corner::UpperLeft | Corner::LowerLeft => u <= w,
                    _ => u >= 1.0 - w,
                };
                let in_y = match c {
                    Corner::UpperLeft | Corner::UpperRight => v >= 1.0 - h,
                    _ => v <= h,
                };
                in_x && in_y
            })
            .count()
    };
    [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
    ]
    .into_iter()
    .min_by_key(|&c| count(c))
    .unwrap_or(Corner::UpperRight)
}

#[allow(clippy::too_many_arguments)]
fn draw_chart<DB, XS, YS>(
    area: &DrawingArea<DB, Shift>,
    fig: &Figure,
    prep: &Prepared,
    lay: &Layout,
    xt: &AxisTicks,
    yt: &AxisTicks,
    x_spec: XS,
    y_spec: YS,
) -> std::result::Result<(), String>
where
    DB: DrawingBackend,
    XS: AsRangedCoord<Value = f64>,
    YS: AsRangedCoord<Value = f64>,
    XS::CoordDescType: ValueFormatter<f64>,
    YS::CoordDescType: ValueFormatter<f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let st = &lay.st;
    let scale = st.s;
    let (w, _) = area.dim_in_pixel();

    // Title strip.
    let body = if fig.title.is_empty() {
        area.clone()
    } else {
        let th = lay.title_h;
        let (top, rest) = area.split_vertically(th);
        top.draw(&Text::new(
            fig.title.as_str(),
            ((w / 2) as i32, th / 2 + st.px(3.0)),
            font(st.title).pos(Pos::new(HPos::Center, VPos::Center)),
        ))
        .map_err(e)?;
        rest
    };
    let (n_x, n_y) = (lay.n_x, lay.n_y);
    let (xfmt, yfmt) = (xt.fmt, yt.fmt);
    let y_tick_w = yt
        .bold
        .iter()
        .map(|&v| text_width(&yfmt.format(v), st.tick))
        .fold(text_width("0", st.tick), f64::max);
    let y_area = (y_tick_w + 16.0 * scale).ceil() as u32;
    let x_area = if fig.x_label.is_empty() {
        (st.tick * 2.0) as u32
    } else {
        (st.tick * 1.7 + st.label * 1.4) as u32
    };
    let top = if fig.y_label.is_empty() {
        st.px(12.0) as u32
    } else {
        (st.label * 2.1) as u32
    };
    // Right margin: room for the last x tick label to overhang.
    let right =
        (text_width(&xfmt.format(prep.x.1), st.tick) / 2.0 + 10.0 * scale).max(22.0 * scale) as u32;

    let mut chart = ChartBuilder::on(&body)
        .margin_top(top)
        .margin_right(right)
        .margin_left(st.px(10.0) as u32)
        .margin_bottom(st.px(6.0) as u32)
        .x_label_area_size(x_area)
        .y_label_area_size(y_area)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(e)?;

    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let xf = move |v: &f64| xfmt.format(*v);
    let yf = move |v: &f64| yfmt.format(*v);
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_labels(n_x)
            .y_labels(n_y)
            .x_label_formatter(&xf)
            .y_label_formatter(&yf)
            .label_style(font(st.tick))
            .axis_desc_style(font(st.label))
            .bold_line_style(RGBColor(220, 220, 220).stroke_width(1))
            .light_line_style(RGBColor(242, 242, 242).stroke_width(1))
            .axis_style(BLACK.stroke_width(1))
            .set_all_tick_mark_size(st.px(5.0))
            // Minor grid: 2…9 × 10^k on log axes, one line between labels on linear axes.
            .x_max_light_lines(if xs == Scale::Log10 { 10 } else { 1 })
            .y_max_light_lines(if ys == Scale::Log10 { 10 } else { 1 });
        if !fig.x_label.is_empty() {
            mesh.x_desc(fig.x_label.as_str());
        }
        mesh.draw().map_err(e)?;
    }

    draw_bands(&mut chart, fig, st)?;
    draw_lines(&mut chart, fig, prep, st)?;
    draw_marks(&mut chart, fig, st)?;
    draw_markers(&mut chart, fig, st)?;
    let legend = draw_legend(&mut chart, fig, prep, st)?;
    draw_reference_labels(&mut chart, fig, prep, st, legend)?;
    let (prx, pry) = chart.plotting_area().get_pixel_range();
    // Frame around the plotting area and the horizontal y label above the y axis.
    let (bx, by) = area.get_base_pixel();
    let (ax0, ay0) = (prx.start - bx, pry.start - by);
    let (ax1, ay1) = (prx.end - bx - 1, pry.end - by - 1);
    area.draw(&PathElement::new(
        vec![(ax0, ay0), (ax1, ay0), (ax1, ay1)],
        BLACK.stroke_width(1),
    ))
    .map_err(e)?;
    if !fig.y_label.is_empty() {
        let x = (ax0 - y_area as i32 + st.px(4.0)).max(st.px(4.0));
        area.draw(&Text::new(
            fig.y_label.as_str(),
            (x, ay0 - st.px(8.0)),
            font(st.label).pos(Pos::new(HPos::Left, VPos::Bottom)),
        ))
        .map_err(e)?;
    }
    Ok(())
}

/// Spread bands: filled polygons between their lower and upper curves, with edges.
fn draw_bands<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    st: &Style,
) -> std::result::Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // Bands.
    for (i, b) in fig.bands.iter().enumerate() {
        let c = pal(b.color.unwrap_or(i));
        let polys: Vec<Polygon<(f64, f64)>> = band_runs(fig, b)
            .into_iter()
            .map(|run| {
                let mut p: Vec<(f64, f64)> = run.iter().map(|&(x, _, hi)| (x, hi)).collect();
                p.extend(run.iter().rev().map(|&(x, lo, _)| (x, lo)));
                Polygon::new(p, c.mix(0.22).filled())
            })
            .collect();
        let anno = chart.draw_series(polys).map_err(e)?;
        if !b.label.is_empty() {
            let r = st.px(7.0);
            let len = st.px(28.0);
            anno.label(b.label.as_str()).legend(move |(x, y)| {
                Rectangle::new([(x, y - r), (x + len, y + r)], c.mix(0.3).filled())
            });
        }
        for run in band_runs(fig, b) {
            for edge in [
                run.iter().map(|&(x, lo, _)| (x, lo)).collect::<Vec<_>>(),
                run.iter().map(|&(x, _, hi)| (x, hi)).collect::<Vec<_>>(),
            ] {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        edge,
                        c.mix(0.45).stroke_width(1),
                    )))
                    .map_err(e)?;
            }
        }
    }

    Ok(())
}

/// Coloured segments and the dashed reference lines (their labels come after the legend).
fn draw_lines<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
) -> std::result::Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    // Segments.
    let seg_w = st.px(3.0).max(1) as u32;
    chart
        .draw_series(
            fig.segments
                .iter()
                .filter(|(a, b, _)| ok(xs, a.0) && ok(ys, a.1) && ok(xs, b.0) && ok(ys, b.1))
                .map(|&(a, b, ci)| PathElement::new(vec![a, b], pal(ci).stroke_width(seg_w))),
        )
        .map_err(e)?;

    // Reference lines (labels are written later, away from the legend).
    let dash = (st.px(8.0) as f64, st.px(5.0) as f64);
    let ref_style = REF_GREY.stroke_width(st.px(1.5).max(1) as u32);
    for (y, _) in fig.hlines.iter().filter(|l| ok(ys, l.0)) {
        chart
            .draw_series(std::iter::once(DashedPathElement::new(
                vec![(prep.x.0, *y), (prep.x.1, *y)],
                dash.0,
                dash.1,
                ref_style,
            )))
            .map_err(e)?;
    }
    for (x, _) in fig.vlines.iter().filter(|l| ok(xs, l.0)) {
        chart
            .draw_series(std::iter::once(DashedPathElement::new(
                vec![(*x, prep.y.0), (*x, prep.y.1)],
                dash.0,
                dash.1,
                ref_style,
            )))
            .map_err(e)?;
    }

    Ok(())
}

/// The data series in their marks, each with its legend entry.
fn draw_marks<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    st: &Style,
) -> std::result::Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let lw = st.px(2.0).max(1) as u32;
    let dash = (st.px(8.0) as f64, st.px(5.0) as f64);
    // Series.
    let len = st.px(28.0);
    let pr = st.px(4.0).max(2);
    for (i, s) in fig.series.iter().enumerate() {
        let c = pal(s.color.unwrap_or(i));
        let line = c.stroke_width(lw);
        let rs = runs(xs, ys, s.x.iter().copied().zip(s.y.iter().copied()));
        let has_label = !s.label.is_empty();
        match s.mark {
            Mark::Line => {
                let anno = chart
                    .draw_series(rs.into_iter().map(|r| PathElement::new(r, line)))
                    .map_err(e)?;
                if has_label {
                    anno.label(s.label.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + len, y)], line));
                }
            }
            Mark::Dashed => {
                let anno = chart
                    .draw_series(
                        rs.into_iter()
                            .map(|r| DashedPathElement::new(r, dash.0, dash.1, line)),
                    )
                    .map_err(e)?;
                if has_label {
                    let d = (dash.0 as i32, dash.1 as i32);
                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (d.0, 0)], line)
                            + PathElement::new(vec![(d.0 + d.1, 0), (len, 0)], line)
                    });
                }
            }
            Mark::Points => {
                let anno = chart
                    .draw_series(
                        rs.into_iter()
                            .flatten()
                            .map(|p| Circle::new(p, pr, c.filled())),
                    )
                    .map_err(e)?;
                if has_label {
                    anno.label(s.label.as_str())
                        .legend(move |(x, y)| Circle::new((x + len / 2, y), pr, c.filled()));
                }
            }
            Mark::LinePoints => {
                chart
                    .draw_series(rs.iter().map(|r| PathElement::new(r.clone(), line)))
                    .map_err(e)?;
                let anno = chart
                    .draw_series(
                        rs.into_iter()
                            .flatten()
                            .map(|p| Circle::new(p, pr, c.filled())),
                    )
                    .map_err(e)?;
                if has_label {
                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (len, 0)], line)
                            + Circle::new((len / 2, 0), pr, c.filled())
                    });
                }
            }
        }
    }

    Ok(())
}

/// Markers: diamonds with a black outline.
fn draw_markers<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    st: &Style,
) -> std::result::Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let len = st.px(28.0);
    // Markers: diamond with a black outline.
    let r = st.px(9.0);
    let diamond = move |c: RGBColor| {
        let pts = vec![(0, -r), (r, 0), (0, r), (-r, 0)];
        let mut closed = pts.clone();
        closed.push((0, -r));
        (
            Polygon::new(pts, c.filled()),
            PathElement::new(closed, BLACK.stroke_width(1)),
        )
    };
    for m in &fig.markers {
        let c = pal(m.color.unwrap_or(BLACK_INDEX));
        let shown = ok(xs, m.x) && ok(ys, m.y);
        let anno = chart
            .draw_series(shown.then(|| {
                let (poly, outline) = diamond(c);
                EmptyElement::at((m.x, m.y)) + poly + outline
            }))
            .map_err(e)?;
        if !m.label.is_empty() {
            anno.label(m.label.as_str()).legend(move |(x, y)| {
                let (poly, outline) = diamond(c);
                EmptyElement::at((x + len / 2, y)) + poly + outline
            });
        }
    }

    Ok(())
}

/// The legend in the emptiest corner; returns the corner and the legend's size in
/// normalised plot coordinates (0×0: no legend).
fn draw_legend<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
) -> std::result::Result<(Corner, (f64, f64)), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let scale = st.s;
    // Legend in the emptiest corner.
    let (prx, pry) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = (
        (prx.end - prx.start).max(1) as f64,
        (pry.end - pry.start).max(1) as f64,
    );
    let labels: Vec<&str> = fig
        .bands
        .iter()
        .map(|b| b.label.as_str())
        .chain(fig.series.iter().map(|s| s.label.as_str()))
        .chain(fig.markers.iter().map(|m| m.label.as_str()))
        .filter(|l| !l.is_empty())
        .collect();
    // Legend size in normalised plot coordinates (0×0: no legend).
    let mut legend_wh = (0.0, 0.0);
    let corner = if labels.is_empty() {
        Corner::UpperRight
    } else {
        let lw_px = labels
            .iter()
            .map(|l| text_width(l, st.legend))
            .fold(0.0, f64::max)
            + 36.0 * scale
            + 30.0 * scale;
        let lh_px = labels.len() as f64 * st.legend * 1.25 + 30.0 * scale;
        legend_wh = (lw_px / pw, lh_px / ph);
        pick_corner(fig, prep, legend_wh.0, legend_wh.1)
    };
    if !labels.is_empty() {
        let pos = match corner {
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        };
        chart
            .configure_series_labels()
            .position(pos)
            .margin(st.px(8.0).max(2) as u32)
            .legend_area_size(st.px(36.0).max(10) as u32)
            .label_font(font(st.legend))
            .background_style(WHITE)
            .border_style(RGBColor(90, 90, 90))
            .draw()
            .map_err(e)?;
    }

    Ok((corner, legend_wh))
}

/// Reference-line labels: hline labels at the right end above the line, vline labels at the
/// top right of the line, each moved to the other end where it would hit the legend.
fn draw_reference_labels<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
    (corner, legend_wh): (Corner, (f64, f64)),
) -> std::result::Result<(), String>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let (prx, pry) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = (
        (prx.end - prx.start).max(1) as f64,
        (pry.end - pry.start).max(1) as f64,
    );
    // Reference-line labels: hline labels at the right end above the line, vline labels at the
    // top right of the line, each moved to the other end where it would hit the legend.
    let legend_right = matches!(corner, Corner::UpperRight | Corner::LowerRight);
    let legend_top = matches!(corner, Corner::UpperRight | Corner::UpperLeft);
    let in_legend_x = |a: f64, b: f64| {
        if legend_right {
            b >= 1.0 - legend_wh.0
        } else {
            a <= legend_wh.0
        }
    };
    let in_legend_y = |a: f64, b: f64| {
        if legend_top {
            b >= 1.0 - legend_wh.1
        } else {
            a <= legend_wh.1
        }
    };
    let gap = st.px(5.0);
    let tw = |l: &str| text_width(l, st.annot) / pw;
    let th = st.annot * 1.3 / ph;
    for (y, label) in fig.hlines.iter().filter(|l| ok(ys, l.0) && !l.1.is_empty()) {
        let v = norm(fig, prep, (prep.x.0, *y)).1;
        let hits = legend_wh.0 > 0.0 && in_legend_x(1.0 - tw(label), 1.0) && in_legend_y(v, v + th);
        let (x, dx, hp) = if hits {
            (prep.x.0, gap, HPos::Left)
        } else {
            (prep.x.1, -gap, HPos::Right)
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, *y))
                    + Text::new(
                        label.clone(),
                        (dx, -gap / 2),
                        font(st.annot)
                            .color(&REF_GREY)
                            .pos(Pos::new(hp, VPos::Bottom)),
                    ),
            ))
            .map_err(e)?;
    }
    for (x, label) in fig.vlines.iter().filter(|l| ok(xs, l.0) && !l.1.is_empty()) {
        let u = norm(fig, prep, (*x, prep.y.0)).0;
        let w = tw(label);
        // Right of the line unless that runs out of the plot.
        let (a, b, dx, hp) = if u + w < 0.98 {
            (u, u + w, gap, HPos::Left)
        } else {
            (u - w, u, -gap, HPos::Right)
        };
        let hits = legend_wh.0 > 0.0 && in_legend_x(a, b) && in_legend_y(1.0 - th, 1.0);
        let (y, dy, vp) = if hits {
            (prep.y.0, -gap, VPos::Bottom)
        } else {
            (prep.y.1, gap, VPos::Top)
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((*x, y))
                    + Text::new(
                        label.clone(),
                        (dx, dy),
                        font(st.annot).color(&REF_GREY).pos(Pos::new(hp, vp)),
                    ),
            ))
            .map_err(e)?;
    }

    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_tick_labels() {
        assert_eq!(format_log_tick(1000.0), "1e3");
        assert_eq!(format_log_tick(0.01), "1e-2");
        assert_eq!(format_log_tick(1.0), "1e0");
        assert_eq!(format_log_tick(2000.0), "2e3");
        assert_eq!(format_log_tick(2.5e-4), "2.5e-4");
    }

    #[test]
    fn linear_tick_labels() {
        let f = TickFmt::for_linear(&[0.0, 0.5, 1.0, 1.5], 1.5);
        assert_eq!(f.format(0.5), "0.5");
        assert_eq!(f.format(1.0), "1.0");
        let f = TickFmt::for_linear(&[0.0, 2e5, 4e5], 4e5);
        assert_eq!(f.format(4e5), "4e5");
        assert_eq!(f.format(0.0), "0");
    }

    #[test]
    fn log_ticks_fit_the_range() {
        let t = log_ticks((1.0, 1e12), 8);
        assert_eq!(t.bold.len(), 7);
        assert_eq!(TickFmt::Log.format(t.bold[1]), "1e2");
        let t = log_ticks((0.9, 11.0), 8);
        assert_eq!(t.bold, vec![1.0, 2.0, 5.0, 10.0]);
        assert_eq!(t.fmt.format(5.0), "5");
        let t = log_ticks((21.0, 29.0), 8);
        assert!(t.bold.len() >= 3 && t.bold.iter().all(|v| (21.0..=29.0).contains(v)));
    }

    #[test]
    fn ranges() {
        assert!(axis_range(&[], Scale::Linear).is_none());
        let (a, b) = axis_range(&[3.0, 3.0], Scale::Linear).unwrap();
        assert!(a < 3.0 && b > 3.0);
    }
}
