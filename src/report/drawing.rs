//! Dimensioned drawings of a design, for a designer to open in any CAD program: a
//! [`Drawing`] of shapes in metres on named layers, written as DXF (with the `dxf` crate) and
//! as an SVG with equal aspect.
//!
//! * **DXF**: AutoCAD R2010 (`AC1024`: text in UTF-8, so θ, rᵢ, ° read as written),
//!   coordinates in **millimetres** with `$INSUNITS` = 4 (mm) and `$MEASUREMENT` = 1
//!   (metric), so a CAD program opens the part at its true size.
//!   Values are written with 12 decimals (of a mm). Dimensions are `DIMENSION` entities
//!   (aligned, radius, angular by three points) on layer `DIM` with their definition points,
//!   measurement and the text `label = <>`, each drawing the anonymous block `*D<k>` of its
//!   picture: lines, filled arrowheads (`SOLID`) and `TEXT` reading the value in mm or degrees
//!   to 0.01, as the SVG draws it (`drawing/dxf_out.rs`). The header
//!   dates are 1900-01-01 and the drawing GUIDs nil, so the same design gives the same bytes.
//! * **SVG**: one uniform scale; the `viewBox` is exactly the drawing's extent (text
//!   included) plus a margin, in mm with y up turned into SVG's y down, and the pixel
//!   `width`/`height` have the `viewBox`'s ratio, so a circle is round in every viewer.
//!
//! Layers: `OUTLINE` (the part or the links), `CENTRE` (axes, pivots, centre lines), `DIM`
//! (dimensions), `PATH` (paths of points over the motion), `NOTE` (title and notes).
//! A result carries its drawings as [`Sheet`]s, built only when the result's files are
//! written (`<name>-<suffix>.dxf` and `<name>-<suffix>.svg`, `super::report_files`).

use crate::geom::P2;
use std::f64::consts::PI;

mod dxf_out;

/// Why a drawing could not be made (the files then carry the reason as a note).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DrawingError {
    /// The `dxf` crate failed to write (its message).
    #[error("DXF writing failed: {0}")]
    Dxf(String),
    /// The data cannot make this drawing (nothing to draw, a coordinate not finite).
    #[error("{0}")]
    Data(String),
}

/// A drawing layer (the same names in DXF and, as `class`, in SVG).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layer {
    /// The part's or the links' outline.
    Outline,
    /// Axes, pivots, centre lines.
    Centre,
    /// Dimensions.
    Dim,
    /// Paths of points over the motion.
    Path,
    /// Title and notes.
    Note,
}

impl Layer {
    /// Every layer, in drawing order.
    pub const ALL: [Layer; 5] = [
        Layer::Path,
        Layer::Centre,
        Layer::Outline,
        Layer::Dim,
        Layer::Note,
    ];

    /// The layer's name: `OUTLINE`, `CENTRE`, `DIM`, `PATH`, `NOTE`.
    pub fn name(self) -> &'static str {
        match self {
            Layer::Outline => "OUTLINE",
            Layer::Centre => "CENTRE",
            Layer::Dim => "DIM",
            Layer::Path => "PATH",
            Layer::Note => "NOTE",
        }
    }

    /// AutoCAD colour index: white/black, red, green, blue, white/black.
    fn aci(self) -> u8 {
        match self {
            Layer::Outline | Layer::Note => 7,
            Layer::Centre => 1,
            Layer::Dim => 3,
            Layer::Path => 5,
        }
    }

    /// SVG colour, stroke width (px) and dash pattern (px).
    fn svg_style(self) -> (&'static str, f64, Option<[f64; 4]>) {
        match self {
            Layer::Outline => ("#000", 1.6, None),
            Layer::Centre => ("#c00", 0.7, Some([14.0, 3.0, 2.0, 3.0])),
            Layer::Dim => ("#070", 0.7, None),
            Layer::Path => ("#06c", 1.0, None),
            Layer::Note => ("#000", 0.7, None),
        }
    }
}

