//! SVG plots for the reports, drawn with plotters into a string (no files, no fonts needed:
//! the SVG backend writes text as `<text>` elements).
//!
//! Two shapes cover every family: [`panels`] — one or more side-by-side x–y panels of
//! lines, point sets and labelled markers (curves against crank angle, a force locus with
//! equal axes, a Pareto front, a jib-head path) — and [`heat_map`] — a scalar field on a
//! regular grid with overlaid curves and markers (Δh over (k1, k2), C4 over (λ, θ)). A
//! batch's summary adds [`bars`], a histogram of counted bins.
//!
//! Every document is drawn at [`S`] times its nominal size and given its nominal `width` and
//! `height` with the drawing's `viewBox`: plotters writes whole-number coordinates, so this
//! gives curves 1/S-pixel resolution instead of whole-pixel steps. Tick labels are the
//! shortest decimal of the value (`600`, not `600.0`; never `-0`); a legend goes to the
//! corner with the fewest data points under it; an equal-aspect panel has the same length per
//! pixel on both axes (a circle is round); a heat map has a colour bar.
//!
//! A plot of panels is also its data ([`Figure`]: the panels with their size, and its JSON
//! for `cwsynth serve`'s page, which draws them itself: [`Panel::to_json`]).

/// Why a plot could not be drawn (a report shows the reason in place of the picture).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlotError {
    /// plotters failed to draw (its message).
    #[error("drawing failed: {0}")]
    Draw(String),
    /// The data cannot make this plot (a grid too small, a geometry that does not exist).
    #[error("{0}")]
    Data(String),
}

impl PlotError {
    /// A plotters error as a [`PlotError::Draw`].
    fn draw(e: impl std::fmt::Display) -> PlotError {
        PlotError::Draw(e.to_string())
    }

    /// Any error of the data behind a plot as a [`PlotError::Data`].
    pub fn data(e: impl std::fmt::Display) -> PlotError {
        PlotError::Data(e.to_string())
    }
}

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A polyline; a non-finite point breaks the line (for excluded windows, poles).
    Line,
    /// Dots.
    Points,
    /// Large crosses with the series name in the legend (optima, the paper's design).
    Marker,
    /// A marked point labelled in the plot with the series name beside it (a peak with its
    /// value), not in the legend.
    Peak,
}

/// One data series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

impl Series {
    /// A line series.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.into(),
            points,
            style: Style::Line,
        }
    }
    /// A marker series.
    pub fn marker(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.into(),
            points,
            style: Style::Marker,
        }
    }
    /// A labelled peak: a ring at each point with `label` written beside it.
    pub fn peak(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: label.into(),
            points,
            style: Style::Peak,
        }
    }
    /// A point series.
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Series {
            name: name.into(),
            points,
            style: Style::Points,
        }
    }
}

/// One x–y panel.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Caption.
    pub title: String,
    /// x axis label (with unit).
    pub x_label: String,
    /// y axis label (with unit).
    pub y_label: String,
    /// The data.
    pub series: Vec<Series>,
    /// Same scale on both axes (a locus, a path).
    pub equal_aspect: bool,
}

impl Style {
    /// The JSON spelling (`line`, `points`, `marker`, `peak`).
    pub fn as_str(self) -> &'static str {
        match self {
            Style::Line => "line",
            Style::Points => "points",
            Style::Marker => "marker",
            Style::Peak => "peak",
        }
    }
}

impl Series {
    /// `{"name", "style", "x": […], "y": […]}`, a non-finite coordinate as `null`.
    pub fn to_json(&self) -> serde_json::Value {
        let finite = |v: f64| v.is_finite().then_some(v);
        let x: Vec<Option<f64>> = self.points.iter().map(|p| finite(p.0)).collect();
        let y: Vec<Option<f64>> = self.points.iter().map(|p| finite(p.1)).collect();
        serde_json::json!({"name": self.name, "style": self.style.as_str(), "x": x, "y": y})
    }
}

impl Panel {
    /// The x axis is an angle in degrees (its unit `deg` or `°`): in every family the
    /// mechanism's input angle, the angle of its motion's frames (the page's slider).
    pub fn x_is_angle(&self) -> bool {
        matches!(unit_of(&self.x_label), Some("deg" | "°"))
    }

    /// `{"title", "x_label", "y_label", "equal_aspect", "angle_x", "series": […]}`
    /// ([`Series::to_json`]; `angle_x`: [`Panel::x_is_angle`]).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "title": self.title,
            "x_label": self.x_label,
            "y_label": self.y_label,
            "equal_aspect": self.equal_aspect,
            "angle_x": self.x_is_angle(),
            "series": self.series.iter().map(Series::to_json).collect::<Vec<_>>(),
        })
    }
}

