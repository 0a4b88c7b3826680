//! A body's mass, centroid and inertia from the drawing a designer already has: the key
//! `outline = { file = "drawings/crank.dxf", layer = "CRANK", thickness = "12 mm",
//! density = "7850 kg/m^3" }` of a problem file reads the closed outlines of a DXF file (with
//! the `dxf` crate) and integrates them exactly (`geom::outline`: Green's theorem, closed forms
//! for lines and arcs, holes by nesting), so the numbers are not typed by hand.
//!
//! Read: LINE, ARC, CIRCLE, LWPOLYLINE and POLYLINE (2-D, with bulges) in model space, on
//! `layer` if given (compared without case, as CAD programs do); text, dimensions, hatches and
//! the like are ignored, and a curve that cannot be integrated exactly (ELLIPSE, SPLINE, a
//! block INSERT, …) on the layer read is an error rather than a silently lighter part. Edges
//! are chained end to end into closed loops within [`CLOSE_TOL`] × the drawing's size; a loop
//! that does not close is an error naming the file and where the gap is.
//!
//! Units are never guessed: the drawing's `$INSUNITS` says its unit; a drawing without one
//! (absent or "unitless") needs `unit` in the problem file, and a `unit` that contradicts the
//! drawing's is an error.
//!
//! The frame: the drawing's origin is the body's reference point (a link's reference joint)
//! and its x axis the body's x axis, unless `origin` (the drawing point that is the reference
//! point) and `angle` (the direction of the body's x axis in the drawing) say otherwise.

use crate::geom::outline::{chain, region, ChainError, Edge, Plate, RegionError};
use crate::geom::{rot, P2};
use crate::problem::{positive, FieldError, Pair};
use crate::units::{Angle, Density, Dim, Length, Qty};
use dxf::entities::{Entity, EntityType};
use serde::Deserialize;
use std::path::Path;

/// The largest drawing read (bytes).
pub const MAX_DRAWING_BYTES: usize = 32 << 20;

/// The most edges an outline may have (chaining compares every free end with every other).
pub const MAX_EDGES: usize = 20_000;

/// Two edge ends meet when they are this close, relative to the diagonal of the drawing's
/// bounding box (a CAD program writes coordinates to 12 or more digits).
pub const CLOSE_TOL: f64 = 1e-7;

/// `outline = { … }`: a plate drawn in a DXF file.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutlineRaw {
    /// The DXF file, relative to the problem file's folder.
    pub file: String,
    /// Only the entities on this layer (compared without case; default every layer).
    pub layer: Option<String>,
    /// t, the plate's thickness.
    pub thickness: Qty<Length>,
    /// ρ, the material's density.
    pub density: Qty<Density>,
    /// The drawing's length unit (`"mm"`, `"in"`, …): required when the drawing does not say
    /// (`$INSUNITS` absent or unitless), else it must agree with it.
    pub unit: Option<String>,
    /// The drawing point that is the body's reference point (default the drawing's origin).
    pub origin: Option<Pair<Qty<Length>>>,
    /// The direction of the body's x axis in the drawing (default the drawing's x axis).
    pub angle: Option<Qty<Angle>>,
}

/// The plate an `outline` key describes, in the body's frame (SI): mass, centroid, inertia
/// about the centroid, area.
pub fn plate(raw: &OutlineRaw, dir: &Path, key: &str) -> Result<Plate, FieldError> {
    drawn(raw, dir, key).map(|(p, _)| p)
}