/// A shape of a drawing, in metres (angles in radians, counter-clockwise from +x).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A segment a–b.
    Line {
        /// Start.
        a: P2,
        /// End.
        b: P2,
    },
    /// A polyline through `points`, closed back to the first if `closed`.
    Polyline {
        /// Vertices.
        points: Vec<P2>,
        /// Closed.
        closed: bool,
    },
    /// A circle.
    Circle {
        /// Centre.
        centre: P2,
        /// Radius (m).
        radius: f64,
    },
    /// A circular arc, counter-clockwise from `start_rad` to `end_rad`.
    Arc {
        /// Centre.
        centre: P2,
        /// Radius (m).
        radius: f64,
        /// Start angle (rad).
        start_rad: f64,
        /// End angle (rad).
        end_rad: f64,
    },
    /// A centre mark (a pivot, an axis): a cross of two text heights.
    CentreMark {
        /// The centre.
        at: P2,
    },
    /// Text of the drawing's standard height, centred at `at`.
    Label {
        /// Centre of the text.
        at: P2,
        /// The text.
        text: String,
    },
    /// An aligned linear dimension of |ab|: the dimension line parallel to a→b, `offset` to
    /// its left (negative: to its right), extension lines from a and b; text `label = |ab|`
    /// in mm.
    Linear {
        /// First point measured.
        a: P2,
        /// Second point measured.
        b: P2,
        /// Distance of the dimension line from a–b (m), positive to the left of a→b.
        offset: f64,
        /// Name of the dimension (`a`, `L`, …), may be empty.
        label: String,
    },
    /// A radius dimension: a line from the centre to the circle at `angle_rad`, an arrow on
    /// the circle; text `label = r` in mm.
    Radius {
        /// Centre.
        centre: P2,
        /// Radius measured (m).
        radius: f64,
        /// Direction of the dimension line (rad).
        angle_rad: f64,
        /// Name (`rᵢ`, `R`, …), may be empty.
        label: String,
    },
    /// An angle dimension: an arc of radius `radius` about `centre` from `start_rad`
    /// counter-clockwise to `end_rad` with arrows, extension lines along both directions from
    /// radius `from` on; text `label = angle` in degrees.
    Angle {
        /// Vertex.
        centre: P2,
        /// Where the extension lines start (m from the vertex).
        from: f64,
        /// Radius of the dimension arc (m).
        radius: f64,
        /// First direction (rad).
        start_rad: f64,
        /// Second direction (rad), counter-clockwise from the first.
        end_rad: f64,
        /// Name (`θ`, …), may be empty.
        label: String,
    },
}

impl Shape {
    /// Whether the shape is a dimension (linear, radius or angle).
    fn is_dimension(&self) -> bool {
        matches!(
            self,
            Shape::Linear { .. } | Shape::Radius { .. } | Shape::Angle { .. }
        )
    }
}

/// A drawing: a title, notes and shapes on layers, in metres.
#[derive(Debug, Clone, PartialEq)]
pub struct Drawing {
    /// Title (first line of the note block under the drawing).
    pub title: String,
    /// Notes (thickness, material, scale words), one line each, under the title.
    pub notes: Vec<String>,
    /// The shapes, each on its layer, drawn in order within a layer.
    pub shapes: Vec<(Layer, Shape)>,
}

/// How text is aligned at its point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Align {
    /// Left end at the point, on its baseline.
    Left,
    /// Centred on the point, both ways.
    Centre,
}

/// One primitive as the writers get it: its layer, and the index in `shapes` of the
/// dimension it draws, if it draws one (the DXF puts those in the DIMENSION's block).
type Placed = (Layer, Prim, Option<usize>);

/// What [`Drawing::primitives`] expands shapes into: what both writers draw.
#[derive(Debug, Clone, PartialEq)]
enum Prim {
    Line(P2, P2),
    Polyline(Vec<P2>, bool),
    Circle(P2, f64),
    /// Centre, radius, start, end (rad, counter-clockwise).
    Arc(P2, f64, f64, f64),
    /// A filled triangle (arrowheads).
    Solid([P2; 3]),
    Text {
        at: P2,
        height: f64,
        text: String,
        angle_rad: f64,
        align: Align,
    },
}