/// A plot's data: side-by-side panels, each `width`×`height` nominal pixels
/// ([`crate::report::Plot::figure`]).
#[derive(Debug, Clone)]
pub struct Figure {
    /// The panels, left to right.
    pub panels: Vec<Panel>,
    /// Each panel's nominal width (px).
    pub width: u32,
    /// Each panel's nominal height (px).
    pub height: u32,
}

impl Figure {
    /// `panels` of `width`×`height` each, every axis label with its unit ([`has_unit`]).
    pub fn new(panels: Vec<Panel>, width: u32, height: u32) -> Result<Figure, PlotError> {
        for p in &panels {
            has_unit(&p.x_label)?;
            has_unit(&p.y_label)?;
        }
        Ok(Figure {
            panels,
            width,
            height,
        })
    }

    /// The SVG document the report writes ([`panels`]).
    pub fn svg(&self) -> Result<String, PlotError> {
        panels(&self.panels, self.width, self.height)
    }

    /// `{"width", "height", "panels": […]}` ([`Panel::to_json`]).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "width": self.width,
            "height": self.height,
            "panels": self.panels.iter().map(Panel::to_json).collect::<Vec<_>>(),
        })
    }
}

/// The text in a label's first parentheses, trimmed (`"|F| (N)"` → `N`).
fn unit_of(label: &str) -> Option<&str> {
    let a = label.find('(')?;
    let b = label[a + 1..].find(')')?;
    Some(label[a + 1..a + 1 + b].trim())
}

/// Every axis label names its unit in parentheses (`"|F| (N)"`, `"λ = R/L (–)"` for a pure
/// number): an axis without one is an error of the plot, not a guess left to the reader.
pub fn has_unit(label: &str) -> Result<(), PlotError> {
    match unit_of(label) {
        Some(u) if !u.is_empty() => Ok(()),
        _ => Err(PlotError::Data(format!(
            "the axis label `{label}` names no unit; write it as `quantity (unit)`, `(–)` for a pure number"
        ))),
    }
}

/// The drawing scale (see the module doc).
pub const S: u32 = 4;

/// `v` nominal pixels at the drawing scale.
fn px(v: u32) -> u32 {
    v * S
}

/// `v` nominal pixels at the drawing scale, signed.
fn pxi(v: i32) -> i32 {
    v * S as i32
}

/// A font of `size` nominal pixels.
fn font(size: u32) -> (&'static str, u32) {
    ("sans-serif", px(size))
}

/// The document drawn at S× as one of nominal size `w`×`h` (its `viewBox` unchanged).
fn finish(buf: String, w: u32, h: u32) -> String {
    let from = format!("<svg width=\"{}\" height=\"{}\"", px(w), px(h));
    buf.replacen(&from, &format!("<svg width=\"{w}\" height=\"{h}\""), 1)
}

/// [`tick`] on an axis spanning `span`: a value within 1e-9·span of 0 is 0 (a tick computed
/// as 0.1 + 0.2 − 0.3 is not written 5.55e-17).
pub fn tick_on(v: f64, span: f64) -> String {
    tick(&if v.abs() <= 1e-9 * span.abs() { 0.0 } else { v })
}

/// A tick label: the value with at most 6 significant digits, trailing zeros dropped
/// (`600`, `0.25`, `1.5e-7`), and no `-0`.
pub fn tick(v: &f64) -> String {
    let v = *v;
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".into()
        } else {
            v.to_string()
        };
    }
    let a = v.abs();
    let s = if (1e-4..1e6).contains(&a) {
        // Six significant digits in fixed notation, then trimmed.
        let decimals = (5 - a.log10().floor() as i32).clamp(0, 10) as usize;
        let t = format!("{v:.decimals$}");
        let t = if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        };
        t
    } else {
        let t = format!("{v:.5e}");
        let (m, e) = t.split_once('e').unwrap_or((&t, "0"));
        let m = if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.')
        } else {
            m
        };
        format!("{m}e{e}")
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// The corner for the legend over data in `x`×`y` (plot area `w`×`h` pixels): the one whose
/// legend box covers the fewest points of the data (a line's segments sampled between its
/// vertices; upper right on a tie), that count, and the box's height as a fraction of the
/// area's (for the headroom that clears it, [`draw_panel`]).
/// The legend box's size in pixels at the drawing scale: 40 px + 7 px per character of the
/// longest entry wide, 18 px per entry + 10 tall (nominal), the peaks not listed.
fn legend_size(series: &[Series]) -> (f64, f64) {
    let listed = series.iter().filter(|s| s.style != Style::Peak);
    let longest = listed
        .clone()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0) as f64;
    (
        (40.0 + 7.0 * longest) * S as f64,
        (10.0 + 18.0 * listed.count() as f64) * S as f64,
    )
}