/// [`plate`] and the drawing's closed loops in the body's frame (SI), to draw the body as
/// it was drawn.
pub fn drawn(
    raw: &OutlineRaw,
    dir: &Path,
    key: &str,
) -> Result<(Plate, Vec<Vec<Edge>>), FieldError> {
    let at = |f: &str| format!("{key}.{f}");
    let t = positive(&at("thickness"), raw.thickness.si())?;
    let rho = positive(&at("density"), raw.density.si())?;
    let path = dir.join(&raw.file);
    let shown = path.display();
    let bytes = crate::problem::read_bounded(&path, MAX_DRAWING_BYTES)
        .map_err(|e| FieldError::new(at("file"), format!("{shown}: cannot read: {e}")))?;
    if bytes.len() > MAX_DRAWING_BYTES {
        return Err(FieldError::new(
            at("file"),
            format!("{shown}: larger than {MAX_DRAWING_BYTES} bytes; allowed: a smaller drawing (the part's layer alone)"),
        ));
    }
    // The reader is a third party's: a panic on a malformed file is this field's error,
    // not the end of a batch or a server.
    let loaded = std::panic::catch_unwind(|| dxf::Drawing::load(&mut bytes.as_slice()));
    let not_dxf = |why: String| {
        FieldError::new(
            at("file"),
            format!("{shown}: not a DXF drawing the reader understands: {why}"),
        )
    };
    let drawing = match loaded {
        Ok(read) => read.map_err(|e| not_dxf(e.to_string()))?,
        Err(_) => return Err(not_dxf("the reader (the dxf crate) failed on it".into())),
    };
    let (scale, unit) = drawing_unit(&drawing, raw.unit.as_deref(), &at("unit"), &shown)?;
    let edges = outline_edges(&drawing, raw.layer.as_deref(), key, &shown)?;
    let (lo, hi) = bounds(&edges);
    let tol = CLOSE_TOL * (hi - lo).norm();
    let loops = chain(&edges, tol).map_err(|e| {
        let xy = |p: P2| format!("({}, {}) {unit}", p.x, p.y);
        let message = match e {
            ChainError::Open { end, nearest } => format!(
                "{shown}: the outline does not close: a chain of edges ends at {}{}; allowed: closed outlines, edges meeting end to end within {tol:e} {unit}",
                xy(end),
                nearest.map_or(String::new(), |(p, d)| format!(", the nearest free end is {d:e} {unit} away at {}", xy(p)))
            ),
            ChainError::Branch { at } => format!(
                "{shown}: more than two edge ends meet at {}, so the outline is ambiguous; allowed: closed outlines that meet only end to end, two ends at a point",
                xy(at)
            ),
        };
        FieldError::new(at_file(key, raw), message)
    })?;
    let about = (lo + hi) / 2.0;
    let m = region(&loops, about).map_err(|e| {
        let message = match e {
            RegionError::Empty(i) => format!("{shown}: loop {} encloses no area", i + 1),
            RegionError::Crossing(i, j) => format!(
                "{shown}: loops {} and {} cross or touch; allowed: loops that are apart or nested (a hole inside a part)",
                i + 1,
                j + 1
            ),
        };
        FieldError::new(at_file(key, raw), message)
    })?;
    // In metres: A s², S s³, J s⁴ (the drawing integrated in its own unit).
    let s = scale;
    let si = crate::geom::outline::Moments {
        area: m.area * s * s,
        first: m.first * (s * s * s),
        second: m.second * (s * s * s * s),
    };
    let p = Plate::new(&si, about * s, t, rho);
    let Placement { origin, angle } = Placement::of(raw);
    let origin = origin.unwrap_or_else(P2::zeros);
    let placed = loops
        .iter()
        .map(|l| {
            l.edges
                .iter()
                .map(|e| e.placed(s, -origin, -angle))
                .collect()
        })
        .collect();
    Ok((
        Plate {
            centroid: rot(-angle, p.centroid - origin),
            ..p
        },
        placed,
    ))
}

/// Where a drawing sits in its body's frame (`origin` and `angle` of `outline`): the drawing
/// point placed at the body's reference point and the direction of the body's x axis in the
/// drawing. A drawing point q (m, the drawing's coordinates) is at Rot(−angle)(q − origin) in
/// the body's frame ([`drawn`] places the loops and the centroid so).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Placement {
    /// The drawing point at the body's reference point (m); `None` where the file leaves
    /// `origin` out (the drawing's origin).
    pub origin: Option<P2>,
    /// The direction of the body's x axis in the drawing (rad; 0 where left out).
    pub angle: f64,
}

impl Placement {
    /// The placement `outline = { … }` gives (its units read; no file read).
    pub fn of(raw: &OutlineRaw) -> Placement {
        Placement {
            origin: raw.origin.as_ref().map(|o| P2::new(o[0].si(), o[1].si())),
            angle: raw.angle.map_or(0.0, Qty::si),
        }
    }

    /// The drawing's own frame as placed in the body's frame, (its origin, its x axis's
    /// angle): the drawing point q is at t + Rot(β) q with β = −angle and
    /// t = Rot(−angle)(−origin), the map above.
    pub fn drawing_frame(&self) -> (P2, f64) {
        let o = self.origin.unwrap_or_else(P2::zeros);
        (rot(-self.angle, -o), -self.angle)
    }
}

/// What `outline` does to the keys it sets, as [`set_by`] says it.
pub const OUTLINE_SETS: &str = "outline, which sets it from the drawing";

/// A key given beside the key that sets it (`by`: [`OUTLINE_SETS`], `uniform_bar = true`):
/// an error at the first such key of `given` (name, given), `key.name`.
pub fn set_by(key: &str, given: &[(&str, bool)], by: &str) -> Result<(), FieldError> {
    match given.iter().find(|(_, g)| *g) {
        Some((f, _)) => Err(FieldError::new(
            format!("{key}.{f}"),
            format!("given with {by}; allowed: one or the other"),
        )),
        None => Ok(()),
    }
}