impl Prim {
    /// Every coordinate and size finite.
    fn is_finite(&self) -> bool {
        let ok = |p: &P2| p.x.is_finite() && p.y.is_finite();
        match self {
            Prim::Line(a, b) => ok(a) && ok(b),
            Prim::Polyline(pts, _) => pts.iter().all(ok),
            Prim::Circle(c, r) => ok(c) && r.is_finite(),
            Prim::Arc(c, r, s, e) => ok(c) && r.is_finite() && s.is_finite() && e.is_finite(),
            Prim::Solid(t) => t.iter().all(ok),
            Prim::Text {
                at,
                height,
                angle_rad,
                ..
            } => ok(at) && height.is_finite() && angle_rad.is_finite(),
        }
    }
}

/// Width of a character as a fraction of the text height, for extents (a generous sans-serif
/// average).
const CHAR_WIDTH: f64 = 0.62;

/// The unit vector at angle `a`.
fn dir(a: f64) -> P2 {
    P2::new(a.cos(), a.sin())
}

/// The left normal of a unit vector.
fn left(u: P2) -> P2 {
    P2::new(-u.y, u.x)
}

/// An angle turned by π if needed so that text along it reads left to right: in (−π/2, π/2].
// pub for the tests in tests/unit_report.rs
#[doc(hidden)]
pub fn readable(a: f64) -> f64 {
    let mut a = a.rem_euclid(2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    }
    if a > 0.5 * PI + 1e-12 {
        a - PI
    } else if a <= -0.5 * PI + 1e-12 {
        a + PI
    } else {
        a
    }
}

/// `label = value` (the value alone without a label).
fn dim_text(label: &str, value: String) -> String {
    if label.is_empty() {
        value
    } else {
        format!("{label} = {value}")
    }
}

/// A length in mm to 0.01 mm.
fn mm(v: f64) -> String {
    format!("{:.2}", v * 1e3)
}

/// The sweep of an arc from `s` to `e` counter-clockwise, in (0, 2π].
fn sweep(s: f64, e: f64) -> f64 {
    let d = (e - s).rem_euclid(2.0 * PI);
    if d == 0.0 {
        2.0 * PI
    } else {
        d
    }
}

/// The primitives that draw one shape, for text height `h` (the arrowheads, extension-line
/// gaps and text placement of the dimensions scale with it).
fn shape_prims(s: &Shape, h: f64) -> Vec<Prim> {
    let (ha, gap) = (1.2 * h, 0.4 * h);
    let arrow = |tip: P2, d: P2| -> Prim {
        let n = left(d) * (ha / 6.0);
        Prim::Solid([tip, tip - ha * d + n, tip - ha * d - n])
    };
    let text = |at: P2, text: String, angle_rad: f64| Prim::Text {
        at,
        height: h,
        text,
        angle_rad,
        align: Align::Centre,
    };
    let mut out = Vec::new();
    let mut put = |p: Prim| out.push(p);
    match s {
        Shape::Line { a, b } => put(Prim::Line(*a, *b)),
        Shape::Polyline { points, closed } => put(Prim::Polyline(points.clone(), *closed)),
        Shape::Circle { centre, radius } => put(Prim::Circle(*centre, *radius)),
        Shape::Arc {
            centre,
            radius,
            start_rad,
            end_rad,
        } => put(Prim::Arc(*centre, *radius, *start_rad, *end_rad)),
        Shape::CentreMark { at } => {
            put(Prim::Line(at - P2::new(h, 0.0), at + P2::new(h, 0.0)));
            put(Prim::Line(at - P2::new(0.0, h), at + P2::new(0.0, h)));
        }
        Shape::Label { at, text: t } => put(text(*at, t.clone(), 0.0)),
        Shape::Linear {
            a,
            b,
            offset,
            label,
        } => {
            let len = (b - a).norm();
            let (u, n, side, a1, b1) = linear_line(*a, *b, *offset);
            if offset.abs() > gap {
                for p in [a, b] {
                    put(Prim::Line(
                        p + side * gap * n,
                        p + (offset + side * gap) * n,
                    ));
                }
            }
            put(Prim::Line(a1, b1));
            put(arrow(a1, -u));
            put(arrow(b1, u));
            let at = text_at(s, h).expect("a dimension");
            put(text(at, dim_text(label, mm(len)), readable(u.y.atan2(u.x))));
        }
        Shape::Radius {
            centre,
            radius,
            angle_rad,
            label,
        } => {
            let u = dir(*angle_rad);
            let p = centre + *radius * u;
            put(Prim::Line(*centre, p));
            put(arrow(p, u));
            let at = text_at(s, h).expect("a dimension");
            put(text(at, dim_text(label, mm(*radius)), readable(*angle_rad)));
        }
        Shape::Angle {
            centre,
            from,
            radius,
            start_rad,
            end_rad,
            label,
        } => {
            let sw = sweep(*start_rad, *end_rad);
            let e = start_rad + sw;
            for a in [*start_rad, e] {
                put(Prim::Line(
                    centre + *from * dir(a),
                    centre + (radius + gap) * dir(a),
                ));
            }
            put(Prim::Arc(*centre, *radius, *start_rad, e));
            put(arrow(
                centre + *radius * dir(*start_rad),
                -left(dir(*start_rad)),
            ));
            put(arrow(centre + *radius * dir(e), left(dir(e))));
            let mid = start_rad + 0.5 * sw;
            put(text(
                text_at(s, h).expect("a dimension"),
                dim_text(label, format!("{:.2}°", sw.to_degrees())),
                readable(mid - 0.5 * PI),
            ));
        }
    }
    out
}