fn legend_corner(
    series: &[Series],
    x: (f64, f64),
    y: (f64, f64),
    w: u32,
    h: u32,
) -> (SeriesLabelPosition, usize, f64) {
    let (lw, lh) = legend_size(series);
    let bw = (lw / w.max(1) as f64).min(1.0);
    let bh = (lh / h.max(1) as f64).min(1.0);
    // Every vertex, and 7 points between consecutive vertices of a line.
    let points: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| {
            let line = s.style == Style::Line;
            s.points.iter().enumerate().flat_map(move |(i, &p)| {
                let next = if line {
                    s.points.get(i + 1).copied()
                } else {
                    None
                };
                (0..if next.is_some() { 8 } else { 1 }).map(move |k| match next {
                    Some(q) => {
                        let t = k as f64 / 8.0;
                        (p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1))
                    }
                    None => p,
                })
            })
        })
        .collect();
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            (1.0 - bw, 1.0),
            (1.0 - bh, 1.0),
        ),
        (SeriesLabelPosition::UpperLeft, (0.0, bw), (1.0 - bh, 1.0)),
        (SeriesLabelPosition::LowerRight, (1.0 - bw, 1.0), (0.0, bh)),
        (SeriesLabelPosition::LowerLeft, (0.0, bw), (0.0, bh)),
    ];
    let count = |(fx, fy): ((f64, f64), (f64, f64))| {
        points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .filter(|p| {
                let u = (p.0 - x.0) / (x.1 - x.0);
                let v = (p.1 - y.0) / (y.1 - y.0);
                u >= fx.0 && u <= fx.1 && v >= fy.0 && v <= fy.1
            })
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, fx, fy) in corners {
        let c = count((fx, fy));
        if c < best.0 {
            best = (c, pos);
        }
    }
    (best.1, best.0, bh)
}

/// The series colours, by index (Tableau 10): ten before a colour repeats (the six-bar
/// press's nine load cases at the band's ends each get their own).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

fn bounds(series: &[Series], equal: bool) -> ((f64, f64), (f64, f64)) {
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = |a: f64, b: f64| {
        let w = (b - a).abs().max(1e-12 * a.abs().max(b.abs())).max(1e-300);
        (a - 0.05 * w, b + 0.05 * w)
    };
    let (mut xr, mut yr) = (pad(x0, x1), pad(y0, y1));
    if equal {
        let w = (xr.1 - xr.0).max(yr.1 - yr.0);
        let (cx, cy) = (0.5 * (xr.0 + xr.1), 0.5 * (yr.0 + yr.1));
        xr = (cx - 0.5 * w, cx + 0.5 * w);
        yr = (cy - 0.5 * w, cy + 0.5 * w);
    }
    (xr, yr)
}

/// A panel's x coordinate: plotters' own for f64, with its tick positions replaced where
/// [`angle_ticks`] gives them. Hand-written because plotters' `WithKeyPoints` over an f64 range
/// has no value formatter, which the mesh needs.
struct XAxis {
    inner: RangedCoordf64,
    /// (bold ticks, light lines), if not plotters' own.
    ticks: Option<(Vec<f64>, Vec<f64>)>,
}

impl Ranged for XAxis {
    type ValueType = f64;
    type FormatOption = DefaultFormatting;

    fn range(&self) -> std::ops::Range<f64> {
        self.inner.range()
    }

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(v, limit)
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        match &self.ticks {
            Some((_, light)) if hint.weight().allow_light_points() => light.clone(),
            Some((bold, _)) => bold.clone(),
            None => self.inner.key_points(hint),
        }
    }

    fn axis_pixel_range(&self, limit: (i32, i32)) -> std::ops::Range<i32> {
        self.inner.axis_pixel_range(limit)
    }
}

/// The chart of a panel on `area` with data ranges `x`×`y`, the x axis's ticks from
/// [`angle_ticks`] where it gives them.
fn chart_on<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    p: &Panel,
    x: (f64, f64),
    y: (f64, f64),
    ticks: Option<(Vec<f64>, Vec<f64>)>,
) -> Result<ChartContext<'a, SVGBackend<'b>, Cartesian2d<XAxis, RangedCoordf64>>, PlotError> {
    let x = XAxis {
        inner: (x.0..x.1).into(),
        ticks,
    };
    ChartBuilder::on(area)
        .caption(&p.title, font(20))
        .margin(px(12))
        .x_label_area_size(px(44))
        .y_label_area_size(px(74))
        .build_cartesian_2d(x, y.0..y.1)
        .map_err(PlotError::draw)
}

