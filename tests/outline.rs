//! Issue 34, "every counterweight a body": mass, centroid and inertia from a closed outline in
//! a DXF file (`problem::outline`, `geom::outline`), checked against closed forms. Every
//! drawing is written here with the `dxf` crate (text DXF, 12 decimals: the numbers below are
//! chosen so that this rounding stays near 1e-14 relative) and read back the program's way.
//!
//! * an annular sector (two ARCs and two LINEs; the same as one LWPOLYLINE with bulges, drawn
//!   either way round; its LINEs shuffled and reversed) against A = θ(ro² − ri²)/2,
//!   |S| = ⅔ sin(θ/2)(ro³ − ri³), J = θ(ro⁴ − ri⁴)/4, to 1e-12 relative; moved and turned in
//!   the drawing and brought back by `origin` and `angle`;
//! * a rectangle with a circular hole, and an island in the hole, against the closed form;
//! * random star-shaped polygons against a fan of triangles summed here, as LINEs in random
//!   order and direction and as polylines either way round;
//! * an open outline, a missing unit, a contradicting unit, a curve that is not read and
//!   `outline` beside `mass` are refused with the file, line and field;
//! * a linkage whose crank and counterweight come from a drawing gives the same result, to the
//!   bit, as the same numbers typed in.

use cwsynth::families::{load, solve_scene};
use cwsynth::geom::outline::Plate;
use cwsynth::geom::P2;
use cwsynth::problem::outline::{plate, OutlineRaw};
use dxf::entities::{Arc, Circle, Entity, EntityType, Line, LwPolyline};
use dxf::enums::{AcadVersion, Units};
use dxf::{Drawing, LwPolylineVertex, Point};
use std::f64::consts::{PI, TAU};
use std::path::{Path, PathBuf};

/// The tolerance of the closed-form checks (relative).
const TOL: f64 = 1e-12;

/// A new drawing in `units`.
fn drawing(units: Units) -> Drawing {
    let mut d = Drawing::new();
    d.header.version = AcadVersion::R2010;
    d.header.default_drawing_units = units;
    d
}

fn add(d: &mut Drawing, layer: &str, specific: EntityType) {
    let mut e = Entity::new(specific);
    e.common.layer = layer.into();
    d.add_entity(e);
}

fn line(d: &mut Drawing, layer: &str, a: P2, b: P2) {
    let l = Line::new(Point::new(a.x, a.y, 0.0), Point::new(b.x, b.y, 0.0));
    add(d, layer, EntityType::Line(l));
}

/// An ARC (counter-clockwise from `from` to `to`, degrees).
fn arc(d: &mut Drawing, layer: &str, c: P2, r: f64, from: f64, to: f64) {
    let a = Arc::new(Point::new(c.x, c.y, 0.0), r, from, to);
    add(d, layer, EntityType::Arc(a));
}

fn circle(d: &mut Drawing, layer: &str, c: P2, r: f64) {
    add(
        d,
        layer,
        EntityType::Circle(Circle::new(Point::new(c.x, c.y, 0.0), r)),
    );
}

/// A closed LWPOLYLINE of (vertex, bulge to the next).
fn lwpolyline(d: &mut Drawing, layer: &str, v: &[(P2, f64)]) {
    let mut p = LwPolyline {
        vertices: v
            .iter()
            .map(|(q, b)| LwPolylineVertex {
                x: q.x,
                y: q.y,
                bulge: *b,
                ..Default::default()
            })
            .collect(),
        ..Default::default()
    };
    p.set_is_closed(true);
    add(d, layer, EntityType::LwPolyline(p));
}

fn save(d: &Drawing, dir: &Path, name: &str) -> PathBuf {
    let p = dir.join(name);
    d.save_file(&p).unwrap();
    p
}

/// The outline key of `file`: thickness 1 m and density 1 kg/m³, so that the plate's mass is
/// its area (m²) and its inertia its J (m⁴).
fn key(file: &str, extra: &str) -> OutlineRaw {
    toml::from_str(&format!(
        "file = \"{file}\"\nthickness = \"1 m\"\ndensity = \"1 kg/m^3\"\n{extra}"
    ))
    .unwrap()
}

