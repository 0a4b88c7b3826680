//! The DXF writer of a [`Drawing`]: each primitive as its entity, and each dimension as a
//! DIMENSION entity (aligned, radius, or angular by three points) with its definition points
//! and measurement, whose picture (the lines, arrowheads and text the SVG draws too) is the
//! anonymous block `*D<k>` it names — what AutoCAD writes, so a CAD program reads a
//! dimension it can edit and re-measure, and a reader that only draws blocks draws the same
//! picture as the SVG.

use super::{
    dim_text, dir, linear_line, sweep, text_at, Align, Drawing, DrawingError, Layer, Prim, Shape,
};
use crate::geom::P2;
use dxf::entities::{self as de, EntityType};
use dxf::enums::{DimensionType, HorizontalTextJustification, VerticalTextJustification};

/// A point in the drawing's millimetres.
fn pt(p: P2) -> dxf::Point {
    dxf::Point::new(p.x * 1e3, p.y * 1e3, 0.0)
}

impl Drawing {
    /// The DXF document (R2010, mm, `$INSUNITS` = 4; see the module doc): every shape as
    /// its entities, a dimension as a DIMENSION entity whose anonymous block `*D<k>` holds
    /// the lines, arrowheads and text that draw it.
    pub fn dxf(&self) -> Result<Vec<u8>, DrawingError> {
        use chrono::TimeZone;
        use dxf::enums::{AcadVersion, DrawingUnits, Units};
        let (prims, h) = self.primitives()?;
        let ext = Self::extent(&prims);
        let mut d = dxf::Drawing::new();
        let hd = &mut d.header;
        hd.version = AcadVersion::R2010;
        hd.default_drawing_units = Units::Millimeters;
        hd.drawing_units = DrawingUnits::Metric;
        hd.minimum_drawing_extents = pt(ext.min);
        hd.maximum_drawing_extents = pt(ext.max);
        // Fixed dates and GUIDs: the same drawing, the same bytes (1900-01-01 is the DXF
        // date epoch, written as 2415021 in any time zone).
        let local = chrono::Local
            .with_ymd_and_hms(1900, 1, 1, 0, 0, 0)
            .single()
            .ok_or_else(|| DrawingError::Dxf("no local 1900-01-01".into()))?;
        let utc = chrono::Utc.with_ymd_and_hms(1900, 1, 1, 0, 0, 0).unwrap();
        hd.creation_date = local;
        hd.update_date = local;
        hd.creation_date_universal = utc;
        hd.update_date_universal = utc;
        hd.fingerprint_guid = uuid::Uuid::nil();
        hd.version_guid = uuid::Uuid::nil();
        for l in Layer::ALL {
            d.add_layer(dxf::tables::Layer {
                name: l.name().into(),
                color: dxf::Color::from_index(l.aci()),
                ..Default::default()
            });
        }
        let mut blocks: std::collections::BTreeMap<usize, Vec<de::Entity>> = Default::default();
        for (layer, p, dim) in &prims {
            let e = entity(*layer, prim_entity(p));
            match dim {
                Some(k) => blocks.entry(*k).or_default().push(e),
                None => {
                    d.add_entity(e);
                }
            }
        }
        for (k, entities) in blocks {
            let name = format!("*D{k}");
            let Some(specific) = dimension(&self.shapes[k].1, &name, h) else {
                continue;
            };
            let mut b = dxf::Block {
                name,
                layer: Layer::Dim.name().into(),
                entities,
                ..Default::default()
            };
            b.set_is_anonymous(true);
            d.add_block(b);
            d.add_entity(entity(self.shapes[k].0, specific));
        }
        let mut buf = Vec::new();
        d.save(&mut buf)
            .map_err(|e| DrawingError::Dxf(e.to_string()))?;
        let text = String::from_utf8(buf).map_err(|e| DrawingError::Dxf(e.to_string()))?;
        Ok(own_endblk_handles(&text).into_bytes())
    }
}

/// The `dxf` crate (0.6.2, `Block::add_code_pairs`) writes each `ENDBLK` with its `BLOCK`'s
/// handle, so a reader finds that handle twice (ezdxf: "non-unique entity handle"). Here each
/// `ENDBLK` of the written text gets a handle of its own from `$HANDSEED` on, and the seed
/// moves past them. Hand-written: a fix of the writer's output, on its code pairs (a code
/// line, a value line, CRLF).
fn own_endblk_handles(text: &str) -> String {
    let mut lines: Vec<String> = text.split("\r\n").map(str::to_string).collect();
    let code = |lines: &[String], k: usize| lines.get(k).map(|l| l.trim().to_string());
    let seed_at = (0..lines.len().saturating_sub(3))
        .step_by(2)
        .find(|&k| code(&lines, k).as_deref() == Some("9") && lines[k + 1] == "$HANDSEED")
        .map(|k| k + 3);
    let Some(seed_at) = seed_at else {
        return text.to_string();
    };
    let Ok(mut next) = u64::from_str_radix(lines[seed_at].trim(), 16) else {
        return text.to_string();
    };
    let mut k = 0;
    while k + 3 < lines.len() {
        let endblk = code(&lines, k).as_deref() == Some("0") && lines[k + 1] == "ENDBLK";
        if endblk && code(&lines, k + 2).as_deref() == Some("5") {
            lines[k + 3] = format!("{next:X}");
            next += 1;
        }
        k += 2;
    }
    lines[seed_at] = format!("{next:X}");
    lines.join("\r\n")
}