/// A panel whose x axis is an angle in degrees over (about) one turn — the crank, carrier or
/// gear angle of a cycle — gets its range on whole quarter turns and ticks at every quarter
/// turn (0, 90, 180, 270, 360°, the angles a designer reads dead centres and quadrature at),
/// with light lines every 30°: `Some((x range, bold ticks, light ticks))`. Other axes: `None`
/// (plotters' own ticks).
fn angle_ticks(p: &Panel, x: (f64, f64)) -> Option<((f64, f64), Vec<f64>, Vec<f64>)> {
    let label = p.x_label.to_lowercase();
    let degrees = label.ends_with("(deg)") || label.ends_with("(°)");
    if !(label.contains("angle") && degrees) || p.equal_aspect {
        return None;
    }
    // The data's own range (without the 5 % padding of `bounds`).
    let w = (x.1 - x.0) / 1.1;
    let (lo, hi) = (x.0 + 0.05 * w, x.1 - 0.05 * w);
    if !(w >= 270.0 && w <= 720.0 + 1e-9) {
        return None;
    }
    let q = 90.0;
    let (a, b) = ((lo / q + 1e-9).floor() * q, (hi / q - 1e-9).ceil() * q);
    let every = |step: f64| {
        let n = ((b - a) / step).round() as usize;
        (0..=n).map(|k| a + k as f64 * step).collect::<Vec<_>>()
    };
    Some(((a, b), every(q), every(30.0)))
}

/// Each peak's label beside its ring ([`peak_label_box`]), the peaks taken from the top of
/// the plot down so that stacked labels keep their points' order, clear of every ring and of
/// the labels before them.
fn label_peaks(
    chart: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<XAxis, RangedCoordf64>>,
    peaks: &[((f64, f64), &str)],
    (lw, lh): (f64, f64),
    corner: &SeriesLabelPosition,
) -> Result<(), PlotError> {
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let area = [xr.start, yr.start, xr.end, yr.end].map(f64::from);
    // The legend's box in its corner (with its margin), which no label covers either.
    let m = f64::from(px(6));
    let (l, t, r, b) = (area[0] + m, area[1] + m, area[2] - m, area[3] - m);
    let legend = match corner {
        SeriesLabelPosition::UpperLeft => [l, t, l + lw, t + lh],
        SeriesLabelPosition::LowerRight => [r - lw, b - lh, r, b],
        SeriesLabelPosition::LowerLeft => [l, b - lh, l + lw, b],
        _ => [r - lw, t, r, t + lh],
    };
    let mut at: Vec<((f64, f64), (f64, f64), &str)> = peaks
        .iter()
        .map(|&(q, name)| {
            let (x, y) = chart.backend_coord(&q);
            (q, (f64::from(x), f64::from(y)), name)
        })
        .collect();
    at.sort_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
    // The rings (radius 6 px and their stroke), which no label covers.
    let r = f64::from(pxi(7));
    let mut placed: Vec<[f64; 4]> = at
        .iter()
        .map(|(_, (x, y), _)| [x - r, y - r, x + r, y + r])
        .chain(std::iter::once(legend))
        .collect();
    let c = RGBColor(20, 20, 20);
    for (q, p, name) in at {
        // The text's size: sans-serif at 12 px averages about 0.56 em a character.
        let size = (
            0.56 * f64::from(px(12)) * name.chars().count() as f64,
            1.25 * f64::from(px(12)),
        );
        let b = peak_label_box(p, size, area, &placed, f64::from(pxi(9)));
        placed.push(b);
        chart
            .draw_series(std::iter::once(
                EmptyElement::at(q)
                    + Text::new(
                        name.to_string(),
                        ((b[0] - p.0) as i32, (b[1] - p.1) as i32),
                        font(12)
                            .into_font()
                            .color(&c)
                            .pos(Pos::new(HPos::Left, VPos::Top)),
                    ),
            ))
            .map_err(PlotError::draw)?;
    }
    Ok(())
}

/// The box [left, top, right, bottom] of a peak's label (pixels, y down) beside its ring at
/// `at`, the text `size` (w, h), inside the plotting `area` [l, t, r, b], clear of the
/// labels already `placed`, `gap` from the point: right of the point where the text fits,
/// else left of it, else as far right as the area lets it start; below a point in the upper
/// half of the area and above one in the lower half (towards the middle, where there is
/// room, and clear of the caption above the plot). A box that overlaps a placed one moves
/// one line further (down below the point, up above it), at most four times, and never out
/// of the area. The page's charts place their labels the same way
/// (`src/serve/assets/plots.js`, `labelBox`).
pub fn peak_label_box(
    at: (f64, f64),
    size: (f64, f64),
    area: [f64; 4],
    placed: &[[f64; 4]],
    gap: f64,
) -> [f64; 4] {
    let (w, h) = size;
    let [l, t, r, b] = area;
    let left = if at.0 + gap + w <= r {
        at.0 + gap
    } else if at.0 - gap - w >= l {
        at.0 - gap - w
    } else {
        (r - w).max(l)
    };
    let below = at.1 < t + 0.5 * (b - t);
    let mut top = if below { at.1 + gap } else { at.1 - gap - h };
    let clamp = |y: f64| y.min(b - h).max(t);
    top = clamp(top);
    let overlaps = |y: f64| {
        placed
            .iter()
            .any(|p| left < p[2] && left + w > p[0] && y < p[3] && y + h > p[1])
    };
    for _ in 0..4 {
        if !overlaps(top) {
            break;
        }
        top = clamp(if below { top + h } else { top - h });
    }
    [left, top, left + w, top + h]
}