/// The field an error about the drawing's geometry names: the layer read, or the file.
fn at_file(key: &str, raw: &OutlineRaw) -> String {
    match raw.layer {
        Some(_) => format!("{key}.layer"),
        None => format!("{key}.file"),
    }
}

/// The lower-left and upper-right corners of the edges' bounding box (arcs by their whole
/// circle: a bound, which is all the tolerance needs).
fn bounds(edges: &[Edge]) -> (P2, P2) {
    let mut lo = P2::repeat(f64::INFINITY);
    let mut hi = P2::repeat(f64::NEG_INFINITY);
    for e in edges {
        let mut add = |p: P2| {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        };
        add(e.from);
        add(e.to);
        if let Some(a) = e.arc {
            add(a.centre - P2::repeat(a.radius));
            add(a.centre + P2::repeat(a.radius));
        }
    }
    (lo, hi)
}

/// The drawing's unit in metres and its symbol: from `$INSUNITS`, or from the file's `unit`
/// when the drawing has none; both given must agree.
fn drawing_unit(
    drawing: &dxf::Drawing,
    unit: Option<&str>,
    field: &str,
    shown: &std::path::Display,
) -> Result<(f64, String), FieldError> {
    let header = header_unit(drawing.header.default_drawing_units)
        .map_err(|name| FieldError::new(field, format!("{shown}: the drawing's unit ($INSUNITS) is {name}, not a unit for a part; allowed: a drawing in mm, cm, m, in or ft")))?;
    let given = match unit {
        None => None,
        Some(u) => match crate::units::unit(u) {
            Some(x) if x.dim == Dim::Length => Some((x.factor, x.symbol.to_string())),
            _ => {
                return Err(FieldError::new(
                    field,
                    format!(
                        "`{u}` is no length unit; allowed: {}",
                        Dim::Length.allowed()
                    ),
                ))
            }
        },
    };
    match (header, given) {
        (Some((h, name)), Some((g, written))) if (h - g).abs() > 1e-15 * h => Err(FieldError::new(
            field,
            format!("{shown} says its unit is {name} ($INSUNITS), the problem file says `{written}`; allowed: the drawing's own unit, or no `unit`"),
        )),
        (Some((h, name)), _) => Ok((h, name.to_string())),
        (None, Some(g)) => Ok(g),
        (None, None) => Err(FieldError::new(
            field,
            format!("missing: {shown} does not say its unit ($INSUNITS absent or unitless), and units are never guessed; allowed: unit = \"mm\" (or another length unit: {})", Dim::Length.allowed()),
        )),
    }
}

/// `$INSUNITS` in metres and its symbol; `Ok(None)` for a unitless drawing, `Err(name)` for a
/// unit no part is drawn in (miles, parsecs, …).
fn header_unit(u: dxf::enums::Units) -> Result<Option<(f64, &'static str)>, String> {
    use dxf::enums::Units as U;
    Ok(Some(match u {
        U::Unitless => return Ok(None),
        U::Millimeters => (1e-3, "mm"),
        U::Centimeters => (1e-2, "cm"),
        U::Decimeters => (0.1, "dm"),
        U::Meters => (1.0, "m"),
        U::Microns => (1e-6, "µm"),
        U::Inches => (0.0254, "in"),
        U::Feet => (0.3048, "ft"),
        U::Yards => (0.9144, "yd"),
        U::Mils => (2.54e-5, "mil"),
        U::Microinches => (2.54e-8, "µin"),
        other => return Err(format!("{other:?}")),
    }))
}

/// The edges of the outline entities (on `layer`, if given) in model space, in the drawing's
/// unit; zero-length straight edges dropped.
fn outline_edges(
    drawing: &dxf::Drawing,
    layer: Option<&str>,
    key: &str,
    shown: &std::path::Display,
) -> Result<Vec<Edge>, FieldError> {
    let field = match layer {
        Some(_) => format!("{key}.layer"),
        None => format!("{key}.file"),
    };
    let mut edges = Vec::new();
    let mut layers = std::collections::BTreeSet::new();
    for e in drawing.entities().filter(|e| !e.common.is_in_paper_space) {
        let on = layer.is_none_or(|l| e.common.layer.eq_ignore_ascii_case(l));
        let got = entity_edges(e).map_err(|kind| {
            FieldError::new(
                &field,
                format!("{shown}: {kind} on layer `{}`, which is not read (no exact integral); allowed: LINE, ARC, CIRCLE, LWPOLYLINE and 2-D POLYLINE (explode blocks, convert curves to arcs)", e.common.layer),
            )
        });
        match (on, got) {
            (true, Err(err)) => return Err(err),
            (true, Ok(Some(v))) => edges.extend(v),
            (false, Ok(Some(_))) => {
                layers.insert(e.common.layer.clone());
            }
            _ => {}
        }
        if edges.len() > MAX_EDGES {
            return Err(FieldError::new(
                &field,
                format!("{shown}: more than {MAX_EDGES} edges; allowed: at most {MAX_EDGES}"),
            ));
        }
    }
    edges.retain(|e| e.arc.is_some() || e.from != e.to);
    if edges.is_empty() {
        let others: Vec<String> = layers.into_iter().collect();
        return Err(FieldError::new(
            field,
            format!(
                "{shown}: no LINE, ARC, CIRCLE or polyline{}; layers that have them: {}",
                layer.map_or(String::new(), |l| format!(" on layer `{l}`")),
                if others.is_empty() {
                    "none".to_string()
                } else {
                    others.join(", ")
                }
            ),
        ));
    }
    Ok(edges)
}

