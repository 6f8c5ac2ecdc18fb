//! The legend in the emptiest corner and the reference-line labels placed around it.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::*;

/// Where the legend box sits: a corner, or the middle of the right or left side (tried after
/// the corners, where every corner holds data).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Corner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
    MiddleRight,
    MiddleLeft,
}

impl Corner {
    const CORNERS: [Corner; 4] = [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
    ];
    const ALL: [Corner; 6] = [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
        Corner::MiddleRight,
        Corner::MiddleLeft,
    ];

    fn right(self) -> bool {
        matches!(
            self,
            Corner::UpperRight | Corner::LowerRight | Corner::MiddleRight
        )
    }

    /// The box's vertical extent in normalised plot coordinates for a legend `h` high.
    fn y_range(self, h: f64) -> (f64, f64) {
        match self {
            Corner::UpperRight | Corner::UpperLeft => (1.0 - h, 1.0),
            Corner::LowerRight | Corner::LowerLeft => (0.0, h),
            Corner::MiddleRight | Corner::MiddleLeft => (0.5 - 0.5 * h, 0.5 + 0.5 * h),
        }
    }
}

/// Corner whose legend-sized box (normalised size `w`×`h`) contains the fewest data samples.
pub(super) fn pick_corner(fig: &Figure, prep: &Prepared, w: f64, h: f64) -> Corner {
    corner_and_count(fig, prep, w, h).0
}

/// The legend's size in pixels, `None` without labels: the longest label plus the sample and
/// padding wide, one line per label plus padding high.
pub(super) fn legend_px(fig: &Figure, st: &Style) -> Option<(f64, f64)> {
    let labels: Vec<&str> = fig
        .bands
        .iter()
        .map(|b| b.label.as_str())
        .chain(fig.series.iter().map(|s| s.label.as_str()))
        .chain(fig.markers.iter().map(|m| m.label.as_str()))
        .filter(|l| !l.is_empty())
        .collect();
    if labels.is_empty() {
        return None;
    }
    let w = labels
        .iter()
        .map(|l| text_width(l, st.legend))
        .fold(0.0, f64::max)
        + 66.0 * st.s;
    let h = labels.len() as f64 * st.legend * 1.25 + 30.0 * st.s;
    Some((w, h))
}

/// The y range with headroom for the legend where every corner of `prep`'s range holds data
/// under a legend of normalised size `w`×`h`: the range grows upwards (downwards on the rare
/// figure whose lower band is the emptier) until the legend's band above (below) the data is
/// empty. Unchanged where a corner is free, or where the legend would take most of the height.
pub(super) fn with_legend_room(fig: &Figure, prep: &Prepared, w: f64, h: f64) -> Prepared {
    let (_, count) = corner_and_count(fig, prep, w, h);
    if count == 0 || h > 0.6 {
        return *prep;
    }
    // Growth frees a band at the top or the bottom: only the corners can use it.
    let (corner, _) = best_of(fig, prep, w, h, &Corner::CORNERS);
    let (a, b) = prep.yt;
    // The data keep the fraction 1 − h − 3 % of the new height.
    let grow = (b - a) / (1.0 - h - 0.03);
    let yt = match corner {
        Corner::LowerLeft | Corner::LowerRight => (b - grow, b),
        _ => (a, a + grow),
    };
    let back = |v: f64| match fig.y_scale {
        Scale::Linear => v,
        Scale::Log10 => 10f64.powf(v),
    };
    let y = (back(yt.0), back(yt.1));
    if !(y.0.is_finite() && y.1.is_finite() && y.0 < y.1) {
        return *prep;
    }
    Prepared { y, yt, ..*prep }
}

/// Whether a legend of normalised size `w`×`h` has a corner free of data (no room needed).
pub(super) fn legend_fits(fig: &Figure, prep: &Prepared, w: f64, h: f64) -> bool {
    corner_and_count(fig, prep, w, h).1 == 0
}

/// Sample points of everything drawn as data (series, bands, markers), in normalised plot
/// coordinates: what a legend or a label placed over them would hide.
fn data_samples(fig: &Figure, prep: &Prepared) -> Vec<(f64, f64)> {
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
    pts
}

/// A box `(x range, y range)` in normalised plot coordinates.
type Rect = ((f64, f64), (f64, f64));

/// Data samples inside the box `[a, b] × [c, d]` (normalised coordinates).
fn samples_in(pts: &[(f64, f64)], (a, b): (f64, f64), (c, d): (f64, f64)) -> usize {
    pts.iter()
        .filter(|&&(u, v)| u >= a && u <= b && v >= c && v <= d)
        .count()
}

