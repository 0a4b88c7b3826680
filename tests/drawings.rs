//! Drawings end to end (`report::drawing`): every shipped scene writes
//! `<name>-drawing.dxf` and `<name>-drawing.svg`, linked from its report; each DXF, read back
//! with the `dxf` crate, is R2010 in millimetres (`$INSUNITS` = 4) and its geometry and
//! dimensions match the design to 1e-9 m (the plate's rᵢ, rₒ, θ and r_c, the gears' centre
//! distance and pitch radius, the crane's link lengths, the linkage's counterweight radii,
//! the slider-crank mechanism's R, L and counterweight radius r, the hypocycloid's R, r, L
//! and its Lanchester shafts with their masses' half-discs, e and d);
//! every SVG has one scale in x and y, and everything it draws lies inside its viewBox; the
//! files are the same bytes on a second run; a batch lists them in its manifest.

use crate::common;
use common::*;
use dxf::entities::EntityType;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Tolerance on a length read back from a DXF (m).
const TOL: f64 = 1e-9;

/// `cwsynth solve --json --out DIR FILES…`: the result JSONs by scene name.
fn solve(files: &[PathBuf], dir: &Path) -> BTreeMap<String, Value> {
    let out = Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["solve", "--json", "--out"])
        .arg(dir)
        .args(files)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            (v["name"].as_str().unwrap().to_string(), v)
        })
        .collect()
}

/// A length of a shipped problem's `[mechanism]` (`crank_radius`, …) in m, through the
/// program's own unit parser.
fn mechanism_length(file: &Path, key: &str) -> Option<f64> {
    let t: toml::Table = std::fs::read_to_string(file).unwrap().parse().unwrap();
    let text = t.get("mechanism")?.get(key)?.as_str()?.to_string();
    Some(cwsynth::units::parse_any(&text).unwrap().0)
}

/// A DXF read back, with its entities by layer in metres.
struct Dxf {
    d: dxf::Drawing,
}

impl Dxf {
    fn load(path: &Path) -> Dxf {
        let d = dxf::Drawing::load_file(path).unwrap();
        assert_eq!(d.header.version, dxf::enums::AcadVersion::R2010);
        assert_eq!(
            d.header.default_drawing_units,
            dxf::enums::Units::Millimeters,
            "{}",
            path.display()
        );
        assert_eq!(d.header.drawing_units, dxf::enums::DrawingUnits::Metric);
        let layers: Vec<&str> = d.layers().map(|l| l.name.as_str()).collect();
        for l in ["OUTLINE", "CENTRE", "DIM", "PATH", "NOTE"] {
            assert!(layers.contains(&l), "{}: layer {l} missing", path.display());
        }
        Dxf { d }
    }