/// A linear dimension's line for the points a, b and the offset: its direction u, the left
/// normal n, the offset's side (±1) and the line's ends a₁ = a + offset·n, b₁ = b + offset·n.
fn linear_line(a: P2, b: P2, offset: f64) -> (P2, P2, f64, P2, P2) {
    let u = (b - a).try_normalize(0.0).unwrap_or(P2::x());
    let n = left(u);
    let side = if offset < 0.0 { -1.0 } else { 1.0 };
    (u, n, side, a + offset * n, b + offset * n)
}

/// The centre of a dimension's text for text height h (None for other shapes): beside the
/// middle of a linear dimension's line, above a radius's line as read, outside the middle
/// of an angle's arc.
fn text_at(s: &Shape, h: f64) -> Option<P2> {
    Some(match s {
        Shape::Linear { a, b, offset, .. } => {
            let (_, n, side, a1, b1) = linear_line(*a, *b, *offset);
            0.5 * (a1 + b1) + side * 0.8 * h * n
        }
        Shape::Radius {
            centre,
            radius,
            angle_rad,
            ..
        } => centre + 0.55 * radius * dir(*angle_rad) + 0.8 * h * left(dir(readable(*angle_rad))),
        Shape::Angle {
            centre,
            radius,
            start_rad,
            end_rad,
            ..
        } => centre + (radius + 0.9 * h) * dir(start_rad + 0.5 * sweep(*start_rad, *end_rad)),
        _ => return None,
    })
}

/// Extent of points: (min, max).
#[derive(Debug, Clone, Copy)]
struct Extent {
    min: P2,
    max: P2,
}

impl Extent {
    fn empty() -> Extent {
        Extent {
            min: P2::new(f64::INFINITY, f64::INFINITY),
            max: P2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        }
    }
    fn add(&mut self, p: P2) {
        self.min = self.min.inf(&p);
        self.max = self.max.sup(&p);
    }
    fn size(&self) -> P2 {
        self.max - self.min
    }
    /// Something was added.
    fn is_valid(&self) -> bool {
        self.min
            .iter()
            .chain(self.max.iter())
            .all(|v| v.is_finite())
    }
    /// Adds an arc: its ends and the quadrant points it passes.
    fn add_arc(&mut self, c: P2, r: f64, s: f64, e: f64) {
        let sw = sweep(s, e);
        self.add(c + r * dir(s));
        self.add(c + r * dir(s + sw));
        for q in 0..4 {
            let a = q as f64 * 0.5 * PI;
            if (a - s).rem_euclid(2.0 * PI) <= sw {
                self.add(c + r * dir(a));
            }
        }
    }
    fn add_prim(&mut self, p: &Prim) {
        match p {
            Prim::Line(a, b) => {
                self.add(*a);
                self.add(*b);
            }
            Prim::Polyline(pts, _) => pts.iter().for_each(|p| self.add(*p)),
            Prim::Circle(c, r) => {
                self.add(c - P2::new(*r, *r));
                self.add(c + P2::new(*r, *r));
            }
            Prim::Arc(c, r, s, e) => self.add_arc(*c, *r, *s, *e),
            Prim::Solid(t) => t.iter().for_each(|p| self.add(*p)),
            Prim::Text {
                at,
                height,
                text,
                angle_rad,
                align,
            } => {
                let w = CHAR_WIDTH * height * text.chars().count() as f64;
                let (u, n) = (dir(*angle_rad), left(dir(*angle_rad)));
                let (x0, y0) = match align {
                    Align::Left => (0.0, -0.25 * height),
                    Align::Centre => (-0.5 * w, -0.5 * height),
                };
                for (dx, dy) in [
                    (x0, y0),
                    (x0 + w, y0),
                    (x0, y0 + height),
                    (x0 + w, y0 + height),
                ] {
                    self.add(at + dx * u + dy * n);
                }
            }
        }
    }
}