/// The plate of `file` in `dir` (mass = A, inertia = J_c, in m).
fn read(dir: &Path, file: &str, extra: &str) -> Plate {
    plate(&key(file, extra), dir, "x.outline").unwrap_or_else(|e| panic!("{e}"))
}

/// A, S and J about the origin (m) of a plate read with unit thickness and density.
fn moments(p: &Plate) -> (f64, P2, f64) {
    let s = p.centroid * p.mass;
    (p.mass, s, p.inertia + p.mass * p.centroid.norm_squared())
}

/// The largest relative error of (A, S, J) against the expected ones.
fn worst(got: (f64, P2, f64), want: (f64, P2, f64)) -> f64 {
    let r = |a: f64, b: f64| ((a - b) / b).abs();
    r(got.0, want.0)
        .max((got.1 - want.1).norm() / want.1.norm())
        .max(r(got.2, want.2))
}

/// The annular sector's A, S and J about its centre: inner and outer radii, sweep θ from the
/// angle a0 (m, rad).
fn sector(ri: f64, ro: f64, a0: f64, theta: f64) -> (f64, P2, f64) {
    let e = P2::new((a0 + theta / 2.0).cos(), (a0 + theta / 2.0).sin());
    (
        theta * (ro * ro - ri * ri) / 2.0,
        e * (2.0 / 3.0 * (theta / 2.0).sin() * (ro.powi(3) - ri.powi(3))),
        theta * (ro.powi(4) - ri.powi(4)) / 4.0,
    )
}

fn at(r: f64, deg: f64) -> P2 {
    P2::new(r * deg.to_radians().cos(), r * deg.to_radians().sin())
}

// The sector: ri = 20 mm, ro = 60 mm, from 30° through θ = 4 atan(1/2) (bulge 0.5 exactly).
const RI: f64 = 20.0;
const RO: f64 = 60.0;
const A0: f64 = 30.0;

fn theta_deg() -> f64 {
    (4.0 * 0.5f64.atan()).to_degrees()
}

/// The sector as two ARCs and two LINEs (in that order, or the LINEs first and reversed),
/// centred at `c` and turned by `turn` degrees.
fn sector_arcs(d: &mut Drawing, c: P2, turn: f64, shuffled: bool) {
    let (a0, a1) = (A0 + turn, A0 + turn + theta_deg());
    let l1 = (c + at(RI, a0), c + at(RO, a0));
    let l2 = (c + at(RO, a1), c + at(RI, a1));
    if shuffled {
        line(d, "S", l2.1, l2.0);
        line(d, "S", l1.1, l1.0);
    }
    arc(d, "S", c, RO, a0, a1);
    arc(d, "S", c, RI, a0, a1);
    if !shuffled {
        line(d, "S", l1.0, l1.1);
        line(d, "S", l2.0, l2.1);
    }
}

/// The sector as one closed LWPOLYLINE with bulges, counter-clockwise or clockwise.
fn sector_polyline(d: &mut Drawing, ccw: bool) {
    let a1 = A0 + theta_deg();
    let (p0, p1, p2, p3) = (at(RI, A0), at(RO, A0), at(RO, a1), at(RI, a1));
    if ccw {
        lwpolyline(d, "S", &[(p0, 0.0), (p1, 0.5), (p2, 0.0), (p3, -0.5)]);
    } else {
        lwpolyline(d, "S", &[(p0, 0.5), (p3, 0.0), (p2, -0.5), (p1, 0.0)]);
    }
}