/// Widens the shorter-scaled range so that both axes have the same length per pixel on a
/// plotting area of `w`×`h` pixels (a circle drawn round).
fn equal_scale(x: (f64, f64), y: (f64, f64), w: u32, h: u32) -> ((f64, f64), (f64, f64)) {
    let (w, h) = (w.max(1) as f64, h.max(1) as f64);
    let (sx, sy) = ((x.1 - x.0) / w, (y.1 - y.0) / h);
    let s = sx.max(sy);
    let widen = |r: (f64, f64), n: f64| {
        let c = 0.5 * (r.0 + r.1);
        (c - 0.5 * s * n, c + 0.5 * s * n)
    };
    (widen(x, w), widen(y, h))
}

fn draw_panel(area: &DrawingArea<SVGBackend, Shift>, p: &Panel) -> Result<(), PlotError> {
    let ((mut x0, mut x1), (mut y0, mut y1)) = bounds(&p.series, p.equal_aspect);
    // The plotting area's size in pixels, from a chart on a scratch document of the same size.
    let (pw, ph) = {
        let (w, h) = area.dim_in_pixel();
        let mut scratch = String::new();
        let root = SVGBackend::with_string(&mut scratch, (w, h)).into_drawing_area();
        let c = chart_on(&root, p, (x0, x1), (y0, y1), None)?;
        c.plotting_area().dim_in_pixel()
    };
    if p.equal_aspect {
        ((x0, x1), (y0, y1)) = equal_scale((x0, x1), (y0, y1), pw, ph);
    }
    // A legend that would cover data in every corner gets headroom above the data instead.
    let (mut corner, covered, bh) = legend_corner(&p.series, (x0, x1), (y0, y1), pw, ph);
    if covered > 0 && !p.equal_aspect && bh < 0.5 {
        y1 += (y1 - y0) * (bh + 0.02) / (1.0 - bh - 0.02);
        corner = SeriesLabelPosition::UpperRight;
    }
    let ticks = angle_ticks(p, (x0, x1)).map(|((a, b), bold, light)| {
        (x0, x1) = (a, b);
        (bold, light)
    });
    let mut chart = chart_on(area, p, (x0, x1), (y0, y1), ticks)?;
    let xt = |v: &f64| tick_on(*v, x1 - x0);
    let yt = |v: &f64| tick_on(*v, y1 - y0);
    chart
        .configure_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .x_label_formatter(&xt)
        .y_label_formatter(&yt)
        .label_style(font(13))
        .axis_desc_style(font(14))
        .bold_line_style(RGBColor(215, 215, 215).stroke_width(S / 2))
        .light_line_style(RGBColor(240, 240, 240).stroke_width(S / 4))
        .axis_style(RGBColor(90, 90, 90).stroke_width(S / 2))
        .set_all_tick_mark_size(px(4))
        .draw()
        .map_err(PlotError::draw)?;
    // The peaks (point, label), labelled once every ring is drawn.
    let mut peaks: Vec<((f64, f64), &str)> = Vec::new();
    for (i, s) in p.series.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        match s.style {
            Style::Line => {
                // Split at non-finite points so that excluded windows stay empty.
                let mut first = true;
                for seg in s.points.split(|q| !(q.0.is_finite() && q.1.is_finite())) {
                    if seg.len() < 2 {
                        continue;
                    }
                    let a = chart
                        .draw_series(LineSeries::new(seg.iter().copied(), c.stroke_width(px(2))))
                        .map_err(PlotError::draw)?;
                    if first {
                        a.label(s.name.clone()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + pxi(18), y)], c.stroke_width(px(2)))
                        });
                        first = false;
                    }
                }
            }
            Style::Points => {
                chart
                    .draw_series(
                        s.points
                            .iter()
                            .filter(|q| q.0.is_finite() && q.1.is_finite())
                            .map(|&q| Circle::new(q, px(2), c.filled())),
                    )
                    .map_err(PlotError::draw)?
                    .label(s.name.clone())
                    .legend(move |(x, y)| Circle::new((x + pxi(9), y), px(3), c.filled()));
            }
            Style::Peak => {
                let c = RGBColor(20, 20, 20);
                for &q in s
                    .points
                    .iter()
                    .filter(|q| q.0.is_finite() && q.1.is_finite())
                {
                    chart
                        .draw_series(std::iter::once(Circle::new(
                            q,
                            px(6),
                            c.stroke_width(px(1)),
                        )))
                        .map_err(PlotError::draw)?;
                    peaks.push((q, s.name.as_str()));
                }
            }
            Style::Marker => {
                chart
                    .draw_series(
                        s.points
                            .iter()
                            .filter(|q| q.0.is_finite() && q.1.is_finite())
                            .map(|&q| Cross::new(q, pxi(7), c.stroke_width(px(3)))),
                    )
                    .map_err(PlotError::draw)?
                    .label(s.name.clone())
                    .legend(move |(x, y)| {
                        Cross::new((x + pxi(9), y), pxi(5), c.stroke_width(px(2)))
                    });
            }
        }
    }
    label_peaks(&mut chart, &peaks, legend_size(&p.series), &corner)?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .label_font(font(13))
        .margin(px(6))
        .legend_area_size(px(26))
        .position(corner)
        .draw()
        .map_err(PlotError::draw)?;
    Ok(())
}

