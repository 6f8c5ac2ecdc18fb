//! The house style: embedded font, the Okabe–Ito palette, one colour and legend name per method, type sizes.

use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::strategy::{self, Glyph, Strategy};
use crate::{Error, Result};

/// The embedded font (DejaVu Sans, see `assets/DejaVuSans-LICENSE.txt`).
pub(super) static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
/// Family name under which the embedded font is registered.
pub(super) const FONT: &str = "sans-serif";

/// Okabe–Ito colour-blind-friendly palette, in the order used for `color: Some(i)` (taken
/// modulo its length) and for default colours (series order): blue, vermillion, bluish green,
/// orange, reddish purple, sky blue, black, yellow; then grey (for a registered rule),
/// brown (`optimal`'s: yellow is too faint for a line on white) and dark red (`barrier`'s).
pub const PALETTE: [(u8, u8, u8); 11] = [
    (0, 114, 178),
    (213, 94, 0),
    (0, 158, 115),
    (230, 159, 0),
    (204, 121, 167),
    (86, 180, 233),
    (0, 0, 0),
    (240, 228, 66),
    (128, 128, 128),
    (140, 86, 60),
    (165, 0, 38),
];

/// Palette index of black (default colour of [`Marker`](super::Marker)s).
pub const BLACK_INDEX: usize = 6;

/// Colour of palette entry `i` (modulo the palette length).
pub(super) fn pal(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// Grey used for reference lines (`hlines`, `vlines`) and their labels.
pub(super) const REF_GREY: RGBColor = RGBColor(70, 70, 70);

/// Registers the embedded font once; later calls return the stored outcome.
pub(super) fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "embedded font assets/DejaVuSans.ttf is not a valid font".to_string())
        })
        .clone()
        .map_err(Error::Numerical)
}

/// Pixel sizes for one figure.
pub(super) struct Style {
    pub(super) title: f64,
    pub(super) label: f64,
    pub(super) tick: f64,
    pub(super) legend: f64,
    pub(super) annot: f64,
    pub(super) s: f64,
}

impl Style {
    pub(super) fn new(s: f64) -> Self {
        Style {
            title: 24.0 * s,
            label: 20.0 * s,
            tick: 17.0 * s,
            legend: 17.0 * s,
            annot: 15.0 * s,
            s,
        }
    }
    pub(super) fn px(&self, v: f64) -> i32 {
        (v * self.s).round() as i32
    }

    /// Width of data lines (px).
    pub(super) fn line_width(&self) -> u32 {
        self.px(2.0).max(1) as u32
    }

    /// Dash and gap lengths of dashed lines (px).
    pub(super) fn dash(&self) -> (f64, f64) {
        (self.px(8.0) as f64, self.px(5.0) as f64)
    }

    /// Length of a legend entry's sample (px).
    pub(super) fn legend_sample(&self) -> i32 {
        self.px(28.0)
    }
}

/// A drawing-area error as the message `draw_figure` reports.
pub(super) fn area_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> String {
    e.to_string()
}

pub(super) fn font(size: f64) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

/// Rendered width of `text` in pixels at font size `size`: the embedded font's own layout
/// (plotters' `box_size`), else 0.6·size per character (an upper bound for DejaVu Sans, about
/// 1.5× the typical width of running text).
pub(super) fn text_width(text: &str, size: f64) -> f64 {
    let estimate = text.chars().count() as f64 * 0.6 * size;
    if ensure_font().is_err() {
        return estimate;
    }
    font(size)
        .font
        .box_size(text)
        .map_or(estimate, |(w, _)| w as f64)
}

/// The strategy whose colour a forming run's name takes: `classical` and
/// `classical-matched` → `constant`,
/// `adaptive` and `paper-residual` → `paper` (Eq. 28 on the residual), `paper-literal`
/// (Eq. 28 as printed) → `spring` (both drop the coupling to the unconstrained DOFs; `spring`
/// never appears in a forming figure).
fn forming_alias(name: &str) -> Option<&'static Strategy> {
    match name {
        "classical" | "classical-matched" => Some(&strategy::constant::STRATEGY),
        "adaptive" | "paper-residual" => Some(&strategy::paper::STRATEGY),
        "paper-literal" => Some(&strategy::spring::STRATEGY),
        _ => None,
    }
}

/// The palette index of a method: the colour its [`Strategy`] declares (one colour per
/// method in every figure); a forming run's name takes its rule's colour, `K alone` (no
/// contact terms) black. Unknown names get yellow (index 7).
pub fn method_color(name: &str) -> usize {
    if name == "K alone" {
        return BLACK_INDEX;
    }
    forming_alias(name)
        .or_else(|| strategy::registry::find(name))
        .map_or(7, |s| s.look.colour)
}

/// The point marker of a method: its [`Strategy`]'s glyph; a forming run's name takes its
/// rule's, except `classical-matched` (a square beside `classical`'s would hide it: a ×) and
/// `K alone` (a circle).
pub fn method_glyph(name: &str) -> Glyph {
    match name {
        "classical-matched" => Glyph::Cross,
        "K alone" => Glyph::Circle,
        n => forming_alias(n)
            .or_else(|| strategy::registry::find(n))
            .map_or(Glyph::Circle, |s| s.look.glyph),
    }
}

/// The legend name of a method in every figure: its [`Strategy`]'s label (the δ-driven
/// rules carry their equation), or a forming run's.
pub fn method_label(name: &str) -> &str {
    match name {
        "adaptive" | "paper-residual" => "adaptive (Eq. 28 on the residual)",
        "paper-literal" => "paper-literal (Eq. 28 as printed)",
        n => strategy::registry::find(n).map_or(n, |s| s.label()),
    }
}