#[test]
fn the_annular_sector_matches_its_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let th = theta_deg().to_radians();
    let want = sector(RI * 1e-3, RO * 1e-3, A0.to_radians(), th);
    let mut errs = Vec::new();
    for (name, draw) in [
        (
            "arcs.dxf",
            &(|d: &mut Drawing| sector_arcs(d, P2::zeros(), 0.0, false)) as &dyn Fn(&mut Drawing),
        ),
        ("arcs-shuffled.dxf", &|d| {
            sector_arcs(d, P2::zeros(), 0.0, true)
        }),
        ("polyline-ccw.dxf", &|d| sector_polyline(d, true)),
        ("polyline-cw.dxf", &|d| sector_polyline(d, false)),
    ] {
        let mut d = drawing(Units::Millimeters);
        draw(&mut d);
        save(&d, dir.path(), name);
        let e = worst(moments(&read(dir.path(), name, "")), want);
        println!("{name}: worst relative error of A, S, J {e:.1e}");
        assert!(e < TOL, "{name}: {e:e}");
        errs.push(e);
    }
    // The same sector drawn about (150, −80) mm and turned by 70°: `origin` and `angle` bring
    // it back to the frame of the first.
    let mut d = drawing(Units::Millimeters);
    sector_arcs(&mut d, P2::new(150.0, -80.0), 70.0, false);
    save(&d, dir.path(), "moved.dxf");
    let extra = "origin = [\"150 mm\", \"-80 mm\"]\nangle = \"70 deg\"";
    let e = worst(moments(&read(dir.path(), "moved.dxf", extra)), want);
    println!("moved and turned: {e:.1e}");
    assert!(e < TOL, "moved: {e:e}");
}

#[test]
fn a_rectangle_with_a_hole_and_an_island_matches_its_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let (w, h, c, r, ri) = (100.0, 40.0, P2::new(30.0, 20.0), 10.0, 4.0);
    let rect = |d: &mut Drawing| {
        let v = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)];
        lwpolyline(d, "P", &v.map(|(x, y)| (P2::new(x, y), 0.0)));
    };
    // A, S, J about the origin of a rectangle [0, w]×[0, h] and of a disc (mm).
    let m = 1e-3;
    let (wm, hm, cm, rm, rim) = (w * m, h * m, c * m, r * m, ri * m);
    let box_ = (
        wm * hm,
        P2::new(wm / 2.0, hm / 2.0) * (wm * hm),
        wm * hm * (wm * wm + hm * hm) / 3.0,
    );
    let disc = |r: f64| {
        (
            PI * r * r,
            cm * (PI * r * r),
            PI * r.powi(4) / 2.0 + PI * r * r * cm.norm_squared(),
        )
    };
    let sub = |a: (f64, P2, f64), b: (f64, P2, f64), k: f64| {
        (a.0 + k * b.0, a.1 + b.1 * k, a.2 + k * b.2)
    };

    let mut d = drawing(Units::Millimeters);
    rect(&mut d);
    circle(&mut d, "P", c, r);
    save(&d, dir.path(), "hole.dxf");
    let e = worst(
        moments(&read(dir.path(), "hole.dxf", "")),
        sub(box_, disc(rm), -1.0),
    );
    println!("rectangle with a hole: {e:.1e}");
    assert!(e < TOL, "{e:e}");

    // An island in the hole is material again (nesting parity); the hole drawn clockwise.
    let mut d = drawing(Units::Millimeters);
    rect(&mut d);
    lwpolyline(
        &mut d,
        "P",
        &[(c + P2::new(r, 0.0), -1.0), (c - P2::new(r, 0.0), -1.0)],
    );
    circle(&mut d, "P", c, ri);
    save(&d, dir.path(), "island.dxf");
    let want = sub(sub(box_, disc(rm), -1.0), disc(rim), 1.0);
    let e = worst(moments(&read(dir.path(), "island.dxf", "")), want);
    println!("with an island: {e:.1e}");
    assert!(e < TOL, "{e:e}");
}