    /// The entities of a layer as a reader draws them: the model space's, and the pictures
    /// (blocks) of its DIMENSION entities.
    fn on<'a>(&'a self, layer: &'a str) -> impl Iterator<Item = &'a EntityType> + 'a {
        let pictures = self
            .d
            .entities()
            .filter_map(|e| dimension(&e.specific))
            .flat_map(move |(base, _)| {
                self.d
                    .blocks()
                    .filter(move |b| b.name == base.block_name)
                    .flat_map(|b| b.entities.iter())
            });
        self.d
            .entities()
            .chain(pictures)
            .filter(move |e| e.common.layer == layer)
            .map(|e| &e.specific)
    }

    /// Every DIMENSION: its block exists and draws something, and its measurement is what
    /// its definition points measure (mm; an angle in radians). Returns how many.
    fn check_dimensions(&self, name: &str) -> usize {
        let mut n = 0;
        for e in self.d.entities() {
            let Some((base, measured)) = dimension(&e.specific) else {
                continue;
            };
            n += 1;
            assert_eq!(e.common.layer, "DIM", "{name}");
            assert!(
                base.block_name.starts_with("*D"),
                "{name}: {}",
                base.block_name
            );
            let block = self.d.blocks().find(|b| b.name == base.block_name);
            assert!(
                block.is_some_and(|b| !b.entities.is_empty() && b.is_anonymous()),
                "{name}: block {} of a dimension",
                base.block_name
            );
            assert!(base.text.contains("<>"), "{name}: {}", base.text);
            let (m, truth) = (base.actual_measurement, measured);
            assert!(
                (m - truth).abs() <= 1e-9 * truth.max(1.0),
                "{name}: {} measures {truth}, says {m}",
                base.block_name
            );
        }
        n
    }

    /// The LINEs of a layer as ((x, y), (x, y)) in m.
    fn lines(&self, layer: &str) -> Vec<([f64; 2], [f64; 2])> {
        self.on(layer)
            .filter_map(|e| match e {
                EntityType::Line(l) => Some((
                    [l.p1.x * 1e-3, l.p1.y * 1e-3],
                    [l.p2.x * 1e-3, l.p2.y * 1e-3],
                )),
                _ => None,
            })
            .collect()
    }

    /// The lengths of a layer's LINEs (m).
    fn lengths(&self, layer: &str) -> Vec<f64> {
        self.lines(layer)
            .iter()
            .map(|(a, b)| (b[0] - a[0]).hypot(b[1] - a[1]))
            .collect()
    }

    /// The ARCs of a layer: (radius m, sweep rad).
    fn arcs(&self, layer: &str) -> Vec<(f64, f64)> {
        self.on(layer)
            .filter_map(|e| match e {
                EntityType::Arc(a) => Some((
                    a.radius * 1e-3,
                    (a.end_angle - a.start_angle).rem_euclid(360.0).to_radians(),
                )),
                _ => None,
            })
            .collect()
    }

    /// The CIRCLEs of a layer: (centre m, radius m).
    fn circles(&self, layer: &str) -> Vec<([f64; 2], f64)> {
        self.on(layer)
            .filter_map(|e| match e {
                EntityType::Circle(c) => {
                    Some(([c.center.x * 1e-3, c.center.y * 1e-3], c.radius * 1e-3))
                }
                _ => None,
            })
            .collect()
    }

    /// The TEXTs of a layer.
    fn texts(&self, layer: &str) -> Vec<String> {
        self.on(layer)
            .filter_map(|e| match e {
                EntityType::Text(t) => Some(t.value.clone()),
                _ => None,
            })
            .collect()
    }
}

/// A DIMENSION's common part and what its definition points measure (mm, or rad for an
/// angle), None for any other entity.
fn dimension(e: &EntityType) -> Option<(&dxf::entities::DimensionBase, f64)> {
    let d = |a: &dxf::Point, b: &dxf::Point| (a.x - b.x).hypot(a.y - b.y);
    Some(match e {
        EntityType::RotatedDimension(r) => (
            &r.dimension_base,
            d(&r.definition_point_2, &r.definition_point_3),
        ),
        EntityType::RadialDimension(r) => (
            &r.dimension_base,
            d(&r.dimension_base.definition_point_1, &r.definition_point_2),
        ),
        EntityType::AngularThreePointDimension(a) => {
            let v = &a.definition_point_4;
            let (p, q) = (&a.definition_point_2, &a.definition_point_3);
            let t = (q.y - v.y).atan2(q.x - v.x) - (p.y - v.y).atan2(p.x - v.x);
            let t = t.rem_euclid(std::f64::consts::TAU);
            (
                &a.dimension_base,
                if t == 0.0 { std::f64::consts::TAU } else { t },
            )
        }
        _ => return None,
    })
}

/// `xs` has a value within `tol` of `want`.
#[track_caller]
fn has(xs: &[f64], want: f64, tol: f64, what: &str) {
    let best = xs
        .iter()
        .map(|x| (x - want).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        best <= tol,
        "{what}: nothing within {tol:e} of {want} (closest off by {best:e}) in {xs:?}"
    );
}

/// The DIM text `label = value` (mm or degrees, 2 decimals) is there.
#[track_caller]
fn has_text(d: &Dxf, label: &str, value: f64, unit: &str) {
    let want = format!("{label} = {value:.2}{unit}");
    let texts = d.texts("DIM");
    assert!(texts.contains(&want), "no `{want}` in {texts:?}");
}

fn design(v: &Value, key: &str) -> f64 {
    v["design"][key]
        .as_f64()
        .unwrap_or_else(|| panic!("no design.{key}"))
}