impl Drawing {
    /// An empty drawing titled `title`.
    pub fn new(title: impl Into<String>) -> Drawing {
        Drawing {
            title: title.into(),
            notes: Vec::new(),
            shapes: Vec::new(),
        }
    }

    /// Adds `shape` on `layer`.
    pub fn add(&mut self, layer: Layer, shape: Shape) -> &mut Drawing {
        self.shapes.push((layer, shape));
        self
    }

    /// Adds a segment a–b on `layer`.
    pub fn line(&mut self, layer: Layer, a: P2, b: P2) -> &mut Drawing {
        self.add(layer, Shape::Line { a, b })
    }

    /// Adds a polyline on `layer`.
    pub fn polyline(&mut self, layer: Layer, points: Vec<P2>, closed: bool) -> &mut Drawing {
        self.add(layer, Shape::Polyline { points, closed })
    }

    /// Adds a circle on `layer`.
    pub fn circle(&mut self, layer: Layer, centre: P2, radius: f64) -> &mut Drawing {
        self.add(layer, Shape::Circle { centre, radius })
    }

    /// Adds an arc on `layer`, counter-clockwise from `start_rad` to `end_rad`.
    pub fn arc(
        &mut self,
        layer: Layer,
        centre: P2,
        radius: f64,
        start_rad: f64,
        end_rad: f64,
    ) -> &mut Drawing {
        self.add(
            layer,
            Shape::Arc {
                centre,
                radius,
                start_rad,
                end_rad,
            },
        )
    }

    /// Adds a centre mark on `CENTRE`.
    pub fn mark(&mut self, at: P2) -> &mut Drawing {
        self.add(Layer::Centre, Shape::CentreMark { at })
    }

    /// Adds a text centred at `at` on `NOTE`.
    pub fn label(&mut self, at: P2, text: impl Into<String>) -> &mut Drawing {
        let text = text.into();
        self.add(Layer::Note, Shape::Label { at, text })
    }

    /// Adds a [`Shape::Linear`] dimension of |ab| on `DIM`.
    pub fn linear(&mut self, a: P2, b: P2, offset: f64, label: &str) -> &mut Drawing {
        let label = label.into();
        self.add(
            Layer::Dim,
            Shape::Linear {
                a,
                b,
                offset,
                label,
            },
        )
    }

    /// Adds a [`Shape::Radius`] dimension on `DIM`.
    pub fn radius(&mut self, centre: P2, radius: f64, angle_rad: f64, label: &str) -> &mut Drawing {
        let label = label.into();
        self.add(
            Layer::Dim,
            Shape::Radius {
                centre,
                radius,
                angle_rad,
                label,
            },
        )
    }

    /// Adds a [`Shape::Angle`] dimension on `DIM`: from `start_rad` counter-clockwise to
    /// `end_rad` about `centre`, the arc at `radius`, extension lines from `from`.
    pub fn angle(
        &mut self,
        centre: P2,
        from: f64,
        radius: f64,
        (start_rad, end_rad): (f64, f64),
        label: &str,
    ) -> &mut Drawing {
        let label = label.into();
        self.add(
            Layer::Dim,
            Shape::Angle {
                centre,
                from,
                radius,
                start_rad,
                end_rad,
                label,
            },
        )
    }