/// splitmix64 in [0, 1).
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn random_polygons_match_a_triangulation_in_any_order_and_direction() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Rng(34);
    let mut worst_seen: f64 = 0.0;
    for case in 0..20 {
        // A star-shaped polygon about `c`: sorted random angles, random radii (mm).
        let n = 3 + (rng.unit() * 30.0) as usize;
        let c = P2::new(rng.unit() * 200.0 - 100.0, rng.unit() * 200.0 - 100.0);
        let mut ang: Vec<f64> = (0..n).map(|_| rng.unit() * TAU).collect();
        ang.sort_by(f64::total_cmp);
        let pts: Vec<P2> = ang
            .iter()
            .map(|&a| c + P2::new(a.cos(), a.sin()) * (10.0 + rng.unit() * 90.0))
            .collect();
        // Independently: the fan of triangles (c, p_i, p_i+1), each A = (b − a)×(c − a)/2,
        // centroid (a + b + c)/3, J = A (|a|² + |b|² + |c|² + a·b + b·c + c·a)/6 (m).
        let mut want = (0.0, P2::zeros(), 0.0);
        for i in 0..n {
            let (a, b, q) = (c * 1e-3, pts[i] * 1e-3, pts[(i + 1) % n] * 1e-3);
            let u = b - a;
            let v = q - a;
            let area = (u.x * v.y - u.y * v.x) / 2.0;
            let dots = a.norm_squared()
                + b.norm_squared()
                + q.norm_squared()
                + a.dot(&b)
                + b.dot(&q)
                + q.dot(&a);
            want.0 += area;
            want.1 += (a + b + q) * (area / 3.0);
            want.2 += area * dots / 6.0;
        }
        // As LINEs in random order and direction.
        let mut order: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            order.swap(i, (rng.unit() * (i + 1) as f64) as usize);
        }
        let mut d = drawing(Units::Millimeters);
        for &i in &order {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            if rng.unit() < 0.5 {
                line(&mut d, "P", a, b);
            } else {
                line(&mut d, "P", b, a);
            }
        }
        save(&d, dir.path(), "lines.dxf");
        let e = worst(moments(&read(dir.path(), "lines.dxf", "")), want);
        assert!(e < TOL, "case {case}, {n} sides, lines: {e:e}");
        worst_seen = worst_seen.max(e);
        // As polylines, counter-clockwise and clockwise.
        for rev in [false, true] {
            let mut v: Vec<(P2, f64)> = pts.iter().map(|&p| (p, 0.0)).collect();
            if rev {
                v.reverse();
            }
            let mut d = drawing(Units::Millimeters);
            lwpolyline(&mut d, "P", &v);
            save(&d, dir.path(), "poly.dxf");
            let e = worst(moments(&read(dir.path(), "poly.dxf", "")), want);
            assert!(e < TOL, "case {case}, polyline reversed {rev}: {e:e}");
            worst_seen = worst_seen.max(e);
        }
    }
    println!("20 random polygons: worst relative error {worst_seen:.1e}");
}

/// A linkage problem file whose crank is `crank` (the body of `[mechanism.links.crank]`).
fn fourbar(crank: &str, counterweight: &str) -> String {
    format!(
        r#"name = "outline-fourbar"
family = "linkage"

[mechanism]
speed = "300 rpm"
crank_length = "40 mm"

[[mechanism.dyads]]
kind = "RRR"
links = ["coupler", "rocker"]
p = "crank.tip"
length1 = "120 mm"
q = ["100 mm", "0 mm"]
length2 = "80 mm"
branch = "left"

[mechanism.links.crank]
{crank}

[mechanism.links.coupler]
mass = "0.6 kg"
uniform_bar = true

[mechanism.links.rocker]
mass = "0.4 kg"
uniform_bar = true

[[design.counterweights]]
link = "crank"
radius = "60 mm"
{counterweight}

[objective]
minimize = "peak-force"
"#
    )
}

/// The crank (a slot 40 mm long, 20 mm wide, with two 10 mm holes; layer CRANK) and an
/// annular-sector counterweight opposite (layer `cw`: radii `ri`, `ro` mm from `a0` to `a1`
/// degrees) of the linkage tests, written to `dir/name`.
fn crank_drawing(
    dir: &Path,
    name: &str,
    cw: &str,
    (ri, ro, a0, a1): (f64, f64, f64, f64),
) -> PathBuf {
    let mut d = drawing(Units::Millimeters);
    let p = |x: f64, y: f64| P2::new(x, y);
    let slot = [
        (p(0.0, -10.0), 0.0),
        (p(40.0, -10.0), 1.0),
        (p(40.0, 10.0), 0.0),
        (p(0.0, 10.0), 1.0),
    ];
    lwpolyline(&mut d, "CRANK", &slot);
    circle(&mut d, "CRANK", p(0.0, 0.0), 5.0);
    circle(&mut d, "CRANK", p(40.0, 0.0), 5.0);
    arc(&mut d, cw, P2::zeros(), ro, a0, a1);
    arc(&mut d, cw, P2::zeros(), ri, a0, a1);
    line(&mut d, cw, at(ri, a0), at(ro, a0));
    line(&mut d, cw, at(ro, a1), at(ri, a1));
    save(&d, dir, name)
}