/// The viewBox, width and height of an SVG, and every coordinate pair it draws.
fn svg_frame(svg: &str) -> ([f64; 4], f64, f64) {
    let attr = |name: &str| -> String {
        let key = format!(" {name}=\"");
        let i = svg.find(&key).unwrap() + key.len();
        svg[i..i + svg[i..].find('"').unwrap()].to_string()
    };
    let vb: Vec<f64> = attr("viewBox")
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    (
        [vb[0], vb[1], vb[2], vb[3]],
        attr("width").parse().unwrap(),
        attr("height").parse().unwrap(),
    )
}

#[test]
fn every_drawing_scene_writes_dimensioned_dxf_and_equal_aspect_svg() {
    let dir = tempfile::tempdir().unwrap();
    let results = solve(&shipped(), dir.path());
    assert_eq!(results.len(), shipped().len());
    let mut drawn = BTreeMap::<String, usize>::new();
    let pair = regex::Regex::new(r"[ML](-?[0-9.]+),(-?[0-9.]+)").unwrap();
    for (name, v) in &results {
        let (dxf_path, svg_path) = (
            dir.path().join(format!("{name}-drawing.dxf")),
            dir.path().join(format!("{name}-drawing.svg")),
        );
        let md = std::fs::read_to_string(dir.path().join(format!("{name}.md"))).unwrap();
        *drawn
            .entry(v["family"].as_str().unwrap().to_string())
            .or_default() += 1;
        assert!(
            md.contains(&format!(
                "[SVG]({name}-drawing.svg) · [DXF]({name}-drawing.dxf)"
            )),
            "{name}: the report links the drawing"
        );
        // The link sits in the design section, before the objectives.
        assert!(md.find("-drawing.svg").unwrap() < md.find("## Objectives").unwrap());

        // SVG: one scale in x and y; everything drawn inside the viewBox.
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        assert!(!svg.contains("not made"), "{name}: {svg}");
        let ([x0, y0, w, h], pw, ph) = svg_frame(&svg);
        let (sx, sy) = (pw / w, ph / h);
        assert!(
            (sx / sy - 1.0).abs() < 1e-12,
            "{name}: scales {sx} and {sy}"
        );
        for c in pair.captures_iter(&svg) {
            let (x, y): (f64, f64) = (c[1].parse().unwrap(), c[2].parse().unwrap());
            assert!(
                (x0..=x0 + w).contains(&x) && (y0..=y0 + h).contains(&y),
                "{name}: ({x}, {y}) outside the viewBox {x0} {y0} {w} {h}"
            );
        }

        let d = Dxf::load(&dxf_path);
        assert!(!d.texts("NOTE").is_empty(), "{name}: a title");
        assert!(d.check_dimensions(name) > 0, "{name}: DIMENSION entities");
        match v["family"].as_str().unwrap() {
            "slider-crank" if !v["shape"]["sector"].is_object() => {
                mechanism_checks(&d, v, &problem(&format!("{name}.toml")));
            }
            "hypocycloid" => hypocycloid_checks(&d, v),
            "slider-crank" => {
                let s = &v["shape"]["sector"];
                let f = |k: &str| s[k].as_f64().unwrap();
                let (ri, ro, th, rc) = (
                    f("inner_radius_m"),
                    f("outer_radius_m"),
                    f("angle_rad"),
                    f("centroid_radius_m"),
                );
                let arcs = d.arcs("OUTLINE");
                assert_eq!(arcs.len(), 2, "{name}: the plate's two arcs");
                let radii: Vec<f64> = arcs.iter().map(|a| a.0).collect();
                has(&radii, ri, TOL, "rᵢ");
                has(&radii, ro, TOL, "rₒ");
                for a in &arcs {
                    assert!((a.1 - th).abs() < 1e-9, "{name}: sweep {} ≠ θ {th}", a.1);
                }
                // The two radial edges run from rᵢ to rₒ.
                has(&d.lengths("OUTLINE"), ro - ri, TOL, "radial edge");
                // Dimension lines as long as what they measure, texts to 0.01 mm.
                let dims = d.lengths("DIM");
                for (want, what) in [(ri, "rᵢ"), (ro, "rₒ"), (rc, "r_c")] {
                    has(&dims, want, TOL, what);
                }
                has_text(&d, "rᵢ", ri * 1e3, "");
                has_text(&d, "rₒ", ro * 1e3, "");
                has_text(&d, "r_c", rc * 1e3, "");
                has_text(&d, "θ", th.to_degrees(), "°");
                let dim_arcs = d.arcs("DIM");
                assert!((dim_arcs[0].1 - th).abs() < 1e-9, "{name}: θ's arc");
            }
            "eccentric-gear" => {
                let a = v["derived"]["center_distance_m"].as_f64().unwrap();
                let big_r = design(v, "pitch_radius_m");
                // O1–O2 on the centre line, and the dimension line, are a long.
                has(&d.lengths("CENTRE"), a, TOL, "centre line O1O2");
                has(&d.lengths("DIM"), a, TOL, "centre distance dimension");
                has_text(&d, "a", a * 1e3, "");
                // Gear 1's pitch circle, R about C at e from O1.
                let c = d.circles("OUTLINE");
                assert_eq!(c.len(), 1, "{name}");
                assert!((c[0].1 - big_r).abs() < TOL);
                let e = design(v, "eccentricity_m");
                assert!((c[0].0[0].hypot(c[0].0[1]) - e).abs() < TOL);
                let polys: Vec<_> = d
                    .on("OUTLINE")
                    .filter_map(|e| match e {
                        EntityType::LwPolyline(p) => Some(p),
                        _ => None,
                    })
                    .collect();
                if v["derived"].get("tooth_profile_closure_gap_m").is_none() {
                    assert_eq!(polys.len(), 1, "{name}: gear 2's pitch curve");
                } else {
                    // With model.tooth_profiles: gear 1's tooth outline lies between the
                    // circles R − 2r and R + 2r about C and reaches both (the tips and roots
                    // of its cycloid arches).
                    assert_eq!(polys.len(), 3, "{name}: pitch curve and two tooth outlines");
                    let rg = design(v, "generating_radius_m");
                    let dist: Vec<f64> = polys[1]
                        .vertices
                        .iter()
                        .map(|q| (q.x * 1e-3 - e).hypot(q.y * 1e-3))
                        .collect();
                    let lo = dist.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = dist.iter().copied().fold(0.0, f64::max);
                    assert!((lo - (big_r - 2.0 * rg)).abs() < TOL, "{name}: roots {lo}");
                    assert!((hi - (big_r + 2.0 * rg)).abs() < TOL, "{name}: tips {hi}");
                    assert!(polys[1].is_closed() && polys[2].is_closed());
                }
            }
            "multi-cylinder" => {
                // Seen along the shaft: a line of length R per throw (cylinders of one phase
                // share it) from the axis; from the side: each plane a line of 2R; the
                // planes' spacings dimensioned.
                let s = cwsynth::families::load(&problem(&format!("{name}.toml"))).unwrap();
                let p = s
                    .machine::<cwsynth::families::multi_cylinder::file::MultiCylinderProblem>()
                    .unwrap();
                let r = p.layout.cylinders[0].sc.r;
                let outline = d.lengths("OUTLINE");
                let distinct =
                    |f: &dyn Fn(&cwsynth::families::multi_cylinder::model::Cylinder) -> f64| {
                        let mut v: Vec<f64> = p.layout.cylinders.iter().map(f).collect();
                        v.sort_by(f64::total_cmp);
                        v.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
                        v.len()
                    };
                let count = |l: f64| outline.iter().filter(|&&x| (x - l).abs() < TOL).count();
                // A phase search draws the chosen phases (the result's).
                let chosen = |c: &cwsynth::families::multi_cylinder::model::Cylinder| {
                    let i = (p.layout.cylinders.iter())
                        .position(|o| std::ptr::eq(c, o))
                        .unwrap();
                    v["design"][format!("cylinder_{}_phase_rad", i + 1)]
                        .as_f64()
                        .unwrap_or(c.phase)
                        .rem_euclid(std::f64::consts::TAU)
                };
                assert_eq!(count(r), distinct(&chosen), "{name}: a line per throw");
                assert_eq!(
                    count(2.0 * r),
                    distinct(&|c| c.z),
                    "{name}: a line per plane"
                );
                let mut z: Vec<f64> = p.layout.cylinders.iter().map(|c| c.z).collect();
                z.sort_by(f64::total_cmp);
                z.dedup();
                let dims = d.lengths("DIM");
                for w in z.windows(2) {
                    has(&dims, w[1] - w[0], TOL, "plane spacing");
                }
            }
            "luffing-crane" => {
                let outline = d.lengths("OUTLINE");
                let dims = d.lengths("DIM");
                for key in [
                    "boom_length_m",
                    "jib_length_m",
                    "jib_tail_m",
                    "tie_length_m",
                ] {
                    let Some(want) = v["design"][key].as_f64() else {
                        continue;
                    };
                    has(&dims, want, TOL, key);
                }
                // The boom A–D from the origin at both reaches.
                let boom = design(v, "boom_length_m");
                let from_a: Vec<f64> = d
                    .lines("OUTLINE")
                    .iter()
                    .filter(|(a, _)| a[0] == 0.0 && a[1] == 0.0)
                    .map(|(_, b)| b[0].hypot(b[1]))
                    .collect();
                // With a boom counterweight, its lever from A at both reaches too; a hung one
                // hangs from its suspension points on the boom's extension (lines from A to
                // them); a lever one pivots on the A-frame (no line from A). A hung or lever
                // counterweight is drawn at its path's centroids (`counterweight_path`).
                let path = &v["balance"]["counterweight_path"];
                let pt = |p: &serde_json::Value| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()];
                let want: Vec<f64> = if path.is_null() {
                    v["design"]["counterweight_lever_m"]
                        .as_f64()
                        .map_or(Vec::new(), |lv| vec![lv, lv])
                } else {
                    path["suspension_point_m"]
                        .as_array()
                        .map_or(Vec::new(), |s| {
                            s.iter().map(|p| pt(p)[0].hypot(pt(p)[1])).collect()
                        })
                };
                let (booms, mut levers): (Vec<f64>, Vec<f64>) =
                    from_a.iter().partition(|&&l| (l - boom).abs() < TOL);
                assert_eq!(booms.len(), 2, "{name}: the boom at two reaches");
                assert_eq!(levers.len(), want.len(), "{name}: lines from A {levers:?}");
                levers.sort_by(f64::total_cmp);
                let mut want = want;
                want.sort_by(f64::total_cmp);
                for (l, w) in levers.iter().zip(&want) {
                    assert!((l - w).abs() < TOL, "{name}: lever {l} ≠ {w}");
                }
                if let Some(cs) = path["centroid_m"].as_array() {
                    let circles = d.circles("OUTLINE");
                    for c in cs.iter().map(pt) {
                        assert!(
                            circles
                                .iter()
                                .any(|(o, _)| (o[0] - c[0]).hypot(o[1] - c[1]) < TOL),
                            "{name}: no weight drawn at the centroid {c:?}"
                        );
                    }
                }
                has_text(&d, "L_c", boom * 1e3, "");
                assert!(!outline.is_empty());
                let paths = d
                    .on("PATH")
                    .filter(|e| matches!(e, EntityType::LwPolyline(_)));
                assert_eq!(paths.count(), 2, "{name}: jib-head and jib-tail paths");
            }
            "linkage" => {
                let dims = d.lengths("DIM");
                let mut n = 0;
                for (k, r) in v["design"].as_object().unwrap() {
                    let Some(link) = k.strip_suffix("_counterweight_radius_m") else {
                        continue;
                    };
                    let m = design(v, &format!("{link}_counterweight_mass_kg"));
                    if m <= 0.0 {
                        continue;
                    }
                    let r = r.as_f64().unwrap();
                    has(&dims, r, TOL, k);
                    has_text(&d, &format!("r ({link})"), r * 1e3, "");
                    n += 1;
                }
                // One disc per counterweight.
                assert!(d.circles("OUTLINE").len() >= n, "{name}");
                // A plate is drawn as cut: its cutting circle's arc, or its ring.
                let radii: Vec<f64> = d.arcs("OUTLINE").iter().map(|a| a.0).collect();
                let rings: Vec<f64> = d.circles("OUTLINE").iter().map(|c| c.1).collect();
                for (k, r) in v["design"].as_object().unwrap() {
                    match k {
                        k if k.ends_with("_plate_cut_radius_m") => {
                            let r = r.as_f64().unwrap();
                            has(&radii, r, 1e-9 * r, k)
                        }
                        k if k.ends_with("_plate_outer_radius_m") => {
                            has(&rings, r.as_f64().unwrap(), TOL, k)
                        }
                        _ => {}
                    }
                }
                // A counterweight from a drawing is drawn as drawn.
                if name.ends_with("-outline") {
                    assert!(
                        d.texts("NOTE")
                            .iter()
                            .any(|t| t.contains("drawn as in its drawing")),
                        "{name}: {:?}",
                        d.texts("NOTE")
                    );
                }
            }
            f => panic!("{name}: family {f} has no drawing check"),
        }
    }
    // Every shipped scene draws: the felling heads (designed for the drive, over the
    // envelope, with Lanchester balancers) their plate, the pistons (with balancers, a
    // flywheel, an envelope) their mechanism, the textbook engines theirs with a stand-in rod.
    assert_eq!(drawn.values().sum::<usize>(), shipped().len(), "{drawn:?}");
    assert_eq!(drawn.get("slider-crank"), Some(&11), "{drawn:?}");
    for f in ["eccentric-gear", "luffing-crane", "linkage", "hypocycloid"] {
        assert!(drawn.get(f).is_some_and(|n| *n >= 2), "{f}: {drawn:?}");
    }
}