thread_local! {
    static DRAWN: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// SVG documents drawn on this thread so far. Plots are drawn only when written
/// ([`crate::report::Plot`]); a test uses this to show that solving draws nothing.
pub fn documents_drawn() -> u64 {
    DRAWN.with(|d| d.get())
}

/// SVG documents drawn by this process so far, on every thread (a batch draws on its worker
/// threads); a test uses this to show that `batch --summary-only` draws no machine's plot.
pub fn documents_drawn_in_process() -> u64 {
    DRAWN_IN_PROCESS.load(std::sync::atomic::Ordering::Relaxed)
}

static DRAWN_IN_PROCESS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

fn count_document() {
    DRAWN.with(|d| d.set(d.get() + 1));
    DRAWN_IN_PROCESS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
}

/// Side-by-side panels as one SVG document, each panel `w`×`h` pixels.
pub fn panels(ps: &[Panel], w: u32, h: u32) -> Result<String, PlotError> {
    for p in ps {
        has_unit(&p.x_label)?;
        has_unit(&p.y_label)?;
    }
    count_document();
    let mut buf = String::new();
    {
        let n = ps.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut buf, (px(w * n), px(h))).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        let areas = root.split_evenly((1, n as usize));
        for (a, p) in areas.iter().zip(ps) {
            draw_panel(a, p)?;
        }
        root.present().map_err(PlotError::draw)?;
    }
    Ok(finish(buf, w * ps.len().max(1) as u32, h))
}

/// A bar chart of counted bins (a histogram whose counting is done): one bar per
/// `(label, count)`, each non-zero count written above its bar, as one SVG document `w`×`h`.
pub fn bars(
    bins: &[(String, u64)],
    x_label: &str,
    y_label: &str,
    w: u32,
    h: u32,
) -> Result<String, PlotError> {
    has_unit(x_label)?;
    has_unit(y_label)?;
    count_document();
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (px(w), px(h))).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        let n = bins.len().max(1);
        let max = bins.iter().map(|b| b.1).max().unwrap_or(0).max(1);
        // Room above the highest bar for its count.
        let top = max + max.div_ceil(8);
        let mut chart = ChartBuilder::on(&root)
            .margin(px(10))
            .x_label_area_size(px(40))
            .y_label_area_size(px(50))
            .build_cartesian_2d((0..n).into_segmented(), 0..top)
            .map_err(PlotError::draw)?;
        let label = |v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) => bins.get(*i).map(|b| b.0.clone()).unwrap_or_default(),
            _ => String::new(),
        };
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(n)
            .x_label_formatter(&label)
            .y_labels(6)
            .y_label_formatter(&|y| format!("{y}"))
            .label_style(font(13))
            .axis_desc_style(font(13))
            .x_desc(x_label)
            .y_desc(y_label)
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(PlotError::draw)?;
        // The bars as plotters' `Histogram` draws them (3 px apart), but in bin order: the
        // histogram series collects its data in a HashMap, so its output order (not its
        // picture) changed from run to run, and a batch's index.html with it.
        let xr = (0..n).into_segmented();
        chart
            .draw_series(bins.iter().enumerate().filter_map(|(i, b)| {
                let (x0, x1) = (xr.from_index(i)?, xr.from_index(i + 1)?);
                let mut bar = Rectangle::new([(x0, b.1), (x1, 0)], PALETTE[0].filled());
                bar.set_margin(0, 0, px(3), px(3));
                Some(bar)
            }))
            .map_err(PlotError::draw)?;
        let font = TextStyle::from(font(12).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
        chart
            .draw_series(
                bins.iter()
                    .enumerate()
                    .filter(|(_, b)| b.1 > 0)
                    .map(|(i, b)| {
                        Text::new(
                            b.1.to_string(),
                            (SegmentValue::CenterOf(i), b.1),
                            font.clone(),
                        )
                    }),
            )
            .map_err(PlotError::draw)?;
        root.present().map_err(PlotError::draw)?;
    }
    Ok(finish(buf, w, h))
}