/// The counterweight of the tests' drawing.
const TEST_CW: (f64, f64, f64, f64) = (15.0, 55.0, 100.0, 220.0);

/// The counterweight of the shipped drawing, `problems/drawings/linkage-fourbar-crank.dxf`.
const SHIPPED_CW: (f64, f64, f64, f64) = (15.0, 60.0, 100.0, 220.0);

/// Writes the shipped drawing (`cargo test --test integration outline:: -- --ignored`).
#[test]
#[ignore]
fn write_the_shipped_drawing() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems/drawings");
    std::fs::create_dir_all(&dir).unwrap();
    crank_drawing(
        &dir,
        "linkage-fourbar-crank.dxf",
        "COUNTERWEIGHT",
        SHIPPED_CW,
    );
}

const CRANK_OUTLINE: &str = r#"outline = { file = "crank.dxf", layer = "CRANK", thickness = "10 mm", density = "7850 kg/m^3" }"#;
const CW_OUTLINE: &str = r#"outline = { file = "crank.dxf", layer = "cw", thickness = "20 mm", density = "7850 kg/m^3" }"#;

#[test]
fn a_drawn_crank_and_counterweight_solve_as_the_same_numbers_typed_in() {
    let dir = tempfile::tempdir().unwrap();
    crank_drawing(dir.path(), "crank.dxf", "CW", TEST_CW);
    let drawn = dir.path().join("drawn.toml");
    std::fs::write(&drawn, fourbar(CRANK_OUTLINE, CW_OUTLINE)).unwrap();
    let body = |layer: &str, t: &str| {
        let raw: OutlineRaw = toml::from_str(&format!(
            "file = \"crank.dxf\"\nlayer = \"{layer}\"\nthickness = \"{t}\"\ndensity = \"7850 kg/m^3\""
        ))
        .unwrap();
        plate(&raw, dir.path(), "x").unwrap()
    };
    let (crank, cw) = (body("CRANK", "10 mm"), body("CW", "20 mm"));
    // The crank's closed form: a 40 × 20 mm slot with round ends, two holes of radius 5 mm,
    // centroid at half its length.
    let area = 40.0 * 20.0 + PI * 100.0 - 2.0 * PI * 25.0;
    let mass = area * 1e-9 * 10.0 * 7850.0;
    assert!(
        ((crank.mass - mass) / mass).abs() < TOL,
        "{} vs {mass}",
        crank.mass
    );
    assert!(
        (crank.centroid - P2::new(0.02, 0.0)).norm() < 1e-15,
        "{:?}",
        crank.centroid
    );
    let typed = |p: &Plate| {
        format!(
            "mass = \"{:e} kg\"\ncentroid = [\"{:e} m\", \"{:e} m\"]\ninertia = \"{:e} kg*m^2\"",
            p.mass, p.centroid.x, p.centroid.y, p.inertia
        )
    };
    let typed_file = dir.path().join("typed.toml");
    std::fs::write(&typed_file, fourbar(&typed(&crank), &typed(&cw))).unwrap();
    let (a, b) = (
        solve_scene(&load(&drawn).unwrap()),
        solve_scene(&load(&typed_file).unwrap()),
    );
    assert_eq!(
        a.status,
        cwsynth::report::Status::Analysed,
        "{:?}",
        a.warnings
    );
    assert_eq!(a.status, b.status);
    assert!(!a.objectives.is_empty());
    assert_eq!(a.objectives, b.objectives);
    assert_eq!(a.design, b.design);
    assert_eq!(a.baselines, b.baselines);
    assert_eq!(a.design["crank_counterweight_mass_kg"], cw.mass);
}

/// The error of loading the linkage file with these crank and counterweight bodies.
fn refused(dir: &Path, crank: &str, cw: &str) -> String {
    let f = dir.join("bad.toml");
    std::fs::write(&f, fourbar(crank, cw)).unwrap();
    load(&f).map(|_| ()).unwrap_err().to_string()
}