/// The LINEs of `layer` from `a` (to 1e-9 m): their other ends.
fn lines_from(d: &Dxf, layer: &str, a: [f64; 2]) -> Vec<[f64; 2]> {
    d.lines(layer)
        .iter()
        .filter(|(p, _)| (p[0] - a[0]).hypot(p[1] - a[1]) < TOL)
        .map(|(_, q)| *q)
        .collect()
}

/// A slider-crank without a plate: the crank OA = R from O and the rod AB = L at φ = 0 with
/// B on the slider line y = e, R and L dimensioned; the counterweight disc at r, β from the
/// crank with r dimensioned (or, unsized, the note |U| = m·r).
#[track_caller]
fn mechanism_checks(d: &Dxf, v: &Value, file: &Path) {
    let big_r = mechanism_length(file, "crank_radius").unwrap();
    let e = v["model"]["offset_m"].as_f64().unwrap();
    let dims = d.lengths("DIM");
    has(&dims, big_r, TOL, "R");
    has_text(d, "R", big_r * 1e3, "");
    // Obliquity neglected with no rod length: the rod is drawn at 4R, not dimensioned.
    let big_l = match mechanism_length(file, "rod_length") {
        Some(l) => {
            has(&dims, l, TOL, "L");
            has_text(d, "L", l * 1e3, "");
            l
        }
        None => {
            assert!(
                d.texts("NOTE").iter().any(|t| t.contains("not to scale")),
                "the stand-in rod is said not to scale"
            );
            4.0 * big_r
        }
    };
    // The crank at φ = 0 ends at A = (R, 0); the rod from A reaches B on y = e at L.
    let a = [big_r, 0.0];
    assert!(lines_from(d, "OUTLINE", [0.0, 0.0])
        .iter()
        .any(|p| (p[0] - a[0]).hypot(p[1] - a[1]) < TOL));
    let rods: Vec<[f64; 2]> = lines_from(d, "OUTLINE", a)
        .into_iter()
        .filter(|b| (b[1] - e).abs() < TOL)
        .collect();
    assert_eq!(rods.len(), 1, "the rod A–B at φ = 0");
    let b = rods[0];
    assert!(((b[0] - a[0]).hypot(b[1] - a[1]) - big_l).abs() < TOL);
    let beta = design(v, "counterweight_angle_rad");
    match v["design"]["counterweight_radius_m"].as_f64() {
        Some(rc) => {
            has(&dims, rc, TOL, "r");
            has_text(d, "r", rc * 1e3, "");
            let c = [rc * beta.cos(), rc * beta.sin()];
            assert!(
                d.circles("OUTLINE")
                    .iter()
                    .any(|(p, _)| (p[0] - c[0]).hypot(p[1] - c[1]) < TOL),
                "the counterweight disc at r, β"
            );
        }
        None => assert!(
            d.texts("NOTE").iter().any(|t| t.contains("size by m·r")),
            "{:?}",
            d.texts("NOTE")
        ),
    }
}