    /// Adds a note line under the title.
    pub fn note(&mut self, text: impl Into<String>) -> &mut Drawing {
        self.notes.push(text.into());
        self
    }

    /// A drawing that only says why the real one could not be made.
    pub fn failed(title: &str, why: &DrawingError) -> Drawing {
        let mut d = Drawing::new(format!("{title}: drawing not made"));
        d.note(why.to_string());
        d
    }

    /// The extent of the geometry alone (shapes and the points dimensions measure, no text).
    fn geometry_extent(&self) -> Extent {
        let mut e = Extent::empty();
        for (_, s) in &self.shapes {
            match s {
                Shape::Line { a, b } => {
                    e.add(*a);
                    e.add(*b);
                }
                Shape::Polyline { points, .. } => points.iter().for_each(|p| e.add(*p)),
                Shape::Circle { centre, radius } => {
                    e.add_prim(&Prim::Circle(*centre, *radius));
                }
                Shape::Arc {
                    centre,
                    radius,
                    start_rad,
                    end_rad,
                } => e.add_arc(*centre, *radius, *start_rad, *end_rad),
                Shape::CentreMark { at } | Shape::Label { at, .. } => e.add(*at),
                Shape::Linear { a, b, offset, .. } => {
                    let u = (b - a).try_normalize(0.0).unwrap_or(P2::x());
                    for p in [a, b] {
                        e.add(*p);
                        e.add(p + *offset * left(u));
                    }
                }
                Shape::Radius {
                    centre,
                    radius,
                    angle_rad,
                    ..
                } => {
                    e.add(*centre);
                    e.add(centre + *radius * dir(*angle_rad));
                }
                Shape::Angle {
                    centre,
                    radius,
                    start_rad,
                    end_rad,
                    ..
                } => {
                    e.add(*centre);
                    e.add_arc(*centre, *radius, *start_rad, *end_rad);
                }
            }
        }
        e
    }

    /// The standard text height (m): 1/60 of the geometry's larger side.
    /// Only notes: 5 mm.
    fn text_height(&self) -> Result<f64, DrawingError> {
        if self.shapes.is_empty() {
            return if self.notes.is_empty() {
                Err(DrawingError::Data("nothing to draw".into()))
            } else {
                Ok(5e-3)
            };
        }
        let size = self.geometry_extent().size();
        let h = size.x.max(size.y) / 60.0;
        Ok(if h > 0.0 { h } else { 1e-3 })
    }

    /// The shapes expanded into lines, arcs, arrowheads and text (what both writers draw),
    /// the title and notes placed under the geometry; with the standard text height.
    fn primitives(&self) -> Result<(Vec<Placed>, f64), DrawingError> {
        let h = self.text_height()?;
        let mut out: Vec<Placed> = Vec::new();
        for (k, (layer, s)) in self.shapes.iter().enumerate() {
            let dim = s.is_dimension().then_some(k);
            out.extend(shape_prims(s, h).into_iter().map(|p| (*layer, p, dim)));
        }
        // The note block: under the geometry, left-aligned.
        if let Some((_, p, _)) = out.iter().find(|(_, p, _)| !p.is_finite()) {
            return Err(DrawingError::Data(format!(
                "a coordinate is not finite in {p:?}"
            )));
        }
        let mut ext = Extent::empty();
        out.iter().for_each(|(_, p, _)| ext.add_prim(p));
        if !ext.is_valid() {
            ext = Extent {
                min: P2::zeros(),
                max: P2::zeros(),
            };
        }
        let mut y = ext.min.y - 2.5 * h;
        for (i, line) in std::iter::once(&self.title).chain(&self.notes).enumerate() {
            let height = if i == 0 { 1.3 * h } else { h };
            out.push((
                Layer::Note,
                Prim::Text {
                    at: P2::new(ext.min.x, y),
                    height,
                    text: line.clone(),
                    angle_rad: 0.0,
                    align: Align::Left,
                },
                None,
            ));
            y -= 1.7 * h;
        }
        Ok((out, h))
    }