/// The 1-based line of the first line of `fourbar(crank, cw)` that starts with `start`, after
/// the line that starts with `after`.
fn line_of(crank: &str, cw: &str, after: &str, start: &str) -> usize {
    let text = fourbar(crank, cw);
    let from = text.lines().position(|l| l.starts_with(after)).unwrap();
    from + 1
        + text
            .lines()
            .skip(from)
            .position(|l| l.starts_with(start))
            .unwrap()
}

#[test]
fn bad_outlines_are_refused_with_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    crank_drawing(dir.path(), "crank.dxf", "CW", TEST_CW);
    let bad = dir.path().join("bad.toml");
    let bad = bad.display();
    let cw = "mass = \"1 kg\"\ncentroid = [\"-30 mm\", \"0 mm\"]\ninertia = \"0 kg*m^2\"";

    // Beside the keys it sets.
    let crank = format!("mass = \"1 kg\"\n{CRANK_OUTLINE}");
    let e = refused(dir.path(), &crank, cw);
    let n = line_of(&crank, cw, "[mechanism.links.crank]", "mass");
    assert!(
        e.starts_with(&format!(
            "{bad}:{n}: field `mechanism.links.crank.mass`: given with outline"
        )),
        "{e}"
    );
    let (crank, cw2) = (
        "mass = \"1 kg\"\nuniform_bar = true",
        format!("mass = \"1 kg\"\n{CW_OUTLINE}"),
    );
    let e = refused(dir.path(), crank, &cw2);
    let n = line_of(crank, &cw2, "[[design.counterweights]]", "mass");
    assert!(
        e.starts_with(&format!(
            "{bad}:{n}: field `design.counterweights[0].mass`: given with outline"
        )),
        "{e}"
    );
    // No mass at all.
    let e = refused(dir.path(), "uniform_bar = true", cw);
    assert!(
        e.contains("field `mechanism.links.crank.mass`: missing"),
        "{e}"
    );

    // An open outline: a rectangle with one corner 1 mm off.
    let mut d = drawing(Units::Millimeters);
    let p = |x: f64, y: f64| P2::new(x, y);
    line(&mut d, "0", p(0.0, 0.0), p(50.0, 0.0));
    line(&mut d, "0", p(50.0, 0.0), p(50.0, 20.0));
    line(&mut d, "0", p(50.0, 20.0), p(0.0, 20.0));
    line(&mut d, "0", p(0.0, 21.0), p(0.0, 0.0));
    save(&d, dir.path(), "open.dxf");
    let o = r#"outline = { file = "open.dxf", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    let open = dir.path().join("open.dxf");
    let n = line_of(o, cw, "[mechanism.links.crank]", "outline");
    assert!(e.starts_with(&format!("{bad}:{n}: field `mechanism.links.crank.outline.file`: {}: the outline does not close: a chain of edges ends at (0, 20) mm, the nearest free end is 1e0 mm away at (0, 21) mm", open.display())), "{e}");

    // No unit in the drawing: `unit` is needed; a contradicting one is refused.
    let mut d = drawing(Units::Unitless);
    circle(&mut d, "0", p(0.0, 0.0), 10.0);
    save(&d, dir.path(), "nounit.dxf");
    let o = r#"outline = { file = "nounit.dxf", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    assert!(
        e.contains("field `mechanism.links.crank.outline.unit`: missing")
            && e.contains("never guessed"),
        "{e}"
    );
    let o = r#"outline = { file = "nounit.dxf", unit = "in", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let f = dir.path().join("ok.toml");
    std::fs::write(&f, fourbar(o, cw)).unwrap();
    let s = load(&f).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.name, "outline-fourbar");
    let o = r#"outline = { file = "crank.dxf", layer = "CRANK", unit = "in", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    assert!(
        e.contains("field `mechanism.links.crank.outline.unit`")
            && e.contains("says its unit is mm"),
        "{e}"
    );

    // A layer with nothing on it; a file that is not there; a curve that is not read.
    let o = r#"outline = { file = "crank.dxf", layer = "NONE", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    assert!(
        e.contains("field `mechanism.links.crank.outline.layer`")
            && e.contains("layers that have them: CRANK, CW"),
        "{e}"
    );
    let o = r#"outline = { file = "none.dxf", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    assert!(
        e.contains("field `mechanism.links.crank.outline.file`") && e.contains("cannot read"),
        "{e}"
    );
    let mut d = drawing(Units::Millimeters);
    let el = dxf::entities::Ellipse {
        major_axis: dxf::Vector::new(10.0, 0.0, 0.0),
        minor_axis_ratio: 0.5,
        end_parameter: TAU,
        ..Default::default()
    };
    add(&mut d, "0", EntityType::Ellipse(el));
    save(&d, dir.path(), "ellipse.dxf");
    let o = r#"outline = { file = "ellipse.dxf", thickness = "10 mm", density = "7850 kg/m^3" }"#;
    let e = refused(dir.path(), o, cw);
    assert!(
        e.contains("an ELLIPSE on layer `0`, which is not read"),
        "{e}"
    );
}