/// The hypocycloid mechanism at φ = 0: R, r, L dimensioned; the ring (3R/2 about O) and
/// the planet (R/2 about O₁ = (R, 0)); the rod A–B of length L with B on the x axis; the
/// path of A, closed, through A at φ = 0 and within R(1 + θ) of O.
#[track_caller]
fn hypocycloid_checks(d: &Dxf, v: &Value) {
    let (big_r, r, big_l) = (
        design(v, "carrier_radius_m"),
        design(v, "crank_arm_m"),
        design(v, "rod_length_m"),
    );
    let dims = d.lengths("DIM");
    for (want, label) in [(big_r, "R"), (r, "r"), (big_l, "L")] {
        has(&dims, want, TOL, label);
        has_text(d, label, want * 1e3, "");
    }
    let circles = d.circles("OUTLINE");
    for (c, rad) in [([0.0, 0.0], 1.5 * big_r), ([big_r, 0.0], 0.5 * big_r)] {
        assert!(
            circles
                .iter()
                .any(|(p, q)| (p[0] - c[0]).hypot(p[1] - c[1]) < TOL && (q - rad).abs() < TOL),
            "a circle of radius {rad} about {c:?} in {circles:?}"
        );
    }
    let alpha0 = v["model"]["orientation_rad"].as_f64().unwrap();
    let a = [big_r + r * alpha0.cos(), r * alpha0.sin()];
    let ends = lines_from(d, "OUTLINE", [big_r, 0.0]);
    assert!(
        ends.iter().any(|p| (p[0] - a[0]).hypot(p[1] - a[1]) < TOL),
        "the crank arm O₁A"
    );
    let rods: Vec<[f64; 2]> = lines_from(d, "OUTLINE", a)
        .into_iter()
        .filter(|b| b[1].abs() < TOL)
        .collect();
    assert_eq!(rods.len(), 1, "the rod A–B");
    assert!(((rods[0][0] - a[0]).hypot(rods[0][1] - a[1]) - big_l).abs() < TOL);
    let paths: Vec<_> = d
        .on("PATH")
        .filter_map(|e| match e {
            EntityType::LwPolyline(p) => Some(p),
            _ => None,
        })
        .collect();
    assert_eq!(paths.len(), 1, "the path of A");
    let p = paths[0];
    assert!(p.is_closed());
    let v0 = &p.vertices[0];
    assert!((v0.x * 1e-3 - a[0]).abs() < TOL && (v0.y * 1e-3 - a[1]).abs() < TOL);
    for q in &p.vertices {
        assert!((q.x * 1e-3).hypot(q.y * 1e-3) <= big_r + r + TOL);
    }
    lanchester_checks(d, v, &dims);
}

