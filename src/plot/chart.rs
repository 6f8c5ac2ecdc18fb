//! Drawing one chart: title, mesh, bands, lines, marks, markers, frame.

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::*;

// ---------------------------------------------------------------------------------------------
// Drawing
// ---------------------------------------------------------------------------------------------

/// The legend's size as a fraction of the plotting area of a `cell` px panel, from the area
/// the margins leave (estimated: the y tick labels' width is not known yet); None without
/// labels or room.
pub(super) fn legend_fraction(fig: &Figure, cell: (f64, f64), scale: f64) -> Option<(f64, f64)> {
    let st = Style::new(scale);
    let title_h = if fig.title.is_empty() {
        0.0
    } else {
        (st.title * 1.9).trunc()
    };
    let plot_w = cell.0 - (st.tick * 5.0 + 60.0 * scale);
    let plot_h = cell.1 - title_h - (st.label * 3.5 + st.tick * 1.7 + 6.0 * scale);
    let (lw, lh) = legend_px(fig, &st)?;
    (plot_w > 0.0 && plot_h > 0.0).then(|| (lw / plot_w, lh / plot_h))
}

pub(super) fn draw_figure<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fig: &Figure,
    prep: &Prepared,
    scale: f64,
) -> Drawn {
    let (w, h) = area.dim_in_pixel();
    let st = Style::new(scale);
    let title_h = if fig.title.is_empty() {
        0
    } else {
        (st.title * 1.9) as i32
    };
    let n_x = ((w as f64 / (85.0 * scale)) as usize).clamp(3, 10);
    let n_y = (((h as i32 - title_h) as f64 / (65.0 * scale)) as usize).clamp(3, 10);
    // Room for the legend where it would cover data in every corner.
    let room;
    let prep = match legend_fraction(fig, (w as f64, h as f64), scale) {
        Some((lw, lh)) => {
            room = with_legend_room(fig, prep, lw, lh);
            &room
        }
        None => prep,
    };
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
pub(super) struct Layout {
    pub(super) st: Style,
    pub(super) title_h: i32,
    pub(super) n_x: usize,
    pub(super) n_y: usize,
}

/// Splits `(x, y)` pairs into runs of consecutive drawable points.
pub(super) fn runs(
    xs: Scale,
    ys: Scale,
    pts: impl Iterator<Item = (f64, f64)>,
) -> Vec<Vec<(f64, f64)>> {
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
pub(super) fn band_runs(fig: &Figure, b: &Band) -> Vec<Vec<(f64, f64, f64)>> {
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

/// Normalised position (0..1 on both axes, y up) of a data point.
pub(super) fn norm(fig: &Figure, prep: &Prepared, (x, y): (f64, f64)) -> (f64, f64) {
    (
        (tr(fig.x_scale, x) - prep.xt.0) / (prep.xt.1 - prep.xt.0),
        (tr(fig.y_scale, y) - prep.yt.0) / (prep.yt.1 - prep.yt.0),
    )
}

/// Sample points (normalised coordinates) along a polyline, about 100 per unit length.
pub(super) fn sample_polyline(pts: &[(f64, f64)], out: &mut Vec<(f64, f64)>) {
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

#[allow(clippy::too_many_arguments)]
pub(super) fn draw_chart<DB, XS, YS>(
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
        .map_err(area_err)?;
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
        .map_err(area_err)?;

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
        mesh.draw().map_err(area_err)?;
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
    .map_err(area_err)?;
    if !fig.y_label.is_empty() {
        let x = (ax0 - y_area as i32 + st.px(4.0)).max(st.px(4.0));
        area.draw(&Text::new(
            fig.y_label.as_str(),
            (x, ay0 - st.px(8.0)),
            font(st.label).pos(Pos::new(HPos::Left, VPos::Bottom)),
        ))
        .map_err(area_err)?;
    }
    Ok(())
}

/// An axis of the plotting area: linear or log over f64.
pub(super) trait Axis: Ranged<ValueType = f64> {}
impl<T: Ranged<ValueType = f64>> Axis for T {}

/// The plotting area the `draw_*` functions paint on.
pub(super) type Chart<'c, 'a, DB, X, Y> = &'c mut ChartContext<'a, DB, Cartesian2d<X, Y>>;

/// What a `draw_*` function returns: nothing, or the backend's error as text.
pub(super) type Drawn = std::result::Result<(), String>;

/// Spread bands: filled polygons between their lower and upper curves, with edges.
pub(super) fn draw_bands<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    st: &Style,
) -> Drawn {
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
        let anno = chart.draw_series(polys).map_err(area_err)?;
        if !b.label.is_empty() {
            let r = st.px(7.0);
            let len = st.legend_sample();
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
                    .map_err(area_err)?;
            }
        }
    }

    Ok(())
}

/// Coloured segments and the dashed reference lines (their labels come after the legend).
pub(super) fn draw_lines<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
) -> Drawn {
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let seg_w = st.px(3.0).max(1) as u32;
    chart
        .draw_series(
            fig.segments
                .iter()
                .filter(|(a, b, _)| ok(xs, a.0) && ok(ys, a.1) && ok(xs, b.0) && ok(ys, b.1))
                .map(|&(a, b, ci)| PathElement::new(vec![a, b], pal(ci).stroke_width(seg_w))),
        )
        .map_err(area_err)?;

    // Reference lines (labels are written later, away from the legend).
    let dash = st.dash();
    let ref_style = REF_GREY.stroke_width(st.px(1.5).max(1) as u32);
    for (y, _) in fig.hlines.iter().filter(|l| ok(ys, l.0)) {
        chart
            .draw_series(std::iter::once(DashedPathElement::new(
                vec![(prep.x.0, *y), (prep.x.1, *y)],
                dash.0,
                dash.1,
                ref_style,
            )))
            .map_err(area_err)?;
    }
    for (x, _) in fig.vlines.iter().filter(|l| ok(xs, l.0)) {
        chart
            .draw_series(std::iter::once(DashedPathElement::new(
                vec![(*x, prep.y.0), (*x, prep.y.1)],
                dash.0,
                dash.1,
                ref_style,
            )))
            .map_err(area_err)?;
    }

    Ok(())
}