/// A scalar field on a regular grid.
#[derive(Debug, Clone)]
pub struct Grid {
    /// x values (columns), increasing.
    pub x: Vec<f64>,
    /// y values (rows), increasing.
    pub y: Vec<f64>,
    /// `values[row][col]`; non-finite cells (infeasible) are drawn grey.
    pub values: Vec<Vec<f64>>,
}

fn colour(t: f64) -> RGBColor {
    // A perceptually ordered blue → yellow ramp (viridis-like, 5 stops).
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let m = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
    RGBColor(m(a.0, b.0), m(a.1, b.1), m(a.2, b.2))
}

/// A chart of `f64` × `f64` on an SVG drawing area.
type Chart2d<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A heat map of `grid` (colour bar in the title range) with `overlay` series on top.
/// `symmetric_log` colours by sign(v)·log10(1 + |v|/scale) so that a zero set stands out.
pub fn heat_map(
    panel: &Panel,
    grid: &Grid,
    symmetric_log: Option<f64>,
    w: u32,
    h: u32,
) -> Result<String, PlotError> {
    has_unit(&panel.x_label)?;
    has_unit(&panel.y_label)?;
    count_document();
    let tf = |v: f64| match symmetric_log {
        Some(s) => v.signum() * (1.0 + v.abs() / s).log10(),
        None => v,
    };
    let vals: Vec<f64> = grid
        .values
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .map(tf)
        .collect();
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = if hi > lo { hi - lo } else { 1.0 };
    let (nx, ny) = (grid.x.len(), grid.y.len());
    if nx < 2 || ny < 2 {
        return Err(PlotError::Data("heat map needs at least a 2×2 grid".into()));
    }
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (px(w), px(h))).into_drawing_area();
        root.fill(&WHITE).map_err(PlotError::draw)?;
        // The map, and on its right the colour bar.
        let (map_area, bar_area) = root.split_horizontally(px(w.saturating_sub(110)));
        let mut chart = heat_chart(&map_area, panel, grid)?;
        let cell_colour = |v: f64| {
            if v.is_finite() {
                colour((tf(v) - lo) / span)
            } else {
                RGBColor(200, 200, 200)
            }
        };
        heat_cells(&mut chart, grid, cell_colour)?;
        heat_overlay(&mut chart, &root, panel)?;
        colour_bar(&bar_area, lo, span, symmetric_log.is_some())?;
        root.present().map_err(PlotError::draw)?;
    }
    Ok(finish(buf, w, h))
}

/// The heat map's chart on `area`: the grid's x and y ranges, the panel's title and axis
/// labels, no mesh.
fn heat_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    panel: &Panel,
    grid: &Grid,
) -> Result<Chart2d<'a, 'b>, PlotError> {
    let (nx, ny) = (grid.x.len(), grid.y.len());
    let (x0, x1) = (grid.x[0], grid.x[nx - 1]);
    let (y0, y1) = (grid.y[0], grid.y[ny - 1]);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, font(17))
        .margin(px(12))
        .x_label_area_size(px(44))
        .y_label_area_size(px(74))
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(PlotError::draw)?;
    let xt = |v: &f64| tick_on(*v, x1 - x0);
    let yt = |v: &f64| tick_on(*v, y1 - y0);
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .x_label_formatter(&xt)
        .y_label_formatter(&yt)
        .label_style(font(13))
        .axis_desc_style(font(14))
        .axis_style(RGBColor(90, 90, 90).stroke_width(S / 2))
        .set_all_tick_mark_size(px(4))
        .disable_mesh()
        .draw()
        .map_err(PlotError::draw)?;
    Ok(chart)
}