/// The Lanchester shafts where the file places them (`[mechanism.lanchester]`, the
/// result's `dynamics.couples.layout`): the co-rotating shaft at (d/2, e) and the
/// counter-rotating one at (−d/2, e), each a journal circle; about each, per balanced order
/// (`balancing`), a half-disc's arc (sweep π) of the radius whose steel half-disc 20 mm thick
/// (assumed) has the pair's m′r′ = ρ_steel t (2/3) ρ³, its middle at the mass's angle at
/// φ = 0 (`phase_co_rad`, `phase_counter_rad`); e and d dimensioned. No shafts without
/// the layout.
#[track_caller]
fn lanchester_checks(d: &Dxf, v: &Value, dims: &[f64]) {
    // (centre, radius, middle angle, sweep) of the OUTLINE arcs, m and rad.
    let arcs: Vec<([f64; 2], f64, f64, f64)> = d
        .on("OUTLINE")
        .filter_map(|e| match e {
            EntityType::Arc(a) => {
                let sweep = (a.end_angle - a.start_angle).rem_euclid(360.0);
                Some((
                    [a.center.x * 1e-3, a.center.y * 1e-3],
                    a.radius * 1e-3,
                    (a.start_angle + 0.5 * sweep).to_radians(),
                    sweep.to_radians(),
                ))
            }
            _ => None,
        })
        .collect();
    let Some(layout) = v["dynamics"]["couples"]["layout"].as_object() else {
        assert!(arcs.is_empty(), "no shafts without [mechanism.lanchester]");
        return;
    };
    let (e, spacing) = (
        layout["offset"].as_f64().unwrap(),
        layout["spacing"].as_f64().unwrap(),
    );
    has(dims, e.abs(), TOL, "e");
    has(dims, spacing, TOL, "d");
    let sigma = 7850.0 * 0.02;
    let circles = d.circles("OUTLINE");
    let pairs = v["balancing"].as_array().unwrap();
    assert_eq!(
        arcs.len(),
        2 * pairs.len(),
        "a half-disc per order and shaft"
    );
    for (c, phase) in [
        ([0.5 * spacing, e], "phase_co_rad"),
        ([-0.5 * spacing, e], "phase_counter_rad"),
    ] {
        assert!(
            circles
                .iter()
                .any(|(p, _)| (p[0] - c[0]).hypot(p[1] - c[1]) < TOL),
            "the shaft at {c:?}"
        );
        for pair in pairs {
            let s = pair["static_moment_kgm"].as_f64().unwrap();
            let rho = (1.5 * s / sigma).cbrt();
            let mid = pair[phase].as_f64().unwrap();
            assert!(
                arcs.iter().any(|(p, r, m, sw)| {
                    let turn = (m - mid).rem_euclid(std::f64::consts::TAU);
                    (p[0] - c[0]).hypot(p[1] - c[1]) < TOL
                        && (r - rho).abs() < TOL
                        && turn.min(std::f64::consts::TAU - turn) < 1e-9
                        && (sw - std::f64::consts::PI).abs() < 1e-9
                }),
                "order {} at {c:?}: a half-disc of radius {rho} towards {mid} in {arcs:?}",
                pair["order"]
            );
        }
    }
}