/// The data series in their marks, each with its legend entry.
pub(super) fn draw_marks<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    st: &Style,
) -> Drawn {
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let lw = st.line_width();
    let dash = st.dash();
    let len = st.legend_sample();
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
                    .map_err(area_err)?;
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
                    .map_err(area_err)?;
                if has_label {
                    let d = (dash.0 as i32, dash.1 as i32);
                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (d.0, 0)], line)
                            + PathElement::new(vec![(d.0 + d.1, 0), (len, 0)], line)
                    });
                }
            }
            Mark::Points | Mark::LinePoints => {
                if s.mark == Mark::LinePoints {
                    chart
                        .draw_series(rs.iter().map(|r| PathElement::new(r.clone(), line)))
                        .map_err(area_err)?;
                }
                let shape = glyph_outline(s.glyph, pr);
                let (offset, stride) = s.glyph_every;
                let at = s.x.iter().zip(&s.y).enumerate().filter(|&(k, (&x, &y))| {
                    k % stride.max(1) == offset
                        && ok(xs, x)
                        && ok(ys, y)
                        && x.is_finite()
                        && y.is_finite()
                });
                let anno = chart
                    .draw_series(at.map(|(_, (&x, &y))| {
                        EmptyElement::at((x, y)) + Polygon::new(shape.clone(), c.filled())
                    }))
                    .map_err(area_err)?;
                if has_label {
                    let (with_line, glyph) = (s.mark == Mark::LinePoints, s.glyph);
                    anno.label(s.label.as_str()).legend(move |(x, y)| {
                        let stroke = if with_line { len } else { 0 };
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (stroke, 0)], line)
                            + Polygon::new(
                                glyph_outline(glyph, pr)
                                    .into_iter()
                                    .map(|(a, b)| (a + len / 2, b))
                                    .collect::<Vec<_>>(),
                                c.filled(),
                            )
                    });
                }
            }
        }
    }

    Ok(())
}

/// The outline of a glyph of half-size `r` px, as pixel offsets from its centre (y down);
/// every shape has about the area of a circle of radius `r`.
pub(super) fn glyph_outline(g: Glyph, r: i32) -> Vec<(i32, i32)> {
    let rf = r as f64;
    let polar = |n: usize, rad: f64, phase: f64| -> Vec<(i32, i32)> {
        (0..n)
            .map(|k| {
                let t = phase + std::f64::consts::TAU * k as f64 / n as f64;
                (
                    (rad * t.cos()).round() as i32,
                    (-rad * t.sin()).round() as i32,
                )
            })
            .collect()
    };
    let half = std::f64::consts::FRAC_PI_2;
    match g {
        Glyph::Circle => polar(16, rf, 0.0),
        Glyph::Square => polar(4, rf * 1.25, half / 2.0),
        Glyph::Diamond => polar(4, rf * 1.3, 0.0),
        Glyph::Triangle => polar(3, rf * 1.45, half),
        Glyph::TriangleDown => polar(3, rf * 1.45, -half),
        Glyph::Pentagon => polar(5, rf * 1.15, half),
        Glyph::Star => (0..10)
            .map(|k| {
                let rad = if k % 2 == 0 { rf * 1.6 } else { rf * 0.65 };
                let t = half + std::f64::consts::TAU * k as f64 / 10.0;
                (
                    (rad * t.cos()).round() as i32,
                    (-rad * t.sin()).round() as i32,
                )
            })
            .collect(),
        Glyph::Plus | Glyph::Cross => {
            // A plus of arm half-width w, turned by 45° for the cross.
            let (a, w) = (rf * 1.35, rf * 0.45);
            let plus = [
                (w, a),
                (w, w),
                (a, w),
                (a, -w),
                (w, -w),
                (w, -a),
                (-w, -a),
                (-w, -w),
                (-a, -w),
                (-a, w),
                (-w, w),
                (-w, a),
            ];
            let turn = if g == Glyph::Cross { half / 2.0 } else { 0.0 };
            let (sn, cs) = turn.sin_cos();
            plus.iter()
                .map(|&(x, y)| {
                    (
                        (x * cs - y * sn).round() as i32,
                        (x * sn + y * cs).round() as i32,
                    )
                })
                .collect()
        }
    }
}

/// Markers: diamonds with a black outline.
pub(super) fn draw_markers<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    st: &Style,
) -> Drawn {
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let len = st.legend_sample();
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
            .map_err(area_err)?;
        if !m.label.is_empty() {
            anno.label(m.label.as_str()).legend(move |(x, y)| {
                let (poly, outline) = diamond(c);
                EmptyElement::at((x + len / 2, y)) + poly + outline
            });
        }
    }

    Ok(())
}