/// One entity's edges in the drawing's plane: `Ok(None)` for an entity that is no outline
/// (text, a dimension, a point), `Err(kind)` for a curve that is not read.
fn entity_edges(e: &Entity) -> Result<Option<Vec<Edge>>, String> {
    let p = |x: f64, y: f64| P2::new(x, y);
    let (edges, normal) = match &e.specific {
        EntityType::Line(l) => (vec![Edge::line(p(l.p1.x, l.p1.y), p(l.p2.x, l.p2.y))], None),
        EntityType::Arc(a) => {
            let mut sweep = (a.end_angle - a.start_angle).rem_euclid(360.0);
            if sweep == 0.0 {
                sweep = 360.0;
            }
            let c = p(a.center.x, a.center.y);
            let arc = Edge::arc(c, a.radius, a.start_angle.to_radians(), sweep.to_radians());
            (vec![arc], Some(&a.normal))
        }
        EntityType::Circle(c) => {
            let centre = p(c.center.x, c.center.y);
            let full = Edge::arc(centre, c.radius, 0.0, std::f64::consts::TAU);
            (vec![full], Some(&c.normal))
        }
        EntityType::LwPolyline(l) => {
            let v: Vec<(P2, f64)> = l.vertices.iter().map(|v| (p(v.x, v.y), v.bulge)).collect();
            (polyline(&v, l.is_closed()), Some(&l.extrusion_direction))
        }
        EntityType::Polyline(l) => {
            // 3-D polylines, meshes and fitted curves (flags 2, 4, 8, 16, 64) are not outlines.
            if l.flags & (2 | 4 | 8 | 16 | 64) != 0 {
                return Err("a 3-D or curve-fitted POLYLINE".into());
            }
            let v: Vec<(P2, f64)> = l
                .vertices()
                .map(|v| (p(v.location.x, v.location.y), v.bulge))
                .collect();
            (polyline(&v, l.is_closed()), Some(&l.normal))
        }
        EntityType::Ellipse(_) => return Err("an ELLIPSE".into()),
        EntityType::Spline(_) => return Err("a SPLINE".into()),
        EntityType::Insert(_) => return Err("a block INSERT".into()),
        EntityType::Helix(_) | EntityType::MLine(_) | EntityType::Region(_) => {
            return Err("a HELIX, MLINE or REGION".into())
        }
        EntityType::Solid(_) | EntityType::Trace(_) => return Err("a SOLID or TRACE".into()),
        _ => return Ok(None),
    };
    if edges
        .iter()
        .any(|e| e.arc.is_some_and(|a| !(a.radius > 0.0)))
    {
        return Err("an arc or circle of radius ≤ 0".into());
    }
    if edges
        .iter()
        .any(|e| !(e.from.iter().chain(e.to.iter()).all(|x| x.is_finite())))
    {
        return Err("an entity with a coordinate that is not a finite number".into());
    }
    // The entity's own coordinates are in its object coordinate system: the drawing's for
    // the normal +z, mirrored in x for −z (the arbitrary-axis rule); any other normal is not
    // in the drawing's plane.
    match normal {
        Some(n) if n.x.abs() > 1e-12 || n.y.abs() > 1e-12 || n.z == 0.0 => {
            Err("an entity out of the drawing's plane (its normal is not ±z)".into())
        }
        Some(n) if n.z < 0.0 => Ok(Some(edges.into_iter().map(Edge::mirrored).collect())),
        _ => Ok(Some(edges)),
    }
}

/// A polyline's edges: vertex i to i + 1 with vertex i's bulge, and back to the first when
/// closed.
fn polyline(v: &[(P2, f64)], closed: bool) -> Vec<Edge> {
    let n = v.len();
    let last = if closed { n } else { n.saturating_sub(1) };
    (0..last)
        .map(|i| Edge::bulge(v[i].0, v[(i + 1) % n].0, v[i].1))
        .collect()
}
