//! Smoke tests for `penalty_lab::plot`: both formats are written, bad data is an error.

use crate::common;
use std::path::PathBuf;

use penalty_lab::plot::{render, render_panels, Band, Figure, Glyph, Mark, Marker, Scale, Series};

fn loglog_figure() -> Figure {
    let eps: Vec<f64> = (0..=24).map(|k| 10f64.powf(k as f64 * 0.5)).collect();
    let kappa: Vec<f64> = eps.iter().map(|e| 1e2 * (1.0 + e)).collect();
    let err: Vec<f64> = eps.iter().map(|e| 1.0 / e + 1e-10 * e).collect();
    let lo: Vec<f64> = kappa.iter().map(|k| k * 0.5).collect();
    let hi: Vec<f64> = kappa.iter().map(|k| k * 2.0).collect();
    Figure::new(
        "Penalty sweep: conditioning vs. accuracy",
        "penalty parameter ε",
        "κ(K), error",
    )
    .scales(Scale::Log10, Scale::Log10)
    .with_band(Band::new("κ spread (min–max)", eps.clone(), lo, hi))
    .with_series(Series::new(
        "condition number κ",
        eps.clone(),
        kappa,
        Mark::LinePoints,
    ))
    .with_series(Series::new("gap error", eps, err, Mark::Dashed).color(1))
    .with_marker(Marker::new("optimum ε*", 1e5, 2e-5).color(1))
    .hline(1e12, "κ limit 1e12")
}

#[test]
fn loglog_renders_png_and_svg() {
    let tmp = common::tmp_dir("plot-loglog");
    let dir = tmp.path();
    let paths = render(&loglog_figure(), &dir.join("loglog")).unwrap();
    assert_eq!(paths.len(), 2);
    let png = paths
        .iter()
        .find(|p| p.extension().unwrap() == "png")
        .unwrap();
    let svg = paths
        .iter()
        .find(|p| p.extension().unwrap() == "svg")
        .unwrap();
    let bytes = std::fs::read(png).unwrap();
    assert!(!bytes.is_empty());
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let text = std::fs::read_to_string(svg).unwrap();
    assert!(text.contains("<svg"));
    assert!(text.contains("condition number κ"));
    assert!(text.contains("gap error"));
    if let Ok(keep) = std::env::var("PLOT_EXAMPLE") {
        std::fs::copy(png, keep).unwrap();
    }
}

#[test]
fn all_nan_is_an_error() {
    let tmp = common::tmp_dir("plot-nan");
    let dir = tmp.path();
    let fig = Figure::new("nan", "x", "y").with_series(Series::new(
        "nan",
        vec![f64::NAN, f64::INFINITY],
        vec![f64::NAN, 1.0],
        Mark::Line,
    ));
    let err = render(&fig, &dir.join("nan")).unwrap_err();
    assert!(matches!(err, penalty_lab::Error::NoneGiven { .. }), "{err}");
    assert!(!dir.join("nan.png").exists());
    // Empty figure as well.
    assert!(render(&Figure::new("", "x", "y"), &dir.join("empty")).is_err());
}

#[test]
fn length_mismatch_is_an_error() {
    let tmp = common::tmp_dir("plot-len");
    let dir = tmp.path();
    let fig = Figure::new("bad", "x", "y").line("s", vec![1.0, 2.0], vec![1.0]);
    assert!(matches!(
        render(&fig, &dir.join("bad")),
        Err(penalty_lab::Error::LengthMismatch { .. })
    ));
}

#[test]
fn log_scale_skips_non_positive_values() {
    let tmp = common::tmp_dir("plot-neg");
    let dir = tmp.path();
    let x = vec![-1.0, 0.0, 1.0, 2.0, 3.0, 4.0, f64::NAN, 6.0];
    let y = vec![1.0, 2.0, -3.0, 4.0, 0.0, 16.0, 25.0, 36.0];
    let fig = Figure::new("negatives", "x", "y")
        .scales(Scale::Log10, Scale::Log10)
        .with_series(Series::new("s", x.clone(), y.clone(), Mark::LinePoints))
        .with_band(Band::new(
            "b",
            x.clone(),
            y.clone(),
            y.iter().map(|v| v * 2.0).collect(),
        ))
        .with_marker(Marker::new("m", -1.0, 5.0))
        .vline(0.0, "ignored")
        .hline(-2.0, "ignored");
    let paths = render(&fig, &dir.join("neg")).unwrap();
    assert!(paths.iter().all(|p| p.exists()));
    // Linear x with log y, and a dotted stem that must keep its dot.
    let fig = fig.scales(Scale::Linear, Scale::Log10);
    let paths = render(&fig, &dir.join("neg_0.5")).unwrap();
    assert!(paths[0].ends_with("neg_0.5.png"), "{:?}", paths[0]);
    assert!(paths.iter().all(|p| p.exists()));
}

#[test]
fn panels_and_segments() {
    let tmp = common::tmp_dir("plot-panels");
    let dir = tmp.path();
    let xs: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
    let figs: Vec<Figure> = [1.0, 1e3, 1e6]
        .iter()
        .map(|&eps| {
            let w: Vec<f64> = xs
                .iter()
                .map(|&x| -0.01 * x * x * (3.0 - x) / (1.0 + 1.0 / eps))
                .collect();
            Figure::new(format!("ε = {eps:e}"), "x [m]", "w [m]")
                .line("beam", xs.clone(), w)
                .segment((0.6, -0.025), (1.0, -0.025), 6)
                .vline(0.6, "obstacle")
        })
        .collect();
    let paths = render_panels(&figs, 3, &dir.join("beam"), (1800, 550)).unwrap();
    assert!(paths.iter().all(|p| p.exists()));
    if let Ok(keep) = std::env::var("PLOT_PANELS") {
        std::fs::copy(&paths[0], keep).unwrap();
    }
    assert!(render_panels(&figs, 0, &dir.join("x"), (800, 600)).is_err());
    assert!(render_panels(&[], 2, &dir.join("x"), (800, 600)).is_err());
}