    /// The extent of everything drawn (text included): (min, max) in m.
    fn extent(prims: &[Placed]) -> Extent {
        let mut e = Extent::empty();
        prims.iter().for_each(|(_, p, _)| e.add_prim(p));
        e
    }

    /// The SVG document: equal aspect, `viewBox` = extent + margin in mm (see the module doc).
    pub fn svg(&self) -> Result<String, DrawingError> {
        use std::fmt::Write;
        let (prims, h) = self.primitives()?;
        let ext = Self::extent(&prims);
        // The viewBox in mm, y down, rounded out to 0.001 mm; the margin two text heights.
        let margin = 2.0 * h;
        let r3 = |v: f64, up: bool| {
            let v = v * 1e3 * 1e3;
            (if up { v.ceil() } else { v.floor() }) / 1e3
        };
        let (x0, x1) = (r3(ext.min.x - margin, false), r3(ext.max.x + margin, true));
        let (y0, y1) = (
            r3(-(ext.max.y + margin), false),
            r3(-(ext.min.y - margin), true),
        );
        let (vw, vh) = (x1 - x0, y1 - y0);
        // Pixels: 960 wide, or 720 high if that is the tighter; the same ratio as the viewBox.
        let (pw, ph) = if vh / vw > 0.75 {
            (720.0 * vw / vh, 720.0)
        } else {
            (960.0, 960.0 * vh / vw)
        };
        let px = vw / pw; // mm per pixel, the same both ways
        let f = |v: f64| {
            let mut s = String::new();
            push_mm(&mut s, v);
            s
        };
        let xy = |p: P2| format!("{},{}", f(p.x * 1e3), f(-p.y * 1e3));
        let mut s = String::new();
        let _ = writeln!(
            s,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{pw}\" height=\"{ph}\" viewBox=\"{x0} {y0} {vw} {vh}\">"
        );
        let _ = writeln!(
            s,
            "<title>{} (dimensions in mm)</title>",
            super::html_escape(&self.title)
        );
        let _ = writeln!(
            s,
            "<rect x=\"{x0}\" y=\"{y0}\" width=\"{vw}\" height=\"{vh}\" fill=\"#fff\"/>"
        );
        for layer in Layer::ALL {
            let (colour, width, dash) = layer.svg_style();
            let dash = dash.map_or(String::new(), |d| {
                format!(" stroke-dasharray=\"{}\"", d.map(|v| f(v * px)).join(" "))
            });
            let _ = writeln!(
                s,
                "<g class=\"{}\" stroke=\"{colour}\" stroke-width=\"{}\" fill=\"none\" stroke-linecap=\"round\" stroke-linejoin=\"round\"{dash}>",
                layer.name(),
                f(width * px)
            );
            for (_, p, _) in prims.iter().filter(|(l, _, _)| *l == layer) {
                let _ = match p {
                    Prim::Line(a, b) => {
                        writeln!(s, "<path d=\"M{}L{}\"/>", xy(*a), xy(*b))
                    }
                    Prim::Polyline(pts, closed) => {
                        // Written in place: an outline has thousands of points.
                        s.push_str("<path d=\"M");
                        for (i, p) in pts.iter().enumerate() {
                            if i > 0 {
                                s.push('L');
                            }
                            push_mm(&mut s, p.x * 1e3);
                            s.push(',');
                            push_mm(&mut s, -p.y * 1e3);
                        }
                        writeln!(s, "{}\"/>", if *closed { "Z" } else { "" })
                    }
                    Prim::Circle(c, r) => writeln!(
                        s,
                        "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
                        f(c.x * 1e3),
                        f(-c.y * 1e3),
                        f(r * 1e3)
                    ),
                    Prim::Arc(c, r, a0, a1) => {
                        let sw = sweep(*a0, *a1);
                        if sw >= 2.0 * PI - 1e-12 {
                            writeln!(
                                s,
                                "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
                                f(c.x * 1e3),
                                f(-c.y * 1e3),
                                f(r * 1e3)
                            )
                        } else {
                            // Counter-clockwise with y up is sweep-flag 0 with y down.
                            writeln!(
                                s,
                                "<path d=\"M{}A{} {} 0 {} 0 {}\"/>",
                                xy(c + *r * dir(*a0)),
                                f(r * 1e3),
                                f(r * 1e3),
                                u8::from(sw > PI),
                                xy(c + *r * dir(a0 + sw))
                            )
                        }
                    }
                    Prim::Solid([a, b, c]) => writeln!(
                        s,
                        "<path d=\"M{}L{}L{}Z\" fill=\"{colour}\" stroke=\"none\"/>",
                        xy(*a),
                        xy(*b),
                        xy(*c)
                    ),
                    Prim::Text {
                        at,
                        height,
                        text,
                        angle_rad,
                        align,
                    } => {
                        let (anchor, baseline) = match align {
                            Align::Left => ("start", ""),
                            Align::Centre => ("middle", " dominant-baseline=\"central\""),
                        };
                        let (x, y) = (f(at.x * 1e3), f(-at.y * 1e3));
                        let rot = if *angle_rad == 0.0 {
                            String::new()
                        } else {
                            format!(
                                " transform=\"rotate({} {x} {y})\"",
                                f(-angle_rad.to_degrees())
                            )
                        };
                        writeln!(
                            s,
                            "<text x=\"{x}\" y=\"{y}\" font-family=\"sans-serif\" font-size=\"{}\" text-anchor=\"{anchor}\"{baseline} fill=\"{colour}\" stroke=\"none\"{rot}>{}</text>",
                            f(height * 1e3),
                            super::html_escape(text)
                        )
                    }
                };
            }
            s.push_str("</g>\n");
        }
        s.push_str("</svg>\n");
        Ok(s)
    }
}