#[test]
fn the_shipped_drawing_is_its_closed_form_and_its_scene_is_near_the_optimum() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("problems");
    let (ri, ro, a0, a1) = SHIPPED_CW;
    let th = (a1 - a0).to_radians();
    let want = sector(ri * 1e-3, ro * 1e-3, a0.to_radians(), th);
    let e = worst(
        moments(&read(
            &dir,
            "drawings/linkage-fourbar-crank.dxf",
            "layer = \"COUNTERWEIGHT\"",
        )),
        want,
    );
    println!("shipped counterweight: {e:.1e}");
    assert!(e < TOL, "{e:e}");
    let crank = read(
        &dir,
        "drawings/linkage-fourbar-crank.dxf",
        "layer = \"crank\"",
    );
    let area = (40.0 * 20.0 + PI * 100.0 - 2.0 * PI * 25.0) * 1e-6;
    assert!(((crank.mass - area) / area).abs() < TOL, "{crank:?}");
    let r = solve_scene(&load(&dir.join("linkage-fourbar-crank-outline.toml")).unwrap());
    assert_eq!(
        r.status,
        cwsynth::report::Status::Analysed,
        "{:?}",
        r.warnings
    );
    // The optimum with this crank (a designed counterweight of radius 60 mm) is 52.82 N.
    let f = r.objectives["peak_shaking_force_n"];
    assert!(f > 52.82 && f < 54.0, "{f}");
}

/// A malformed drawing is the field's error, never a panic or a hang: 300 mutants of the
/// shipped drawing (bytes flipped, lines dropped or repeated, the file cut short) each read
/// to a plate or to an error naming `outline.file` (a panic inside the `dxf` crate included).
#[test]
fn mutated_drawings_are_errors_not_panics() {
    let shipped = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/drawings/linkage-fourbar-crank.dxf"),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut state = 0x5eed_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let (mut read, mut refused) = (0, 0);
    for k in 0..300 {
        let mut lines: Vec<&[u8]> = shipped.split(|&b| b == b'\n').collect();
        let mut bytes;
        match k % 3 {
            0 => {
                bytes = shipped.clone();
                for _ in 0..1 + next() % 8 {
                    let i = (next() as usize) % bytes.len();
                    bytes[i] = (next() % 256) as u8;
                }
            }
            1 => {
                let i = (next() as usize) % lines.len();
                if next() % 2 == 0 {
                    lines.remove(i);
                } else {
                    lines.insert(i, lines[i]);
                }
                bytes = lines.join(&b'\n');
            }
            _ => bytes = shipped[..(next() as usize) % shipped.len()].to_vec(),
        }
        std::fs::write(dir.path().join("m.dxf"), &bytes).unwrap();
        let got = std::panic::catch_unwind(|| {
            plate(&key("m.dxf", "unit = \"mm\""), dir.path(), "x.outline")
        });
        match got {
            Ok(Ok(_)) => read += 1,
            Ok(Err(e)) => {
                assert!(e.to_string().contains("x.outline"), "{e}");
                refused += 1;
            }
            Err(_) => panic!("mutant {k} panicked out of `plate`"),
        }
    }
    eprintln!("{read} read, {refused} refused");
    assert_eq!(read + refused, 300);
}