#[test]
fn gallery_of_edge_cases() {
    let (_tmp, dir) = match std::env::var("PLOT_GALLERY") {
        Ok(d) => {
            std::fs::create_dir_all(&d).unwrap();
            (None, PathBuf::from(d))
        }
        Err(_) => {
            let tmp = common::tmp_dir("plot-gallery");
            let dir = tmp.path().to_path_buf();
            (Some(tmp), dir)
        }
    };
    // Linear axes with large values (scientific tick labels), points and a vline.
    let x: Vec<f64> = (0..30).map(|i| i as f64 * 1e5).collect();
    let y: Vec<f64> = x.iter().map(|v| 3e-4 * (v / 1e6).sin()).collect();
    let fig = Figure::new(
        "Linear, large/small values",
        "load F [N]",
        "displacement u [m]",
    )
    .points("measured", x.clone(), y.clone())
    .with_series(
        Series::new(
            "model",
            x,
            y.iter().map(|v| v * 0.9).collect(),
            Mark::Dashed,
        )
        .color(2),
    )
    .vline(1.5e6, "yield")
    .hline(0.0, "");
    render(&fig, &dir.join("linear_sci")).unwrap();
    // Narrow log range (no power of ten inside the data) on y, log x within a decade.
    let x: Vec<f64> = (0..10).map(|i| 2.0 + i as f64 * 0.6).collect();
    let y: Vec<f64> = x.iter().map(|v| 20.0 + v).collect();
    let fig = Figure::new("Narrow log ranges", "n", "time [ms]")
        .scales(Scale::Log10, Scale::Log10)
        .with_series(Series::new("t(n)", x, y, Mark::LinePoints));
    render(&fig, &dir.join("narrow_log")).unwrap();
    // Every glyph, on a line and alone, decimated.
    let mut fig = Figure::new("glyphs", "x", "y");
    for (k, g) in [
        Glyph::Circle,
        Glyph::Square,
        Glyph::Triangle,
        Glyph::TriangleDown,
        Glyph::Diamond,
        Glyph::Cross,
        Glyph::Plus,
        Glyph::Pentagon,
        Glyph::Star,
    ]
    .into_iter()
    .enumerate()
    {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y = x.iter().map(|v| v + k as f64).collect();
        let mark = if k % 2 == 0 {
            Mark::Points
        } else {
            Mark::LinePoints
        };
        fig = fig.with_series(
            Series::new(format!("{g:?}"), x, y, mark)
                .glyph(g)
                .glyph_every(k, 4),
        );
    }
    render(&fig, &dir.join("glyphs")).unwrap();
    // A single point, no title.
    let fig = Figure::new("", "x", "y").with_marker(Marker::new("only point", 1.0, 1.0));
    render(&fig, &dir.join("single")).unwrap();
}

/// One colour and one glyph per method everywhere: each distinct across the built-in
/// strategies, and the forming runs take the colour and glyph of the rule they use (the
/// matched classical run its own glyph, since it shares classical's colour).
#[test]
fn one_colour_per_method() {
    use penalty_lab::plot::{method_color, method_glyph, method_label};
    use penalty_lab::strategy::registry::BUILT_IN;
    let mut seen: Vec<usize> = BUILT_IN.iter().map(|s| method_color(s.name)).collect();
    seen.sort_unstable();
    seen.dedup();
    assert_eq!(seen.len(), BUILT_IN.len());
    assert_eq!(method_color("classical"), method_color("constant"));
    assert_eq!(method_color("adaptive"), method_color("paper"));
    assert!(method_label("paper").contains("Eq. 26"));
    assert_eq!(method_label("lagrange"), "lagrange");
    let mut glyphs: Vec<String> = BUILT_IN
        .iter()
        .map(|s| format!("{:?}", method_glyph(s.name)))
        .collect();
    glyphs.sort_unstable();
    glyphs.dedup();
    assert_eq!(glyphs.len(), BUILT_IN.len());
    assert_eq!(method_glyph("adaptive"), method_glyph("paper"));
    assert_ne!(method_glyph("classical-matched"), method_glyph("classical"));
}

/// No panel is squashed: a grid asked at a size whose cells would be strips grows to
/// [`MIN_PANEL`] per cell (the forming thickness-strain figure asked 2 rows in 520 px); a
/// size with room to spare is kept.
#[test]
fn panels_are_never_squashed() {
    use penalty_lab::plot::{panel_canvas, MIN_PANEL};
    assert_eq!(panel_canvas(2, 3, (1950, 520)), (1950, 2 * MIN_PANEL.1));
    assert_eq!(panel_canvas(1, 3, (1700, 700)), (1700, 700));
    assert_eq!(panel_canvas(3, 2, (400, 2000)), (2 * MIN_PANEL.0, 2000));
    // The image written has the grown size (PNG header: width, height at bytes 16..24).
    let dir = tempfile::tempdir().unwrap();
    let f = |k: usize| {
        Figure::new(format!("panel {k}"), "x", "y").with_series(Series::new(
            "s",
            vec![0.0, 1.0],
            vec![0.0, 1.0],
            Mark::Line,
        ))
    };
    let figs: Vec<Figure> = (0..5).map(f).collect();
    let files = render_panels(&figs, 3, &dir.path().join("grid"), (1950, 520)).unwrap();
    let png = std::fs::read(&files[0]).unwrap();
    let h = u32::from_be_bytes([png[20], png[21], png[22], png[23]]);
    assert_eq!(h, 2 * MIN_PANEL.1);
}