/// Where along its line an hline label sits.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LabelAt {
    RightEnd,
    LeftEnd,
    /// Just inside the edge of a legend at one end.
    BesideLegend,
}

/// Where an hline label of width `w` and height `th` (normalised) at height `v` hides least:
/// its place, its box's x range (`beside`: the box beside a legend at one end, where there is
/// one) and whether it is above the line, by `cost` of its box (lowest first; ties keep the
/// earlier of right-above, left-above, right-below, left-below, beside-above, beside-below).
fn hline_label_place(
    v: f64,
    w: f64,
    th: f64,
    beside: Option<(f64, f64)>,
    cost: &impl Fn((f64, f64), (f64, f64)) -> (bool, usize),
) -> (LabelAt, (f64, f64), bool) {
    let right = (LabelAt::RightEnd, (1.0 - w, 1.0));
    let ends = [right, (LabelAt::LeftEnd, (0.0, w))];
    let at_ends = [true, false]
        .into_iter()
        .flat_map(move |up| ends.into_iter().map(move |(at, x)| (at, x, up)));
    let at_legend = beside
        .into_iter()
        .flat_map(|x| [true, false].map(|up| (LabelAt::BesideLegend, x, up)));
    // `min_by_key` keeps the first of equal costs: the order above is the preference.
    at_ends
        .chain(at_legend)
        .min_by_key(|&(_, x, up)| cost(x, if up { (v, v + th) } else { (v - th, v) }))
        .unwrap_or((right.0, right.1, true))
}

/// [`pick_corner`] with the number of data samples inside its legend box.
fn corner_and_count(fig: &Figure, prep: &Prepared, w: f64, h: f64) -> (Corner, usize) {
    best_of(fig, prep, w, h, &Corner::ALL)
}

/// The place among `places` whose `w`×`h` legend box holds the fewest data samples (the first
/// on ties).
fn best_of(fig: &Figure, prep: &Prepared, w: f64, h: f64, places: &[Corner]) -> (Corner, usize) {
    let pts = data_samples(fig, prep);
    let count = |c: Corner| {
        let (y0, y1) = c.y_range(h);
        pts.iter()
            .filter(|&&(u, v)| {
                let in_x = if c.right() { u >= 1.0 - w } else { u <= w };
                in_x && v >= y0 && v <= y1
            })
            .count()
    };
    places
        .iter()
        .map(|&c| (c, count(c)))
        .min_by_key(|&(_, n)| n)
        .unwrap_or((Corner::UpperRight, 0))
}

