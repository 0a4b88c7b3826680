//! Issue 39: the radial engine's master and articulated rods. The shipped five-cylinder radial
//! against the linkage family's general engine (the same machine written as a crank, the
//! master rod's RRP dyad and one RRP dyad per articulated rod from a point of the master rod:
//! independent code, 1e-12); the articulated accelerations against a double-double
//! finite-difference of the closed-form positions (the stated round-off bound covers the
//! difference, near the fold of the articulated rod too); an articulated rod of zero knuckle
//! radius and the master's length is the plain slider-crank; the certified counterweight; and
//! the problem file's errors.

use crate::common::{assert_names, dd_sin_cos, problem, with, Dd, Lcg};
use cwsynth::families::linkage::file::LinkageProblem;
use cwsynth::families::multi_cylinder::articulated::Articulated;
use cwsynth::families::multi_cylinder::file::MultiCylinderProblem;
use cwsynth::families::multi_cylinder::model::Cylinder;
use cwsynth::families::{load, parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::report::Status;
use std::f64::consts::TAU;
use std::path::Path;

fn radial() -> MultiCylinderProblem {
    let s = load(&problem("radial-5-articulated.toml")).unwrap();
    s.machine::<MultiCylinderProblem>().unwrap().clone()
}

/// The layout written as a linkage-family file: the crank (its mass at the pin), the master
/// rod and piston (an RRP dyad on the master's axis), each articulated rod and piston (an RRP
/// dyad from the knuckle point of the master rod's frame), every centre of mass where the
/// multi-cylinder model puts it.
fn as_linkage(p: &MultiCylinderProblem) -> String {
    let cyl = &p.layout.cylinders;
    let m = &cyl[0];
    let sc = &m.sc;
    let mut t = format!(
        "name = \"radial-as-linkage\"\nfamily = \"linkage\"\n\n[mechanism]\nspeed = \"{} rad/s\"\ncrank_length = \"{} m\"\n",
        p.omega, sc.r
    );
    let dyad = |i: usize, from: String, l: f64, bank: f64| {
        format!(
            "\n[[mechanism.dyads]]\nkind = \"RRP\"\nlinks = [\"rod{i}\", \"piston{i}\"]\np = {from}\nlength = \"{l} m\"\nline_point = [\"0 m\", \"0 m\"]\nline_angle = \"{bank} rad\"\nbranch = \"left\"\n"
        )
    };
    t += &dyad(1, "\"crank.tip\"".into(), sc.l, m.bank);
    for (i, c) in cyl.iter().enumerate().skip(1) {
        let a = c.articulated.unwrap();
        let at = P2::new(a.knuckle_angle.cos(), a.knuckle_angle.sin()) * a.knuckle_radius;
        let from = format!(
            "{{ link = \"rod1\", at = [\"{} m\", \"{} m\"] }}",
            at.x, at.y
        );
        t += &dyad(i + 1, from, c.sc.l, c.bank);
    }
    let link = |name: String, mass: f64, x: f64, inertia: f64| {
        format!(
            "\n[mechanism.links.{name}]\nmass = \"{mass} kg\"\ncentroid = [\"{x} m\", \"0 m\"]\ninertia = \"{inertia} kg*m^2\"\n"
        )
    };
    t += &link("crank".into(), sc.crank.mass, sc.crank.centroid, 0.0);
    for (i, c) in cyl.iter().enumerate() {
        let rod = &c.sc.rod;
        t += &link(format!("rod{}", i + 1), rod.mass, rod.centroid, rod.inertia);
        t += &link(format!("piston{}", i + 1), c.sc.slider_mass, 0.0, 0.0);
    }
    t + "\n[objective]\nminimize = \"peak-force\"\n"
}

#[test]
fn the_radial_is_the_linkage_engines_crank_master_rod_and_articulated_dyads() {
    let p = radial();
    let text = as_linkage(&p);
    let s = parse_str(&text, Path::new("radial-as-linkage.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    let lk = &s.machine::<LinkageProblem>().unwrap().scene.linkage;
    let w2 = p.omega * p.omega;
    let alpha = p.layout.cylinders[0].phase;
    let scale = p.layout.scale() * w2;
    let (mut worst, mut worst_roll): (f64, f64) = (0.0, 0.0);
    let roll_bound: f64 = w2
        * p.layout
            .cylinders
            .iter()
            .map(|c| c.roll_error0())
            .sum::<f64>();
    for k in 0..720 {
        let phi = TAU * k as f64 / 720.0 + 0.003;
        let ours = p.layout.shaking0(phi).unwrap().force * w2;
        let theirs = lk.fields(phi + alpha, P2::zeros()).unwrap();
        worst = worst.max((ours - theirs.force).norm());
        // The roll: the linkage's shaking moment about the crank's pivot (the shaft).
        let roll = p.layout.roll0(phi).unwrap() * w2;
        worst_roll = worst_roll.max((roll - theirs.moment).abs());
    }
    eprintln!("radial vs linkage engine: force {worst:e} N (scale {scale:e} N), roll {worst_roll:e} N·m (bound {roll_bound:e})");
    assert!(
        worst <= 1e-12 * scale,
        "{worst} N against a scale of {scale} N"
    );
    assert!(
        worst_roll <= roll_bound,
        "roll off by {worst_roll} N·m, bound {roll_bound}"
    );
}

/// The articulated piston's distance s and knuckle pin K at θ in double-double (positions
/// only: the closed-form dyads, no derivatives).
fn dd_position(a: &Articulated, r: f64, l: f64, bank: f64, theta: Dd) -> (Dd, [Dd; 2]) {
    let (st, ct) = dd_sin_cos(theta);
    let (cx, cy) = (ct * r, st * r);
    let big_l = Dd::from(a.master_rod);
    let c = (big_l * big_l - cy * cy).sqrt();
    let (ux, uy) = (c / big_l, -cy / big_l);
    let (sd, cd) = dd_sin_cos(Dd::from(a.knuckle_angle));
    let kx = cx + (cd * ux - sd * uy) * a.knuckle_radius;
    let ky = cy + (sd * ux + cd * uy) * a.knuckle_radius;
    let (sp, cp) = dd_sin_cos(Dd::from(bank) - Dd::from(a.master_bank));
    let aa = kx * cp + ky * sp;
    let b = -kx * sp + ky * cp;
    let ll = Dd::from(l);
    (aa + (ll * ll - b * b).sqrt(), [kx, ky])
}

/// f″ by the sixth-order central difference (2, −27, 270, −490, 270, −27, 2)/(180h²).
fn second(f: impl Fn(Dd) -> Dd, x: Dd, h: f64) -> Dd {
    let w = [2.0, -27.0, 270.0, -490.0, 270.0, -27.0, 2.0];
    let mut sum = Dd::from(0.0);
    for (j, wj) in w.iter().enumerate() {
        sum += f(x + (j as f64 - 3.0) * h) * *wj;
    }
    sum / (180.0 * h * h)
}

#[test]
fn the_articulated_accelerations_are_within_their_round_off_bound() {
    let mut rng = Lcg(39_002);
    let mut ratio: f64 = 0.0;
    for case in 0..200 {
        let r = rng.range(0.03, 0.08);
        let big_l = r * rng.range(1.2, 5.0);
        let rk = r * rng.range(0.0, 1.5);
        // Every fourth case near the fold: the rod just reaches its axis (R + r_k ≈ l).
        let l = if case % 4 == 0 {
            (r + rk) * (1.0 + rng.log(1e-4, 1e-2))
        } else {
            (r + rk) * rng.range(1.1, 3.0)
        };
        let a = Articulated {
            master_bank: rng.range(-3.0, 3.0),
            master_rod: big_l,
            knuckle_radius: rk,
            knuckle_angle: rng.range(-3.0, 3.0),
        };
        let bank = rng.range(-3.0, 3.0);
        let theta = rng.range(0.0, TAU);
        let st = a.state(r, l, bank, theta).unwrap();
        let h = 1e-5;
        let pos = |t: Dd| dd_position(&a, r, l, bank, t);
        let s2 = second(|t| pos(t).0, Dd::from(theta), h);
        let k2 = [0, 1].map(|j| second(|t| pos(t).1[j], Dd::from(theta), h));
        let err_s = (Dd::from(st.s[2]) - s2).abs().hi();
        let err_k = (Dd::from(st.k[2].x) - k2[0])
            .abs()
            .hi()
            .max((Dd::from(st.k[2].y) - k2[1]).abs().hi());
        let bound = a.acc_error(r, l);
        assert!(
            err_s <= bound && err_k <= bound,
            "case {case}: s'' off by {err_s:e}, K'' by {err_k:e}, bound {bound:e}"
        );
        ratio = ratio.max(err_s.max(err_k) / bound);
    }
    eprintln!("articulated round-off: worst error / bound = {ratio:e}");
    // The bound is not vacuous: within four decades of the worst error seen.
    assert!(ratio > 1e-4, "{ratio}");
}

#[test]
fn an_articulated_rod_on_the_crank_pin_is_the_plain_slider_crank() {
    let p = radial();
    let mut rng = Lcg(39_003);
    for c in p.layout.cylinders.iter().skip(1) {
        let plain = Cylinder {
            sc: cwsynth::families::slider_crank::model::SliderCrank {
                l: p.layout.cylinders[0].sc.l,
                ..c.sc
            },
            articulated: None,
            ..c.clone()
        };
        let mut on_pin = plain.clone();
        on_pin.articulated = Some(Articulated {
            knuckle_radius: 0.0,
            ..c.articulated.unwrap()
        });
        for _ in 0..50 {
            let phi = rng.range(0.0, TAU);
            let (a, b) = (plain.force0(phi).unwrap(), on_pin.force0(phi).unwrap());
            assert!((a - b).norm() <= 1e-14 * p.layout.scale(), "{a:?} vs {b:?}");
        }
    }
}

#[test]
fn the_shipped_radials_counterweight_is_certified_and_its_articulation_is_visible() {
    let s = load(&problem("radial-5-articulated.toml")).unwrap();
    let r = solve_scene(&s);
    assert_eq!(r.status, Status::Optimal, "{:?}", r.warnings);
    let d = &r.derived;
    // The textbook's idealised secondary (every rod on the pin) is a twentieth of the
    // articulated layout's.
    assert!(
        d["bare_secondary_force_forward_n"] > 10.0 * d["textbook_secondary_force_forward_n"],
        "{} vs {}",
        d["bare_secondary_force_forward_n"],
        d["textbook_secondary_force_forward_n"]
    );
    // The counterweight takes the primary's forward part almost whole.
    assert!(d["primary_force_forward_n"] < 0.02 * d["bare_primary_force_forward_n"]);
    assert!(
        r.objectives["peak_shaking_force_n"] < 0.2 * r.baselines["bare"]["peak_shaking_force_n"]
    );
    assert_eq!(
        r.model["firing"],
        "four-stroke: 1 even firing order, every 144.0000°: 1-3-5-2-4"
    );
}

#[test]
fn articulated_rods_are_checked_with_file_line_and_field() {
    let base = std::fs::read_to_string(problem("radial-5-articulated.toml")).unwrap();
    assert_names(
        &with(
            &base,
            "phase = \"90 deg\"\nbank = \"162 deg\"",
            "phase = \"91 deg\"\nbank = \"162 deg\"",
        ),
        "mechanism.cylinders[1].articulated",
        "articulated = { knuckle_radius = \"62 mm\", rod_length = \"190 mm\" }",
        "0 cylinders could be this rod's master",
    );
    assert_names(
        &with(
            &base,
            "kinematics = \"exact\"",
            "kinematics = \"two-harmonic\"",
        ),
        "model.kinematics",
        "kinematics = \"two-harmonic\"",
        "articulated rods need",
    );
    assert_names(
        &with(
            &base,
            "bank = \"234 deg\"\n",
            "bank = \"234 deg\"\ncrank_mass = \"1 kg\"\n",
        ),
        "mechanism.cylinders[2].crank_mass",
        "crank_mass = \"1 kg\"",
        "no throw of its own",
    );
    assert_names(
        &with(
            &base,
            "rod_length = \"190 mm\" }",
            "rod_length = \"120 mm\" }",
        ),
        "mechanism.cylinders[1].articulated.rod_length",
        "rod_length = \"120 mm\" }",
        "cannot reach its cylinder axis",
    );
    assert_names(
        &with(
            &base,
            "[objective]",
            "[design.phases]\nstep = \"72 deg\"\n\n[objective]",
        ),
        "design.phases",
        "[design.phases]",
        "share their master's throw",
    );
}

#[test]
fn lumped_in_line_cylinders_exert_no_roll_and_the_radials_articulation_does() {
    // Point masses on the crank circle at constant speed and on lines through the shaft:
    // r × r̈ = 0 for each, so the inline-3's roll moment vanishes within its bound.
    let r = solve_scene(&load(&problem("inline-3-balance-shaft.toml")).unwrap());
    let (v, e) = (
        r.derived["peak_roll_moment_nm"],
        r.derived["peak_roll_moment_error_nm"],
    );
    assert!(v <= e, "{v} ± {e}");
    let r = solve_scene(&load(&problem("radial-5-articulated.toml")).unwrap());
    assert!(r.derived["peak_roll_moment_nm"] > 100.0);
}