/// A drawing of a result, made only when the result's files are written (like a
/// [`super::Plot`]): `<name>-<suffix>.dxf` and `<name>-<suffix>.svg`.
#[derive(Clone)]
pub struct Sheet {
    /// File name suffix: `<name>-<suffix>.dxf` / `.svg`.
    pub suffix: String,
    /// Caption for reports.
    pub caption: String,
    build: std::sync::Arc<dyn Fn() -> Result<Drawing, DrawingError> + Send + Sync>,
}

impl Sheet {
    /// A sheet whose drawing `build` makes when the sheet is written.
    pub fn new(
        suffix: impl Into<String>,
        caption: impl Into<String>,
        build: impl Fn() -> Result<Drawing, DrawingError> + Send + Sync + 'static,
    ) -> Sheet {
        Sheet {
            suffix: suffix.into(),
            caption: caption.into(),
            build: std::sync::Arc::new(build),
        }
    }

    /// The drawing, made now.
    pub fn drawing(&self) -> Result<Drawing, DrawingError> {
        (self.build)()
    }

    /// The DXF and SVG documents; if the drawing cannot be made, both say why (a report's
    /// link never breaks; a drawing that cannot be made is a bug to report).
    pub fn files(&self) -> (Vec<u8>, Vec<u8>) {
        let both = |d: &Drawing| Ok::<_, DrawingError>((d.dxf()?, d.svg()?.into_bytes()));
        self.drawing()
            .and_then(|d| both(&d))
            .or_else(|e| both(&Drawing::failed(&self.caption, &e)))
            .unwrap_or_else(|e| (e.to_string().into_bytes(), e.to_string().into_bytes()))
    }
}

impl std::fmt::Debug for Sheet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Sheet")
            .field("suffix", &self.suffix)
            .field("caption", &self.caption)
            .finish_non_exhaustive()
    }
}

impl PartialEq for Sheet {
    /// Sheets are equal when they would be written to the same files with the same caption.
    fn eq(&self, other: &Sheet) -> bool {
        self.suffix == other.suffix && self.caption == other.caption
    }
}

/// Appends v (mm) as the SVG writes a coordinate: 4 decimals (0.1 µm), trailing zeros and a
/// trailing point dropped, −0 as 0 — in place, without the three allocations of
/// `format!` + trim + `to_string` per number (an outline has thousands).
fn push_mm(s: &mut String, v: f64) {
    use std::fmt::Write;
    let start = s.len();
    let _ = write!(s, "{v:.4}");
    let kept = s[start..].trim_end_matches('0').trim_end_matches('.').len();
    s.truncate(start + kept);
    if &s[start..] == "-0" {
        s.truncate(start);
        s.push('0');
    }
}
