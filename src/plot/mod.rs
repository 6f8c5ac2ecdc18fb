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
//! skipped too. A figure without a single drawable point is an [`Error::NoneGiven`].
//!
//! Files: `style.rs` (font, palette, per-method colours and labels, type sizes), `axes.rs`
//! (ranges, scales, ticks), `chart.rs` (one chart), `legend.rs` (legend corner, reference
//! labels); this module holds the figure data types and the renderers.
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

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::{Error, Result};

mod axes;
mod chart;
mod legend;
mod style;

pub use crate::strategy::Glyph;
use axes::*;
use chart::*;
use legend::*;
use style::*;
pub use style::{method_color, method_glyph, method_label, BLACK_INDEX, PALETTE};

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
    /// Point shape of [`Mark::Points`] and [`Mark::LinePoints`].
    pub glyph: Glyph,
    /// `(offset, stride)`: glyphs at the points whose index i has i % stride == offset (a
    /// line of 100 steps carries a glyph every few steps; offsets stagger coinciding curves).
    pub glyph_every: (usize, usize),
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
            glyph: Glyph::Circle,
            glyph_every: (0, 1),
        }
    }
    /// Sets the palette index.
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
    /// Colour and point shape of the method (or forming run) `name`: [`method_color`],
    /// [`method_glyph`].
    pub fn method(self, name: &str) -> Self {
        self.color(method_color(name)).glyph(method_glyph(name))
    }
    /// Sets the point shape.
    pub fn glyph(mut self, glyph: Glyph) -> Self {
        self.glyph = glyph;
        self
    }
    /// Draws glyphs only at every `stride`-th point from `offset` (stride ≥ 1).
    pub fn glyph_every(mut self, offset: usize, stride: usize) -> Self {
        self.glyph_every = (offset, stride.max(1));
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
/// Errors: [`Error::LengthMismatch`] for inconsistent lengths, [`Error::OutOfRange`] for an
/// image side below 50 px, [`Error::NoneGiven`] for a figure with no finite data;
/// [`Error::Io`] when a file cannot be written.
pub fn render(fig: &Figure, stem: &Path) -> Result<Vec<PathBuf>> {
    render_panels_impl(std::slice::from_ref(fig), 1, stem, fig.size)
}

/// Draws several figures side by side in one image (`cols` per row, rows as needed, equal
/// cells), each with its own title, axes and legend; each figure's `size` is ignored in favour
/// of the total `size`, grown where a cell would be smaller than [`MIN_PANEL`]
/// ([`panel_canvas`]). Writes `<stem>.png` and `<stem>.svg` and returns the paths.
///
/// Errors as for [`render`]; also [`Error::NoneGiven`] for no figures and
/// [`Error::OutOfRange`] for `cols == 0`.
pub fn render_panels(
    figs: &[Figure],
    cols: usize,
    stem: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>> {
    render_panels_impl(figs, cols, stem, size)
}

/// Whether `fig`'s legend finds a corner free of data when drawn in a cell of `cell` px (as in
/// [`render_panels`]), i.e. without the y range grown to make room for it
/// (`legend::with_legend_room`). True for a figure without labels. For figures that share
/// one legend: carry it on a panel where it fits.
pub fn legend_fits(fig: &Figure, cell: (f64, f64)) -> Result<bool> {
    let prep = prepare(fig)?;
    let scale = (cell.0 / 900.0).min(cell.1 / 600.0).clamp(0.95, 2.0);
    Ok(chart::legend_fraction(fig, cell, scale)
        .is_none_or(|(w, h)| legend::legend_fits(fig, &prep, w, h)))
}

/// One legend for panels that share their series' labels (the same rules in every panel): the
/// labels stay on the panel naming the most series (the first of those) among the panels
/// whose legend [fits](legend_fits) in its cell of the [`render_panels`] grid (`cols`,
/// `size`), else on the first panel, and are cleared on the others. Bands' and markers' labels are left alone.
pub fn share_legend(figs: &mut [Figure], cols: usize, size: (u32, u32)) -> Result<()> {
    if figs.is_empty() || cols == 0 {
        return Ok(());
    }
    let cols = cols.min(figs.len());
    let rows = figs.len().div_ceil(cols);
    let canvas = panel_canvas(rows, cols, size);
    let cell = (canvas.0 as f64 / cols as f64, canvas.1 as f64 / rows as f64);
    // The panel whose legend names the most series (the first of those), among those where
    // it fits: a panel missing a series (no nodal AMG on a scalar family) would leave it
    // unnamed.
    let mut keep = 0;
    let mut most = None;
    for (i, f) in figs.iter().enumerate() {
        let named = f.series.iter().filter(|s| !s.label.is_empty()).count();
        if most.is_none_or(|m| named > m) && legend_fits(f, cell)? {
            keep = i;
            most = Some(named);
        }
    }
    for (i, f) in figs.iter_mut().enumerate() {
        if i != keep {
            for s in &mut f.series {
                s.label.clear();
            }
        }
    }
    Ok(())
}

/// Smallest cell of a panel grid (px): below it the plot area of a panel, under its title,
/// axis labels and ticks, shrinks to a strip.
pub const MIN_PANEL: (u32, u32) = (420, 340);

/// The image size for `rows × cols` panels asked as `size`: each side grown where needed so
/// that no cell is smaller than [`MIN_PANEL`].
pub fn panel_canvas(rows: usize, cols: usize, size: (u32, u32)) -> (u32, u32) {
    (
        size.0.max(MIN_PANEL.0 * cols as u32),
        size.1.max(MIN_PANEL.1 * rows as u32),
    )
}

fn render_panels_impl(
    figs: &[Figure],
    cols: usize,
    stem: &Path,
    size: (u32, u32),
) -> Result<Vec<PathBuf>> {
    if figs.is_empty() {
        return Err(Error::none_given("plot: figures to render", ""));
    }
    if cols == 0 {
        return Err(Error::out_of_range("plot: panel columns", cols, "≥ 1"));
    }
    if size.0 < 50 || size.1 < 50 {
        return Err(Error::out_of_range(
            "plot: image size",
            format!("{}×{} px", size.0, size.1),
            "at least 50 px on each side",
        ));
    }
    let preps = figs.iter().map(prepare).collect::<Result<Vec<_>>>()?;
    ensure_font()?;

    let cols = cols.min(figs.len());
    let rows = figs.len().div_ceil(cols);
    let size = panel_canvas(rows, cols, size);
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

    /// One shared legend: kept on the first panel where it fits (the second here, the first
    /// being covered by a dense grid of points), cleared on the others.
    #[test]
    fn shared_legend_goes_where_it_fits() {
        let grid: Vec<(f64, f64)> = (0..21)
            .flat_map(|i| (0..21).map(move |j| (i as f64, j as f64)))
            .collect();
        let dense = Figure::new("dense", "x", "y").with_series(Series::new(
            "rule",
            grid.iter().map(|p| p.0).collect(),
            grid.iter().map(|p| p.1).collect(),
            Mark::Points,
        ));
        let free = Figure::new("free", "x", "y").with_series(Series::new(
            "rule",
            vec![0.0, 1.0],
            vec![0.0, 1.0],
            Mark::Line,
        ));
        let mut figs = vec![dense, free];
        share_legend(&mut figs, 2, (1200, 500)).unwrap();
        assert!(figs[0].series[0].label.is_empty());
        assert_eq!(figs[1].series[0].label, "rule");
    }

    /// The legend stays on the panel that names every series, not on the first one.
    #[test]
    fn shared_legend_goes_where_it_names_the_most_series() {
        let line =
            |label: &str, y: f64| Series::new(label, vec![0.0, 1.0], vec![y, y + 1.0], Mark::Line);
        let one = Figure::new("one", "x", "y").with_series(line("a", 0.0));
        let two = Figure::new("two", "x", "y")
            .with_series(line("a", 0.0))
            .with_series(line("b", 5.0));
        let mut figs = vec![one, two];
        share_legend(&mut figs, 2, (1200, 500)).unwrap();
        assert!(figs[0].series[0].label.is_empty());
        assert_eq!(figs[1].series[1].label, "b");
    }
}