/// An entity on `layer`, opaque (0x020000FF; the crate's default 0 is no valid transparency).
fn entity(layer: Layer, specific: EntityType) -> de::Entity {
    let mut e = de::Entity::new(specific);
    e.common.layer = layer.name().into();
    e.common.transparency = 0x0200_00FF;
    e
}

/// The entity of one primitive.
fn prim_entity(p: &Prim) -> EntityType {
    let specific = match p {
        Prim::Line(a, b) => EntityType::Line(de::Line::new(pt(*a), pt(*b))),
        Prim::Polyline(pts, closed) => {
            let mut pl = de::LwPolyline {
                vertices: pts
                    .iter()
                    .map(|p| dxf::LwPolylineVertex {
                        x: p.x * 1e3,
                        y: p.y * 1e3,
                        ..Default::default()
                    })
                    .collect(),
                ..Default::default()
            };
            pl.set_is_closed(*closed);
            EntityType::LwPolyline(pl)
        }
        Prim::Circle(c, r) => EntityType::Circle(de::Circle::new(pt(*c), r * 1e3)),
        Prim::Arc(c, r, s, e) => {
            let (s, e) = (
                s.to_degrees().rem_euclid(360.0),
                e.to_degrees().rem_euclid(360.0),
            );
            EntityType::Arc(de::Arc::new(pt(*c), r * 1e3, s, e))
        }
        Prim::Solid([a, b, c]) => EntityType::Solid(de::Solid::new(pt(*a), pt(*b), pt(*c), pt(*c))),
        Prim::Text {
            at,
            height,
            text,
            angle_rad,
            align,
        } => {
            let mut t = de::Text {
                location: pt(*at),
                text_height: height * 1e3,
                value: text.clone(),
                rotation: angle_rad.to_degrees(),
                ..Default::default()
            };
            if *align == Align::Centre {
                t.horizontal_text_justification = HorizontalTextJustification::Center;
                t.vertical_text_justification = VerticalTextJustification::Middle;
                t.second_alignment_point = pt(*at);
            }
            EntityType::Text(t)
        }
    };
    specific
}

/// The DIMENSION entity of a dimension shape (None for any other shape), drawn by the block
/// `block`; its text is the shape's label with `<>`, the CAD program's own measurement.
fn dimension(s: &Shape, block: &str, h: f64) -> Option<EntityType> {
    let base =
        |kind: DimensionType, at: P2, text_at: P2, label: &str, measured: f64| de::DimensionBase {
            block_name: block.into(),
            definition_point_1: pt(at),
            text_mid_point: pt(text_at),
            dimension_type: kind,
            attachment_point: dxf::enums::AttachmentPoint::MiddleCenter,
            actual_measurement: measured,
            text: dim_text(label, "<>".into()),
            is_block_reference_referenced_by_this_block_only: true,
            ..Default::default()
        };
    let text_at = text_at(s, h)?;
    Some(match s {
        Shape::Linear {
            a,
            b,
            offset,
            label,
        } => {
            let (.., b1) = linear_line(*a, *b, *offset);
            EntityType::RotatedDimension(de::RotatedDimension {
                dimension_base: base(
                    DimensionType::Aligned,
                    b1,
                    text_at,
                    label,
                    (b - a).norm() * 1e3,
                ),
                definition_point_2: pt(*a),
                definition_point_3: pt(*b),
                ..Default::default()
            })
        }
        Shape::Radius {
            centre,
            radius,
            angle_rad,
            label,
        } => EntityType::RadialDimension(de::RadialDimension {
            dimension_base: base(DimensionType::Radius, *centre, text_at, label, radius * 1e3),
            definition_point_2: pt(centre + *radius * dir(*angle_rad)),
            ..Default::default()
        }),
        Shape::Angle {
            centre,
            radius,
            start_rad,
            end_rad,
            label,
            ..
        } => {
            let sw = sweep(*start_rad, *end_rad);
            // 10: a point of the dimension arc; 13, 14: the legs; 15: the vertex. The
            // measurement of an angular dimension is in radians.
            EntityType::AngularThreePointDimension(de::AngularThreePointDimension {
                dimension_base: base(
                    DimensionType::AngularThreePoint,
                    centre + *radius * dir(start_rad + 0.5 * sw),
                    text_at,
                    label,
                    sw,
                ),
                definition_point_2: pt(centre + *radius * dir(*start_rad)),
                definition_point_3: pt(centre + *radius * dir(start_rad + sw)),
                definition_point_4: pt(*centre),
                ..Default::default()
            })
        }
        _ => return None,
    })
}