/// The grid's cells, each from the midpoints to its neighbours (the edge cells from the
/// edge), filled with `cell_colour` of its value.
fn heat_cells(
    chart: &mut Chart2d,
    grid: &Grid,
    cell_colour: impl Fn(f64) -> RGBColor,
) -> Result<(), PlotError> {
    let (nx, ny) = (grid.x.len(), grid.y.len());
    let (x0, x1) = (grid.x[0], grid.x[nx - 1]);
    let (y0, y1) = (grid.y[0], grid.y[ny - 1]);
    let half = |v: &[f64], i: usize| {
        let a = if i == 0 {
            v[0]
        } else {
            0.5 * (v[i - 1] + v[i])
        };
        let b = if i + 1 == v.len() {
            v[i]
        } else {
            0.5 * (v[i] + v[i + 1])
        };
        (a, b)
    };
    // Each cell reaches one nominal pixel into the next one (drawn after it, in row
    // order), so no seam of the background shows between cells.
    let (pw, ph) = chart.plotting_area().dim_in_pixel();
    let (ex, ey) = (
        f64::from(S) * (x1 - x0) / pw.max(1) as f64,
        f64::from(S) * (y1 - y0) / ph.max(1) as f64,
    );
    chart
        .draw_series(
            (0..ny)
                .flat_map(|r| (0..nx).map(move |c| (r, c)))
                .map(|(r, c)| {
                    let (xa, xb) = half(&grid.x, c);
                    let (ya, yb) = half(&grid.y, r);
                    let (xb, yb) = ((xb + ex).min(x1), (yb + ey).min(y1));
                    let col = cell_colour(grid.values[r][c]);
                    Rectangle::new([(xa, ya), (xb, yb)], col.filled())
                }),
        )
        .map_err(PlotError::draw)?;
    Ok(())
}

/// The panel's series on top of the map (red, white, black, magenta in turn: lines, points
/// or crosses), each named in a legend line in the corner of `root`.
fn heat_overlay(
    chart: &mut Chart2d,
    root: &DrawingArea<SVGBackend, Shift>,
    panel: &Panel,
) -> Result<(), PlotError> {
    let longest = panel
        .series
        .iter()
        .map(|s| s.name.chars().count() + 9)
        .max()
        .unwrap_or(0) as i32;
    for (i, s) in panel.series.iter().enumerate() {
        let c = [RED, WHITE, BLACK, MAGENTA][i % 4];
        match s.style {
            Style::Line | Style::Points => {
                for seg in s.points.split(|q| !(q.0.is_finite() && q.1.is_finite())) {
                    if seg.len() >= 2 {
                        chart
                            .draw_series(LineSeries::new(
                                seg.iter().copied(),
                                c.stroke_width(px(2)),
                            ))
                            .map_err(PlotError::draw)?;
                    } else if seg.len() == 1 {
                        chart
                            .draw_series(std::iter::once(Circle::new(seg[0], px(2), c.filled())))
                            .map_err(PlotError::draw)?;
                    }
                }
            }
            Style::Marker | Style::Peak => {
                chart
                    .draw_series(
                        s.points
                            .iter()
                            .map(|&q| Cross::new(q, pxi(8), c.stroke_width(px(3)))),
                    )
                    .map_err(PlotError::draw)?;
            }
        }
        // Legend entry as text in the corner, on a light band so it reads on any colour.
        let text = format!(
            "{}: {}",
            ["red", "white", "black", "magenta"][i % 4],
            s.name
        );
        let (tx, ty) = (pxi(92), pxi(44 + 17 * i as i32));
        root.draw(&Rectangle::new(
            [
                (tx - pxi(3), ty - pxi(2)),
                (tx + pxi(6 * longest + 6), ty + pxi(15)),
            ],
            WHITE.mix(0.75).filled(),
        ))
        .map_err(PlotError::draw)?;
        root.draw(&Text::new(
            text,
            (tx, ty),
            font(13).into_font().color(&BLACK),
        ))
        .map_err(PlotError::draw)?;
    }
    Ok(())
}

/// The colour bar on `area`: the ramp over [lo, lo + span] in 128 stripes with its own
/// ticks, labelled with the colour's transform (`symmetric_log`) or the title's value.
fn colour_bar(
    area: &DrawingArea<SVGBackend, Shift>,
    lo: f64,
    span: f64,
    symmetric_log: bool,
) -> Result<(), PlotError> {
    let mut bar = ChartBuilder::on(area)
        .margin_top(px(44))
        .margin_bottom(px(56))
        .margin_right(px(8))
        .y_label_area_size(px(70))
        .build_cartesian_2d(0.0..1.0, lo..(lo + span))
        .map_err(PlotError::draw)?;
    let bt = |v: &f64| tick_on(*v, span);
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&bt)
        .y_desc(if symmetric_log {
            "colour: sign·log10(1 + |v|/s)"
        } else {
            "colour: the value in the title"
        })
        .label_style(font(12))
        .axis_desc_style(font(13))
        .set_all_tick_mark_size(px(4))
        .draw()
        .map_err(PlotError::draw)?;
    let steps = 128;
    bar.draw_series((0..steps).map(|k| {
        let (a, b) = (k as f64 / steps as f64, (k + 1) as f64 / steps as f64);
        // Half a stripe into the next one (no seams).
        let b = (b + 0.5 / steps as f64).min(1.0);
        Rectangle::new(
            [(0.0, lo + a * span), (1.0, lo + b * span)],
            colour(0.5 * (a + b)).filled(),
        )
    }))
    .map_err(PlotError::draw)?;
    Ok(())
}