#[test]
fn a_slider_crank_whose_counterweight_is_not_sized_draws_the_unbalance_direction() {
    let text = std::fs::read_to_string(problem("piston-1000rpm.toml")).unwrap();
    let text = with(&text, "radius = \"50 mm\"", "");
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("piston-1000rpm.toml");
    std::fs::write(&file, text).unwrap();
    let v = &solve(std::slice::from_ref(&file), dir.path())["piston-1000rpm"];
    assert!(v["design"]["counterweight_radius_m"].is_null());
    let d = Dxf::load(&dir.path().join("piston-1000rpm-drawing.dxf"));
    mechanism_checks(&d, v, &problem("piston-1000rpm.toml"));
    let svg = std::fs::read_to_string(dir.path().join("piston-1000rpm-drawing.svg")).unwrap();
    assert!(svg.contains("size by m·r"));
}

#[test]
fn drawings_are_the_same_bytes_every_run_and_listed_in_a_batch_manifest() {
    let file = problem("felling-head-150rpm.toml");
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    solve(std::slice::from_ref(&file), a.path());
    // A second process, a second later: the DXF header carries no clock or random GUID.
    std::thread::sleep(std::time::Duration::from_millis(1100));
    let out = Command::new(env!("CARGO_BIN_EXE_cwsynth"))
        .args(["batch", "--quiet", "--threads", "1", "--out"])
        .arg(b.path())
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for ext in ["dxf", "svg"] {
        let f = format!("felling-head-150rpm-drawing.{ext}");
        let (x, y) = (
            std::fs::read(a.path().join(&f)).unwrap(),
            std::fs::read(b.path().join(&f)).unwrap(),
        );
        assert!(x == y, "{f} differs between runs");
    }
    let v: Value =
        serde_json::from_slice(&std::fs::read(b.path().join("felling-head-150rpm.json")).unwrap())
            .unwrap();
    let files = v["batch"]["files"].as_object().unwrap();
    for ext in ["dxf", "svg"] {
        let f = format!("felling-head-150rpm-drawing.{ext}");
        assert!(files.contains_key(&f), "{f} not in the manifest: {files:?}");
    }
}