/// The legend in the emptiest corner; returns the corner and the legend's size in
/// normalised plot coordinates (0×0: no legend).
pub(super) fn draw_legend<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
) -> std::result::Result<(Corner, (f64, f64)), String> {
    // Legend in the emptiest corner.
    let (prx, pry) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = (
        (prx.end - prx.start).max(1) as f64,
        (pry.end - pry.start).max(1) as f64,
    );
    // Legend size in normalised plot coordinates (0×0: no legend).
    let mut legend_wh = (0.0, 0.0);
    let size = legend_px(fig, st);
    let corner = match size {
        None => Corner::UpperRight,
        Some((lw_px, lh_px)) => {
            legend_wh = (lw_px / pw, lh_px / ph);
            pick_corner(fig, prep, legend_wh.0, legend_wh.1)
        }
    };
    if size.is_some() {
        let pos = match corner {
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
            Corner::MiddleRight => SeriesLabelPosition::MiddleRight,
            Corner::MiddleLeft => SeriesLabelPosition::MiddleLeft,
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
            .map_err(area_err)?;
    }

    Ok((corner, legend_wh))
}

/// Reference-line labels where they hide least: an hline label at the right or left end,
/// above or below its line; a vline label right or left of its line, at the top or the
/// bottom — never over the legend or an earlier label where another place is free, then
/// over the fewest data samples (preferring right and above/top on ties).
pub(super) fn draw_reference_labels<'a, DB: DrawingBackend + 'a, X: Axis, Y: Axis>(
    chart: Chart<'_, 'a, DB, X, Y>,
    fig: &Figure,
    prep: &Prepared,
    st: &Style,
    (corner, legend_wh): (Corner, (f64, f64)),
) -> Drawn {
    let (xs, ys) = (fig.x_scale, fig.y_scale);
    let (prx, pry) = chart.plotting_area().get_pixel_range();
    let (pw, ph) = (
        (prx.end - prx.start).max(1) as f64,
        (pry.end - pry.start).max(1) as f64,
    );
    let legend_right = corner.right();
    let (ly0, ly1) = corner.y_range(legend_wh.1);
    let in_legend_x = |a: f64, b: f64| {
        if legend_right {
            b >= 1.0 - legend_wh.0
        } else {
            a <= legend_wh.0
        }
    };
    let in_legend_y = |a: f64, b: f64| a <= ly1 && b >= ly0;
    let gap = st.px(5.0);
    let tw = |l: &str| text_width(l, st.annot) / pw;
    let th = st.annot * 1.3 / ph;
    let pts = data_samples(fig, prep);
    // A candidate box's cost: covering the legend or a label already placed first, then the
    // data samples under it.
    let placed: std::cell::RefCell<Vec<Rect>> = Default::default();
    let cost = |x: (f64, f64), y: (f64, f64)| {
        let legend = legend_wh.0 > 0.0 && in_legend_x(x.0, x.1) && in_legend_y(y.0, y.1);
        let overlaps = placed
            .borrow()
            .iter()
            .any(|(px, py)| px.0 < x.1 && x.0 < px.1 && py.0 < y.1 && y.0 < py.1);
        (legend || overlaps, samples_in(&pts, x, y))
    };
    // The legend's inner edge, as a gap from the plot's side (its margin and a gap more).
    let legend_edge = legend_wh.0 + (st.px(8.0) + gap) as f64 / pw;
    for (y, label) in fig.hlines.iter().filter(|l| ok(ys, l.0) && !l.1.is_empty()) {
        let v = norm(fig, prep, (prep.x.0, *y)).1;
        let w = tw(label);
        let beside = (legend_wh.0 > 0.0 && legend_edge + w < 1.0).then_some(if legend_right {
            (1.0 - legend_edge - w, 1.0 - legend_edge)
        } else {
            (legend_edge, legend_edge + w)
        });
        let (at, xb, above) = hline_label_place(v, w, th, beside, &cost);
        placed
            .borrow_mut()
            .push((xb, if above { (v, v + th) } else { (v - th, v) }));
        // Anchored at a side of the plot, offset in pixels to the box's outer edge.
        let edge = (legend_edge * pw) as i32;
        let (x, dx, hp) = match at {
            LabelAt::RightEnd => (prep.x.1, -gap, HPos::Right),
            LabelAt::LeftEnd => (prep.x.0, gap, HPos::Left),
            LabelAt::BesideLegend if legend_right => (prep.x.1, -edge, HPos::Right),
            LabelAt::BesideLegend => (prep.x.0, edge, HPos::Left),
        };
        let (dy, vp) = if above {
            (-gap / 2, VPos::Bottom)
        } else {
            (gap / 2, VPos::Top)
        };
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((x, *y))
                    + Text::new(
                        label.clone(),
                        (dx, dy),
                        font(st.annot).color(&REF_GREY).pos(Pos::new(hp, vp)),
                    ),
            ))
            .map_err(area_err)?;
    }
    for (x, label) in fig.vlines.iter().filter(|l| ok(xs, l.0) && !l.1.is_empty()) {
        let u = norm(fig, prep, (*x, prep.y.0)).0;
        let w = tw(label);
        // Right or left of the line (not out of the plot), at the top or the bottom: the
        // candidate that hides least.
        let (right, top) = [(true, true), (false, true), (true, false), (false, false)]
            .into_iter()
            .filter(|&(r, _)| if r { u + w < 0.98 } else { u - w > 0.02 })
            .min_by_key(|&(r, t)| {
                let xb = if r { (u, u + w) } else { (u - w, u) };
                let yb = if t { (1.0 - th, 1.0) } else { (0.0, th) };
                cost(xb, yb)
            })
            .unwrap_or((u + w < 0.98, true));
        placed.borrow_mut().push((
            if right { (u, u + w) } else { (u - w, u) },
            if top { (1.0 - th, 1.0) } else { (0.0, th) },
        ));
        let (dx, hp) = if right {
            (gap, HPos::Left)
        } else {
            (-gap, HPos::Right)
        };
        let (y, dy, vp) = if top {
            (prep.y.1, gap, VPos::Top)
        } else {
            (prep.y.0, -gap, VPos::Bottom)
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
            .map_err(area_err)?;
    }

    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An hline label goes where no curve runs: a curve over the right end above the line
    /// sends it to the left end; curves above at both ends send it below; no data keeps it at
    /// the right end above.
    #[test]
    fn reference_labels_avoid_curves() {
        let (v, w, th) = (0.5, 0.3, 0.05);
        let line = |x0: f64, x1: f64, y: f64| -> Vec<(f64, f64)> {
            (0..=50)
                .map(|k| (x0 + (x1 - x0) * k as f64 / 50.0, y))
                .collect()
        };
        let right = (LabelAt::RightEnd, (1.0 - w, 1.0));
        let left = (LabelAt::LeftEnd, (0.0, w));
        let place = |pts: Vec<(f64, f64)>| {
            let (at, x, up) =
                hline_label_place(v, w, th, None, &|x, y| (false, samples_in(&pts, x, y)));
            ((at, x), up)
        };
        assert_eq!(place(vec![]), (right, true));
        assert_eq!(place(line(0.6, 1.0, 0.52)), (left, true));
        let mut both = line(0.0, 1.0, 0.52);
        both.extend(line(0.0, 1.0, 0.53));
        assert_eq!(place(both.clone()), (right, false));
        // The legend outranks any number of samples.
        let legend_right_above = |x: (f64, f64), y: (f64, f64)| (x.1 > 0.9 && y.0 >= v, 0);
        assert_eq!(
            hline_label_place(v, w, th, None, &legend_right_above),
            (left.0, left.1, true)
        );
        // A legend over the right end, data over the left end: beside the legend, where
        // nothing runs (the contact benchmark's leaderboard).
        let beside = (0.35, 0.65);
        let legend_right = |x: (f64, f64), y: (f64, f64)| {
            let legend = x.1 > 0.7 && y.1 >= 0.4;
            let data =
                samples_in(&line(0.0, 0.2, 0.51), x, y) + samples_in(&line(0.0, 0.2, 0.47), x, y);
            (legend, data)
        };
        assert_eq!(
            hline_label_place(v, w, th, Some(beside), &legend_right),
            (LabelAt::BesideLegend, beside, true)
        );
        // Where an end is free, it is kept over the place beside the legend.
        assert_eq!(
            hline_label_place(v, w, th, Some(beside), &|x, y| (
                false,
                samples_in(&both, x, y)
            )),
            (right.0, right.1, false)
        );
    }

    /// Data in every corner (a line from corner to corner and back): the legend gets a band
    /// of its own above the data, where no sample lies; a figure with a free corner keeps its
    /// range.
    #[test]
    fn legend_room_frees_a_corner() {
        let zigzag = Series::new(
            "a long legend label for the zigzag series",
            vec![0.0, 1.0, 2.0, 3.0, 4.0],
            vec![0.0, 10.0, 0.0, 10.0, 0.0],
            Mark::Line,
        );
        let fig = Figure::new("t", "x", "y").with_series(zigzag.clone());
        let prep = axes::prepare(&fig).unwrap();
        let (w, h) = (0.5, 0.2);
        assert!(corner_and_count(&fig, &prep, w, h).1 > 0);
        let room = with_legend_room(&fig, &prep, w, h);
        assert!(room.y.1 > prep.y.1 && room.y.0 == prep.y.0);
        assert_eq!(corner_and_count(&fig, &room, w, h).1, 0);
        let free = Figure::new("t", "x", "y").with_series(Series::new(
            "rising",
            vec![0.0, 1.0],
            vec![0.0, 1.0],
            Mark::Line,
        ));
        let prep = axes::prepare(&free).unwrap();
        assert_eq!(with_legend_room(&free, &prep, 0.3, 0.2).y, prep.y);
    }

    /// Data in all four corners and none in the middle of a side: the legend goes to the
    /// middle (right first) and the y range is not grown (the contact benchmark's leaderboard
    /// panel once reached 1e-24 for its legend's band).
    #[test]
    fn legend_takes_a_free_side_middle() {
        let corners = Series::new(
            "points in the four corners",
            vec![0.0, 0.0, 1.0, 1.0],
            vec![0.0, 1.0, 0.0, 1.0],
            Mark::Points,
        );
        let fig = Figure::new("t", "x", "y").with_series(corners);
        let prep = axes::prepare(&fig).unwrap();
        let (w, h) = (0.3, 0.3);
        assert!(best_of(&fig, &prep, w, h, &Corner::CORNERS).1 > 0);
        assert_eq!(
            corner_and_count(&fig, &prep, w, h),
            (Corner::MiddleRight, 0)
        );
        assert_eq!(with_legend_room(&fig, &prep, w, h).y, prep.y);
    }
}
