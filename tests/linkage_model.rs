//! The general linkage's physics (`families::linkage::model`) against independent
//! references: finite differences of positions, of the momenta and of the kinetic energy, a
//! Newton–Euler solution of the joint forces, the slider-crank family's formulas, the
//! Berkof–Lowen closed form, the analytic assembly limits of a four-bar and a double-double
//! reference near a toggle.

use crate::common;

use common::dd::{dd_sin_cos, Dd};
use cwsynth::families::linkage::model::{
    Body, Dyad, Inertia, JointKind, Linkage, Params, Point, Pose,
};
use cwsynth::families::slider_crank::model::{Crank, Kinematics, Rod, SliderCrank};
use cwsynth::geom::{cross, perp, Side, P2};
use std::f64::consts::{PI, TAU};

// ---------------------------------------------------------------- fixtures

fn inertia(mass: f64, cx: f64, cy: f64, j: f64) -> Inertia {
    Inertia {
        mass,
        centroid: P2::new(cx, cy),
        j,
    }
}

/// A four-bar: A0 = 0, B0 = (a1, 0), crank a2, coupler a3, rocker a4 (m), assembled on
/// `side`, with generic mass properties (centroids off the link lines).
fn four_bar(a1: f64, a2: f64, a3: f64, a4: f64, side: Side) -> Linkage {
    Linkage::new(
        P2::zeros(),
        vec![Dyad::Rrr {
            p: Point::On {
                link: 0,
                at: P2::new(a2, 0.0),
            },
            l1: a3,
            q: Point::Frame(P2::new(a1, 0.0)),
            l2: a4,
            side,
        }],
        vec![
            inertia(0.5, 0.4 * a2, 0.01, 2e-4),
            inertia(1.2, 0.45 * a3, 0.03, 1.1e-2),
            inertia(0.9, 0.4 * a4, -0.02, 6e-3),
        ],
        50.0,
        P2::zeros(),
    )
    .unwrap()
}

/// Grashof crank-rocker: s + l = 0.1 + 0.4 ≤ p + q = 0.35 + 0.3, crank shortest.
fn crank_rocker() -> Linkage {
    four_bar(0.4, 0.1, 0.35, 0.3, Side::Left)
}

/// Grashof double-crank (drag link): the frame is the shortest link.
fn double_crank() -> Linkage {
    four_bar(0.1, 0.3, 0.35, 0.3, Side::Left)
}

/// Offset slider-crank as crank + RRP: R, L, offset e, slider on y = e along +x.
fn slider_crank(r: f64, l: f64, e: f64, masses: [Inertia; 3]) -> Linkage {
    Linkage::new(
        P2::zeros(),
        vec![Dyad::Rrp {
            p: Point::On {
                link: 0,
                at: P2::new(r, 0.0),
            },
            l,
            origin: P2::new(0.0, e),
            angle: 0.0,
            side: Side::Left,
        }],
        masses.to_vec(),
        2.0 * PI * 1000.0 / 60.0,
        P2::zeros(),
    )
    .unwrap()
}

fn offset_slider_crank() -> Linkage {
    slider_crank(
        0.035,
        0.14,
        0.01,
        [
            inertia(0.35, 0.0175, 0.002, 1e-5),
            inertia(0.3, 0.05, 0.004, 4e-4),
            inertia(1.03, 0.01, -0.005, 2e-4),
        ],
    )
}

/// Stephenson III six-bar: the crank-rocker with a coupler point C driving a second RRR dyad
/// to the frame pivot D0.
fn stephenson() -> Linkage {
    let mut dyads = crank_rocker().dyads().to_vec();
    dyads.push(Dyad::Rrr {
        p: Point::On {
            link: 1,
            at: P2::new(0.2, 0.12),
        },
        l1: 0.35,
        q: Point::Frame(P2::new(0.45, 0.45)),
        l2: 0.32,
        side: Side::Right,
    });
    let mut m = crank_rocker().inertia().to_vec();
    m.push(inertia(0.7, 0.14, 0.01, 5e-3));
    m.push(inertia(0.6, 0.11, -0.015, 3e-3));
    Linkage::new(P2::zeros(), dyads, m, 40.0, P2::zeros()).unwrap()
}

/// Watt II six-bar: the crank-rocker whose rocker is ternary (point D) drives a second
/// four-bar D–E–C0.
fn watt() -> Linkage {
    let mut dyads = crank_rocker().dyads().to_vec();
    dyads.push(Dyad::Rrr {
        p: Point::On {
            link: 2,
            at: P2::new(0.15, -0.08),
        },
        l1: 0.3,
        q: Point::Frame(P2::new(0.75, 0.05)),
        l2: 0.2,
        side: Side::Left,
    });
    let mut m = crank_rocker().inertia().to_vec();
    m.push(inertia(0.5, 0.15, 0.0, 4e-3));
    m.push(inertia(0.4, 0.08, 0.02, 2e-3));
    Linkage::new(P2::zeros(), dyads, m, 40.0, P2::zeros()).unwrap()
}

/// Crank shaper: a crank pin drives a block in a slotted lever pivoted below (RPR, with an
/// offset slot), whose tip drives the ram (RRP) on a horizontal line above.
fn shaper() -> Linkage {
    Linkage::new(
        P2::zeros(),
        vec![
            Dyad::Rpr {
                p: Point::Frame(P2::new(0.0, -0.3)),
                q: Point::On {
                    link: 0,
                    at: P2::new(0.1, 0.0),
                },
                offset: 0.02,
                side: Side::Left,
            },
            Dyad::Rrp {
                p: Point::On {
                    link: 1,
                    at: P2::new(0.5, 0.02),
                },
                l: 0.25,
                origin: P2::new(0.0, 0.3),
                angle: 0.0,
                side: Side::Left,
            },
        ],
        vec![
            inertia(0.4, 0.03, 0.0, 3e-4),
            inertia(2.0, 0.25, 0.01, 4e-2),
            inertia(0.3, 0.0, 0.0, 5e-5),
            inertia(0.8, 0.12, 0.0, 4e-3),
            inertia(3.0, 0.05, 0.02, 1e-2),
        ],
        12.0,
        P2::zeros(),
    )
    .unwrap()
}

fn fixtures() -> Vec<(&'static str, Linkage)> {
    vec![
        ("crank-rocker", crank_rocker()),
        ("double-crank", double_crank()),
        ("offset slider-crank", offset_slider_crank()),
        ("stephenson III", stephenson()),
        ("watt II", watt()),
        ("shaper (RPR + RRP)", shaper()),
    ]
}

/// A deterministic stream of angles in [0, 2π).
fn angles(seed: u64, n: usize) -> Vec<f64> {
    let mut x = seed;
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64 * TAU
        })
        .collect()
}

/// The centroid of link i and its derivatives.
fn centroid(l: &Linkage, pose: &Pose, i: usize) -> [P2; 3] {
    pose.links[i].point(l.inertia()[i].centroid)
}

fn wrap(x: f64) -> f64 {
    (x + PI).rem_euclid(TAU) - PI
}

// ---------------------------------------------------------------- (a) kinematics

#[test]
fn every_fixture_turns_fully() {
    for (name, l) in fixtures() {
        assert!(l.unreachable(720, 1e-12).is_empty(), "{name}");
    }
}

/// `places` against `pose` at θ: both fail alike, or every link's P and e agree to the bit.
fn assert_places_are_the_poses(name: &str, l: &Linkage, theta: f64) {
    match (l.pose(theta), l.places(theta)) {
        (Ok(pose), Ok(places)) => {
            assert_eq!(places.len(), pose.links.len(), "{name} at {theta}");
            for (i, (pl, ls)) in places.iter().zip(&pose.links).enumerate() {
                let bits = |v: P2| [v.x.to_bits(), v.y.to_bits()];
                assert_eq!(
                    bits(pl.p),
                    bits(ls.p[0]),
                    "{name}: P of link {i} at {theta}"
                );
                assert_eq!(bits(pl.e), bits(ls.e), "{name}: e of link {i} at {theta}");
                let at = P2::new(0.37, -0.11);
                assert_eq!(
                    bits(pl.point(at)),
                    bits(ls.point(at)[0]),
                    "{name}: X at {theta}"
                );
            }
        }
        (pose, places) => assert_eq!(pose.err(), places.err(), "{name} at {theta}"),
    }
}

/// A four-bar of random proportions (frame 0.2–0.6, crank 0.05–0.25, coupler and rocker
/// 0.1–0.5) with a second RRR dyad from a random coupler point to a random frame pivot.
fn random_six_bar(seed: u64) -> (Linkage, Linkage) {
    let u: Vec<f64> = angles(seed, 10).iter().map(|t| t / TAU).collect();
    let side = |v: f64| if v < 0.5 { Side::Left } else { Side::Right };
    let four = four_bar(
        0.2 + 0.4 * u[0],
        0.05 + 0.2 * u[1],
        0.1 + 0.4 * u[2],
        0.1 + 0.4 * u[3],
        side(u[4]),
    );
    let mut dyads = four.dyads().to_vec();
    dyads.push(Dyad::Rrr {
        p: Point::On {
            link: 1,
            at: P2::new(0.3 * u[5], 0.2 * u[6] - 0.1),
        },
        l1: 0.2 + 0.3 * u[7],
        q: Point::Frame(P2::new(0.5 * u[8], 0.4)),
        l2: 0.2 + 0.3 * u[9],
        side: side(u[6]),
    });
    let mut m = four.inertia().to_vec();
    m.extend([
        inertia(0.7, 0.14, 0.01, 5e-3),
        inertia(0.6, 0.11, -0.015, 3e-3),
    ]);
    let six = Linkage::new(P2::zeros(), dyads, m, 40.0, P2::zeros()).unwrap();
    (four, six)
}

#[test]
fn places_are_the_poses_positions_bit_for_bit() {
    for (name, l) in fixtures() {
        for theta in angles(7, 200) {
            assert_places_are_the_poses(name, &l, theta);
        }
    }
    // Random four-bars and six-bars, Grashof or not: where they assemble and where not.
    for seed in 0..40 {
        let (four, six) = random_six_bar(1000 + seed);
        for theta in angles(seed, 100) {
            assert_places_are_the_poses("random four-bar", &four, theta);
            assert_places_are_the_poses("random six-bar", &six, theta);
        }
    }
    // Towards a fold (|AB0| → a3 + a4, κ → ∞), from either side, and at the limits that
    // `unreachable` bisects to.
    let (a1, a2, a3, a4) = (0.3, 0.25, 0.15, 0.18);
    let l = four_bar(a1, a2, a3, a4, Side::Left);
    let t = limit(a1, a2, a3 + a4);
    for k in 1..=16 {
        for theta in [t - 10f64.powi(-k), t + 10f64.powi(-k)] {
            assert_places_are_the_poses("near a fold", &l, theta);
        }
    }
    for r in l.unreachable(360, 1e-15) {
        for theta in [r.from, r.to] {
            assert_places_are_the_poses("at a fold", &l, theta);
            assert!(l.places(theta).is_err(), "{theta}");
        }
    }
}

#[test]
fn derivatives_match_central_differences() {
    let h = 1e-5;
    for (name, l) in fixtures() {
        for t in angles(7, 40) {
            let (p0, pm, pp) = (
                l.pose(t).unwrap(),
                l.pose(t - h).unwrap(),
                l.pose(t + h).unwrap(),
            );
            for i in 0..l.n_links() {
                let (a, m, p) = (&p0.links[i], &pm.links[i], &pp.links[i]);
                let s1 = a.p[1].norm() + 0.1;
                let s2 = a.p[2].norm() + 0.1;
                assert!(
                    ((p.p[0] - m.p[0]) / (2.0 * h) - a.p[1]).norm() < 1e-8 * s1,
                    "{name} P'_{i} at {t}"
                );
                assert!(
                    ((p.p[1] - m.p[1]) / (2.0 * h) - a.p[2]).norm() < 1e-8 * s2,
                    "{name} P''_{i} at {t}"
                );
                let d1 = wrap(p.psi[0] - m.psi[0]) / (2.0 * h);
                assert!(
                    (d1 - a.psi[1]).abs() < 1e-8 * (a.psi[1].abs() + 1.0),
                    "{name} psi'_{i} at {t}: {d1} vs {}",
                    a.psi[1]
                );
                let d2 = (p.psi[1] - m.psi[1]) / (2.0 * h);
                assert!(
                    (d2 - a.psi[2]).abs() < 1e-8 * (a.psi[2].abs() + 1.0),
                    "{name} psi''_{i} at {t}: {d2} vs {}",
                    a.psi[2]
                );
                // e is the unit vector of ψ.
                assert!((a.e - P2::new(a.psi[0].cos(), a.psi[0].sin())).norm() < 1e-14);
                // The centroid's derivatives (points on links).
                let (g, gm, gp) = (
                    centroid(&l, &p0, i),
                    centroid(&l, &pm, i),
                    centroid(&l, &pp, i),
                );
                assert!(((gp[0] - gm[0]) / (2.0 * h) - g[1]).norm() < 1e-8 * (g[1].norm() + 0.1));
                assert!(((gp[1] - gm[1]) / (2.0 * h) - g[2]).norm() < 1e-8 * (g[2].norm() + 0.1));
            }
            for (k, d) in p0.dyads.iter().enumerate() {
                let (m, p) = (&pm.dyads[k], &pp.dyads[k]);
                let fd = (p.joint[0] - m.joint[0]) / (2.0 * h);
                assert!((fd - d.joint[1]).norm() < 1e-8 * (d.joint[1].norm() + 0.1));
                let fd = (p.var[1] - m.var[1]) / (2.0 * h);
                assert!(
                    (fd - d.var[2]).abs() < 1e-8 * (d.var[2].abs() + 0.1),
                    "{name} var''"
                );
                assert!(d.kappa() >= 1.0 && d.kappa().is_finite());
            }
        }
    }
}

#[test]
fn constructions_close_their_loops() {
    for (name, l) in fixtures() {
        for t in angles(11, 20) {
            let pose = l.pose(t).unwrap();
            for (k, d) in l.dyads().iter().enumerate() {
                let (a, b) = Linkage::dyad_links(k);
                let (la, lb) = (&pose.links[a], &pose.links[b]);
                match *d {
                    Dyad::Rrr { l1, l2, .. } => {
                        for n in 0..3 {
                            let ba = la.point(P2::new(l1, 0.0))[n];
                            let bb = lb.point(P2::new(l2, 0.0))[n];
                            assert!((ba - bb).norm() < 1e-13 * (ba.norm() + 1.0), "{name}");
                        }
                    }
                    Dyad::Rrp {
                        l, origin, angle, ..
                    } => {
                        let b = la.point(P2::new(l, 0.0));
                        for (bn, pn) in b.iter().zip(&lb.p) {
                            assert!((bn - pn).norm() < 1e-13 * (bn.norm() + 1.0));
                        }
                        let u = P2::new(angle.cos(), angle.sin());
                        assert!(cross(b[0] - origin, u).abs() < 1e-15);
                    }
                    Dyad::Rpr { offset, .. } => {
                        // Q lies on the guide's slide line at offset e.
                        let v = lb.p[0] - la.p[0];
                        assert!((cross(la.e, v) - offset).abs() < 1e-15, "{name}");
                        assert_eq!(la.psi, lb.psi);
                    }
                }
            }
        }
    }
}

// ---------------------------------------------------------------- (b) momentum

/// Linear momentum / ω, Σ m r_G', and angular momentum about O / ω, Σ [(r_G − O) × m r_G'
/// + J ψ'], written from the pose alone.
fn momenta(l: &Linkage, pose: &Pose, o: P2) -> (P2, f64) {
    let mut p = P2::zeros();
    let mut h = 0.0;
    for (i, m) in l.inertia().iter().enumerate() {
        let g = centroid(l, pose, i);
        p += g[1] * m.mass;
        h += m.mass * cross(g[0] - o, g[1]) + m.j * pose.links[i].psi[1];
    }
    (p, h)
}

/// Kinetic energy / ω², ½ Σ (m |r_G'|² + J ψ'²).
fn energy(l: &Linkage, pose: &Pose) -> f64 {
    let mut e = 0.0;
    for (i, m) in l.inertia().iter().enumerate() {
        let g = centroid(l, pose, i);
        e += 0.5 * (m.mass * g[1].norm_squared() + m.j * pose.links[i].psi[1].powi(2));
    }
    e
}

#[test]
fn shaking_force_and_moment_are_momentum_rates() {
    let h = 1e-5;
    let o = P2::new(0.05, -0.02);
    for (name, l) in fixtures() {
        let w = l.omega();
        let peak = angles(1, 64)
            .into_iter()
            .map(|t| l.fields(t, o).unwrap())
            .fold((0.0f64, 0.0f64, 0.0f64), |a, f| {
                (
                    a.0.max(f.force.norm()),
                    a.1.max(f.moment.abs()),
                    a.2.max(f.torque.abs()),
                )
            });
        for t in angles(3, 30) {
            let f = l.fields(t, o).unwrap();
            let (pp, hp) = momenta(&l, &l.pose(t + h).unwrap(), o);
            let (pm, hm) = momenta(&l, &l.pose(t - h).unwrap(), o);
            // d/dt = ω d/dθ, and the momenta carry one ω.
            let fd_force = -(pp - pm) / (2.0 * h) * (w * w);
            let fd_moment = -(hp - hm) / (2.0 * h) * (w * w);
            assert!(
                (fd_force - f.force).norm() < 1e-8 * peak.0,
                "{name} F at {t}"
            );
            assert!(
                (fd_moment - f.moment).abs() < 1e-8 * peak.1,
                "{name} M at {t}"
            );
            let de = (energy(&l, &l.pose(t + h).unwrap()) - energy(&l, &l.pose(t - h).unwrap()))
                / (2.0 * h)
                * (w * w);
            assert!((de - f.torque).abs() < 1e-8 * peak.2, "{name} T at {t}");
            // Moment about another point: M_P = M_O − (P − O) × F.
            let q = P2::new(-0.3, 0.7);
            let fq = l.fields(t, q).unwrap();
            assert!((fq.moment - (f.moment - cross(q - o, f.force))).abs() < 1e-12 * peak.1);
        }
    }
}

/// The drive's terms (issue 33) against independent evaluations from the pose alone: J is
/// twice the kinetic energy per ω² ([`energy`]), J′ its central difference, ½ J′ ω² + G the
/// balance map's input torque (with and without gravity, with a counterweight added to every
/// link), the momentum Σ m r_G′ that of [`momenta`] and its rate that momentum's difference.
#[test]
fn drive_terms_are_the_energy_its_rate_and_the_input_torque() {
    let h = 1e-5;
    for (name, l0) in fixtures() {
        for g in [P2::zeros(), P2::new(3.0, -9.81)] {
            let l = with_gravity(&l0, g);
            let w2 = l.omega() * l.omega();
            let extra: Vec<(usize, Params)> = (0..l.n_links())
                .map(|i| (i, Params::new(0.3, 0.01 * i as f64, -0.02, 4e-4)))
                .collect();
            for t in angles(11, 24) {
                let pose = l.pose(t).unwrap();
                let bare = l.drive_terms(&pose, &[]);
                let scale = bare.j.abs() + bare.dj.abs() + 1e-12;
                assert!(
                    (bare.j - 2.0 * energy(&l, &pose)).abs() < 1e-12 * scale,
                    "{name} J at {t}"
                );
                let jp = l.drive_terms(&l.pose(t + h).unwrap(), &[]).j;
                let jm = l.drive_terms(&l.pose(t - h).unwrap(), &[]).j;
                assert!(
                    ((jp - jm) / (2.0 * h) - bare.dj).abs() < 1e-7 * scale,
                    "{name} J′ at {t}: {} vs {}",
                    (jp - jm) / (2.0 * h),
                    bare.dj
                );
                let (p, _) = momenta(&l, &pose, P2::zeros());
                assert!(
                    (p - bare.momentum).norm() < 1e-12 * (p.norm() + 1e-9),
                    "{name}"
                );
                let (pp, _) = momenta(&l, &l.pose(t + h).unwrap(), P2::zeros());
                let (pm, _) = momenta(&l, &l.pose(t - h).unwrap(), P2::zeros());
                let rate = (pp - pm) / (2.0 * h);
                assert!(
                    (rate - bare.momentum_rate).norm() < 1e-7 * (rate.norm() + 1e-6),
                    "{name} momentum rate at {t}"
                );
                for ex in [&[][..], &extra[..]] {
                    let d = l.drive_terms(&pose, ex);
                    let map = l.balance_map(&pose, P2::zeros());
                    let tq = map.fields(ex).torque;
                    let f = map.fields(ex).force;
                    let tscale = map.blocks.iter().fold(0.0, |s, b| s + b.torque.norm());
                    assert!(
                        (0.5 * d.dj * w2 + d.g - tq).abs() < 1e-12 * tscale,
                        "{name} g={g:?} T at {t}: {} vs {tq}",
                        0.5 * d.dj * w2 + d.g
                    );
                    // At constant speed the shaking force is −ω² Σ m r_G″.
                    assert!((f + d.momentum_rate * w2).norm() < 1e-9 * (f.norm() + 1.0));
                }
            }
        }
    }
}

// ---------------------------------------------------------------- (c) Newton–Euler

fn with_gravity(l: &Linkage, g: P2) -> Linkage {
    Linkage::new(
        l.pivot(),
        l.dyads().to_vec(),
        l.inertia().to_vec(),
        l.omega(),
        g,
    )
    .unwrap()
}

#[test]
fn virtual_work_torque_equals_newton_euler() {
    for (name, l0) in fixtures() {
        for g in [P2::zeros(), P2::new(3.0, -9.81)] {
            let l = with_gravity(&l0, g);
            let params = l.params();
            for t in angles(5, 30) {
                let pose = l.pose(t).unwrap();
                let map = l.balance_map(&pose, P2::zeros());
                let ne = l.reactions(&pose, &params).unwrap();
                let scale = map
                    .blocks
                    .iter()
                    .zip(&params)
                    .fold(0.0, |s, (b, p)| s + b.torque.norm() * p.norm());
                assert!(
                    (ne.torque - map.base.torque).abs() < 1e-12 * scale,
                    "{name} g={g:?} at {t}: NE {} vs energy {}",
                    ne.torque,
                    map.base.torque
                );
                // The reaction map gives the same loads.
                let rm = l.reaction_map(&pose).unwrap();
                let n = rm.base.len();
                assert!((rm.base[n - 1] - ne.torque).abs() < 1e-12 * scale);
                for (j, ld) in ne.loads.iter().enumerate() {
                    for (c, v) in ld.iter().enumerate() {
                        assert!((rm.base[2 * j + c] - v).abs() < 1e-9 * (v.abs() + 1.0));
                    }
                }
            }
        }
    }
}

/// Process loads (a force at a point of the last link, over a window of the turn): the input
/// torque gains −F·X′ with X′ from central differences of the point's position (virtual
/// work), Newton–Euler with the load on its link gives the same torque, the reaction map's
/// base is the reactions of the own parameters, the shaking force does not change, and the
/// drive's G carries the load too.
#[test]
fn process_loads_enter_the_torque_by_virtual_work_and_the_joint_loads() {
    use cwsynth::families::linkage::model::ProcessLoad;
    let h = 1e-6;
    for (name, l0) in fixtures() {
        let last = l0.n_links() - 1;
        let at = P2::new(0.013, -0.007);
        let load = ProcessLoad {
            link: last,
            at,
            direction: P2::new(0.6, 0.8),
            table: vec![(0.5, 0.0), (1.5, 900.0), (2.5, 400.0), (4.0, 0.0)],
        };
        let l = with_gravity(&l0, P2::new(0.0, -9.81))
            .with_loads(vec![load.clone()])
            .unwrap();
        let bare = with_gravity(&l0, P2::new(0.0, -9.81));
        let params = l.params();
        for t in angles(17, 30) {
            let pose = l.pose(t).unwrap();
            let x = |t: f64| l.pose(t).unwrap().links[last].point(at)[0];
            let dx = (x(t + h) - x(t - h)) / (2.0 * h);
            let want = -load.force(t).dot(&dx);
            let map = l.balance_map(&pose, P2::zeros());
            let map0 = bare.balance_map(&pose, P2::zeros());
            let scale = map.load_scale + map0.base.torque.abs() + 1.0;
            assert!(
                (map.base.torque - map0.base.torque - want).abs() < 1e-6 * scale,
                "{name} at {t}: {} vs {want}",
                map.base.torque - map0.base.torque
            );
            assert_eq!(map.base.force, map0.base.force, "{name}");
            let ne = l.reactions(&pose, &params).unwrap();
            assert!(
                (ne.torque - map.base.torque).abs() < 1e-9 * scale,
                "{name} at {t}: NE {} vs energy {}",
                ne.torque,
                map.base.torque
            );
            let rm = l.reaction_map(&pose).unwrap();
            for (j, ld) in ne.loads.iter().enumerate() {
                for (c, v) in ld.iter().enumerate() {
                    assert!((rm.base[2 * j + c] - v).abs() < 1e-9 * (v.abs() + 1.0));
                }
            }
            let d = l.drive_terms(&pose, &[]);
            let d0 = bare.drive_terms(&pose, &[]);
            assert!((d.g - d0.g - map.load_torque).abs() < 1e-12 * scale);
        }
    }
}

/// Without gravity the pins and slides on the frame carry exactly the shaking force, and
/// their moment minus the motor's reaction −T is the shaking moment.
#[test]
fn frame_reactions_are_the_shaking_force_and_moment() {
    let o = P2::new(0.1, 0.2);
    for (name, l) in fixtures() {
        let params = l.params();
        let joints = l.joints();
        assert_eq!(joints.len(), 1 + 3 * l.dyads().len());
        for t in angles(9, 20) {
            let pose = l.pose(t).unwrap();
            let ne = l.reactions(&pose, &params).unwrap();
            let f = l.fields(t, o).unwrap();
            let (mut force, mut moment) = (P2::zeros(), -ne.torque);
            for (jt, ld) in joints.iter().zip(&ne.loads) {
                if jt.first != Body::Frame {
                    continue;
                }
                let s = &pose.links[jt.second];
                let (r, x, c) = match jt.kind {
                    JointKind::Revolute => (P2::new(ld[0], ld[1]), s.point(jt.at)[0], 0.0),
                    JointKind::Prismatic => (perp(s.e) * ld[0], s.p[0], ld[1]),
                };
                // The frame receives −R and −C.
                force -= r;
                moment -= cross(x - o, r) + c;
            }
            let sf = f.force.norm().max(1.0);
            assert!((force - f.force).norm() < 1e-10 * sf, "{name} F at {t}");
            assert!(
                (moment - f.moment).abs() < 1e-10 * f.moment.abs().max(1.0),
                "{name} M at {t}"
            );
        }
    }
}

// ---------------------------------------------------------------- (d) slider-crank family

#[test]
fn slider_crank_as_linkage_matches_the_family() {
    let (r, l_rod) = (0.035, 0.14);
    for e in [0.0, 0.012] {
        let family = SliderCrank {
            r,
            l: l_rod,
            e,
            kinematics: Kinematics::Exact,
            crank: Crank {
                mass: 0.35,
                centroid: r / 2.0,
            },
            rod: Rod::rigid(0.30, l_rod, None, None),
            slider_mass: 1.03,
        };
        let link = slider_crank(
            r,
            l_rod,
            e,
            [
                inertia(0.35, r / 2.0, 0.0, 0.0),
                Inertia::bar(0.30, l_rod),
                inertia(1.03, 0.0, 0.0, 0.0),
            ],
        );
        let w2 = link.omega().powi(2);
        let peak = (0..360)
            .map(|k| {
                (family.shaking_force0(&family.state(k as f64 * TAU / 360.0).unwrap()) * w2).norm()
            })
            .fold(0.0, f64::max);
        for k in 0..97 {
            let phi = k as f64 * TAU / 97.0 + 0.01;
            let st = family.state(phi).unwrap();
            let f = link.fields(phi, P2::zeros()).unwrap();
            let ff = family.shaking_force0(&st) * w2;
            assert!(
                (f.force - ff).norm() < 1e-12 * peak,
                "e={e} F at {phi}: {:?} vs {ff:?}",
                f.force
            );
            let m = family.shaking_moment0(&st) * w2;
            let t = family.drive_torque0(&st) * w2;
            assert!(
                (f.moment - m).abs() < 1e-12 * peak * l_rod,
                "M at {phi}: {} vs {m}",
                f.moment
            );
            assert!(
                (f.torque - t).abs() < 1e-12 * peak * r,
                "T at {phi}: {} vs {t}",
                f.torque
            );
        }
    }
}

// ---------------------------------------------------------------- (e) Berkof–Lowen

fn peak_force(l: &Linkage, extra: &[(usize, Params)]) -> f64 {
    (0..720)
        .map(|k| {
            let pose = l.pose(k as f64 * TAU / 720.0).unwrap();
            l.balance_map(&pose, P2::zeros()).fields(extra).force.norm()
        })
        .fold(0.0, f64::max)
}

/// A point-mass counterweight of first moment u (kg·m) at radius r: (m, u, m r²).
fn counterweight(u: P2, r: f64) -> Params {
    let m = u.norm() / r;
    Params::new(m, u.x, u.y, m * r * r)
}

#[test]
fn berkof_lowen_balances_a_four_bar() {
    for l in [
        crank_rocker(),
        double_crank(),
        four_bar(0.4, 0.1, 0.35, 0.3, Side::Right),
    ] {
        let bare = peak_force(&l, &[]);
        let fb = l.berkof_lowen().unwrap();
        // As counterweights added to the links.
        let (c, rk) = fb.links;
        let cw = [
            (c, counterweight(fb.crank_add, 0.05)),
            (rk, counterweight(fb.rocker_add, 0.07)),
        ];
        let balanced = peak_force(&l, &cw);
        assert!(balanced <= 1e-12 * bare, "{balanced} vs {bare}");
        eprintln!("Berkof–Lowen: balanced/bare peak = {:.2e}", balanced / bare);
        // As the links' own first moments.
        let mut lb = l.clone();
        for (i, u) in [(c, fb.crank), (rk, fb.rocker)] {
            let m = lb.inertia()[i];
            lb.set_inertia(
                i,
                Inertia {
                    centroid: u / m.mass,
                    ..m
                },
            )
            .unwrap();
        }
        assert!(peak_force(&lb, &[]) <= 1e-12 * bare);
    }
    // The domain doc's form for the crank-rocker (crank pin on the crank's x axis):
    // m2 r2 e^{iφ2} = m3 a2 ((r3/a3) e^{iφ3} − 1), m4 r4 e^{iφ4} = −m3 r3 (a4/a3) e^{iφ3}.
    let l = crank_rocker();
    let fb = l.berkof_lowen().unwrap();
    let (a2, a3, a4) = (0.1, 0.35, 0.3);
    let c3 = l.inertia()[1];
    let (m3, r3, phi3) = (
        c3.mass,
        c3.centroid.norm(),
        c3.centroid.y.atan2(c3.centroid.x),
    );
    let e3 = P2::new(phi3.cos(), phi3.sin());
    let want2 = (e3 * (r3 / a3) - P2::new(1.0, 0.0)) * (m3 * a2);
    let want4 = -e3 * (m3 * r3 * a4 / a3);
    assert!((fb.crank - want2).norm() < 1e-15 && (fb.rocker - want4).norm() < 1e-15);
    assert!(stephenson().berkof_lowen().is_err());
}

// ---------------------------------------------------------------- (f) non-Grashof

/// |A − B0|² = a1² + a2² − 2 a1 a2 cos θ reaches r² at θ = ±acos((a1² + a2² − r²)/(2 a1 a2)).
fn limit(a1: f64, a2: f64, r: f64) -> f64 {
    ((a1 * a1 + a2 * a2 - r * r) / (2.0 * a1 * a2)).acos()
}

#[test]
fn non_grashof_four_bars_report_their_unreachable_ranges() {
    // One range around θ = π, where |AB0| > a3 + a4.
    let (a1, a2, a3, a4) = (0.3, 0.25, 0.15, 0.18);
    let l = four_bar(a1, a2, a3, a4, Side::Left);
    let u = l.unreachable(360, 1e-13);
    assert_eq!(u.len(), 1, "{u:?}");
    let t = limit(a1, a2, a3 + a4);
    assert!((u[0].from - t).abs() < 1e-10, "{} vs {t}", u[0].from);
    assert!(
        (u[0].to - (TAU - t)).abs() < 1e-10,
        "{} vs {}",
        u[0].to,
        TAU - t
    );
    assert_eq!(u[0].dyad, 0);
    let f = l.pose(PI).unwrap_err();
    assert_eq!(f.dyad, 0);
    let d = (a1 + a2) - (a3 + a4);
    assert!((f.gap - d).abs() < 1e-15);

    // Two ranges: around θ = 0 (|AB0| < |a3 − a4|, wrapping past 0) and around π.
    let (a1, a2, a3, a4) = (0.3, 0.25, 0.2, 0.12);
    let l = four_bar(a1, a2, a3, a4, Side::Right);
    let u = l.unreachable(360, 1e-13);
    assert_eq!(u.len(), 2, "{u:?}");
    let t_in = limit(a1, a2, a3 - a4);
    let t_out = limit(a1, a2, a3 + a4);
    let near = u.iter().find(|r| r.to > TAU).expect("a range across 0");
    assert!((near.from - (TAU - t_in)).abs() < 1e-10);
    assert!((near.to - (TAU + t_in)).abs() < 1e-10);
    let far = u.iter().find(|r| r.to < TAU).unwrap();
    assert!((far.from - t_out).abs() < 1e-10 && (far.to - (TAU - t_out)).abs() < 1e-10);
    assert!(l.pose(0.0).is_err() && l.pose(PI).is_err() && l.pose(0.8).is_ok());

    // Nothing assembles.
    let l = four_bar(1.0, 0.1, 0.2, 0.3, Side::Left);
    let u = l.unreachable(36, 1e-12);
    assert_eq!(u.len(), 1);
    assert_eq!((u[0].from, u[0].to), (0.0, TAU));
}

// ---------------------------------------------------------------- (g) near toggle

/// The four-bar's coupler and rocker (ψ_a', ψ_a'', ψ_b', ψ_b'') in double-double, from the
/// same f64 inputs (cos θ, sin θ as the crank's direction).
fn dd_four_bar(a1: f64, a2: f64, a3: f64, a4: f64, side: f64, theta: f64) -> [f64; 4] {
    let (s, c) = theta.sin_cos();
    let (c, s) = (Dd::from(c), Dd::from(s));
    let _ = dd_sin_cos; // (the f64 direction is the model's input; no Dd trig needed)
    let (ax, ay) = (c * a2, s * a2);
    let (a1x, a1y) = (-s * a2, c * a2);
    let (a2x, a2y) = (-ax, -ay);
    let (dx, dy) = (Dd::from(a1) - ax, -ay);
    let dd2 = dx * dx + dy * dy;
    let d = dd2.sqrt();
    let a = (dd2 + a3 * a3 - a4 * a4) / (d * 2.0);
    let h = (Dd::from(a3 * a3) - a * a).sqrt();
    let (ux, uy) = (dx / d, dy / d);
    let (bx, by) = (ax + ux * a + (-uy) * h * side, ay + uy * a + ux * h * side);
    let (eax, eay) = ((bx - ax) / a3, (by - ay) / a3);
    let (ebx, eby) = ((bx - a1) / a4, by / a4);
    // Columns l1 J e_a and −l2 J e_b.
    let (cax, cay) = (-eay * a3, eax * a3);
    let (cbx, cby) = (eby * a4, -ebx * a4);
    let det = cax * cby - cay * cbx;
    let solve = |wx: Dd, wy: Dd| ((wx * cby - wy * cbx) / det, (cax * wy - cay * wx) / det);
    let (wa, wb) = solve(-a1x, -a1y);
    let w2x = -a2x + eax * (wa * wa * a3) - ebx * (wb * wb * a4);
    let w2y = -a2y + eay * (wa * wa * a3) - eby * (wb * wb * a4);
    let (wa2, wb2) = solve(w2x, w2y);
    [wa.into(), wa2.into(), wb.into(), wb2.into()]
}

#[test]
fn near_toggle_values_stay_finite_and_within_their_bounds() {
    let (a1, a2, a3, a4) = (0.3, 0.25, 0.15, 0.18);
    let l = four_bar(a1, a2, a3, a4, Side::Left);
    let t_lim = limit(a1, a2, a3 + a4);
    let params = l.params();
    let mut worst: f64 = 0.0;
    for k in 1..=12 {
        let dt = 10f64.powi(-k);
        let t = t_lim - dt;
        let pose = l.pose(t).unwrap();
        let map = l.balance_map(&pose, P2::zeros());
        let f = map.base;
        assert!(f.force.x.is_finite() && f.moment.is_finite() && f.torque.is_finite());
        // κ grows as dt^(−1/2).
        assert!(
            pose.kappa() > 0.1 / dt.sqrt(),
            "κ {} at dθ {dt}",
            pose.kappa()
        );
        // The derivatives against the double-double reference, within ρ of their scale.
        let r = dd_four_bar(a1, a2, a3, a4, 1.0, t);
        let (la, lb) = (&pose.links[1], &pose.links[2]);
        let got = [la.psi[1], la.psi[2], lb.psi[1], lb.psi[2]];
        let scale = [
            la.psi[1].abs(),
            la.psi[2].abs() + la.psi[1].powi(2),
            lb.psi[1].abs(),
            lb.psi[2].abs() + lb.psi[1].powi(2),
        ];
        for n in 0..4 {
            let err = (got[n] - r[n]).abs() / scale[n];
            worst = worst.max(err / map.rho);
            assert!(
                err <= map.rho,
                "dθ {dt}: quantity {n}: {} vs {} (rel {err:e}, ρ {:e})",
                got[n],
                r[n],
                map.rho
            );
        }
        // The fields' own bound is finite and grows with κ.
        let (ef, em, et) = map.error(&params, &[]);
        assert!(ef.is_finite() && em.is_finite() && et.is_finite());
        // Joint reactions still solvable (large but finite) until the very last steps.
        if k <= 8 {
            let ne = l.reactions(&pose, &params).unwrap();
            assert!(
                (ne.torque - f.torque).abs()
                    < 1e-9 * f.torque.abs().max(1.0) * pose.kappa().powi(2)
            );
        }
    }
    eprintln!(
        "near toggle: worst error / ρ = {worst:.3e}, κ up to {:.3e}",
        l.pose(t_lim - 1e-12).unwrap().kappa()
    );
    // Past the limit: a value, not a NaN.
    let f = l.pose(t_lim + 1e-9).unwrap_err();
    assert_eq!(f.dyad, 0);
    assert!(f.gap >= 0.0 && f.gap < 1e-9);
}

const BETA: f64 = 0.7;
const SHIFT: P2 = P2::new(0.37, -1.21);

fn rot(v: P2) -> P2 {
    let (s, c) = BETA.sin_cos();
    P2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// The same linkage turned by BETA and moved by SHIFT (its crank angle is θ + BETA).
fn rotated(l: &Linkage) -> Linkage {
    let mv = |pt: Point| match pt {
        Point::Frame(x) => Point::Frame(rot(x) + SHIFT),
        on => on,
    };
    let dyads = l
        .dyads()
        .iter()
        .map(|d| match *d {
            Dyad::Rrr { p, l1, q, l2, side } => Dyad::Rrr {
                p: mv(p),
                l1,
                q: mv(q),
                l2,
                side,
            },
            Dyad::Rrp {
                p,
                l,
                origin,
                angle,
                side,
            } => Dyad::Rrp {
                p: mv(p),
                l,
                origin: rot(origin) + SHIFT,
                angle: angle + BETA,
                side,
            },
            Dyad::Rpr { p, q, offset, side } => Dyad::Rpr {
                p: mv(p),
                q: mv(q),
                offset,
                side,
            },
        })
        .collect();
    Linkage::new(
        rot(l.pivot()) + SHIFT,
        dyads,
        l.inertia().to_vec(),
        l.omega(),
        P2::zeros(),
    )
    .unwrap()
}

/// The fields of `l` at θ and of its rotated copy agree within the sum of their stated
/// bounds; returns the largest |difference| / bound.
fn agree_rotated(name: &str, l: &Linkage, lr: &Linkage, t: f64) -> f64 {
    let params = l.params();
    let o = P2::new(0.02, 0.05);
    let m0 = l.balance_map(&l.pose(t).unwrap(), o);
    let m1 = lr.balance_map(&lr.pose(t + BETA).unwrap(), rot(o) + SHIFT);
    let (e0, e1) = (m0.error(&params, &[]), m1.error(&params, &[]));
    let r = [
        (rot(m0.base.force) - m1.base.force).norm() / (e0.0 + e1.0),
        (m0.base.moment - m1.base.moment).abs() / (e0.1 + e1.1),
        (m0.base.torque - m1.base.torque).abs() / (e0.2 + e1.2),
    ];
    for (q, v) in ["F", "M", "T"].iter().zip(r) {
        assert!(
            v <= 1.0,
            "{name} {q} at {t} (κ {}): {v} of the bound",
            m0.kappa
        );
    }
    r.into_iter().fold(0.0, f64::max)
}

/// Away from toggles, the rotated and translated linkage gives the rotated fields, within the
/// stated bounds (two independent roundings of the same exact value).
#[test]
fn rotation_and_translation_change_only_the_rounding() {
    for (name, l) in fixtures() {
        let lr = rotated(&l);
        for t in angles(13, 30) {
            agree_rotated(name, &l, &lr, t);
        }
    }
}

/// Linkages that cannot turn fully, one per dyad kind and one whose second dyad limits it:
/// near each end of each unreachable range the values are finite, κ is large, and the
/// rotated copy agrees within the stated bounds.
#[test]
fn near_the_limits_of_every_dyad_kind() {
    let sc = slider_crank(
        0.035,
        0.04,
        0.01,
        [
            inertia(0.35, 0.0175, 0.0, 0.0),
            Inertia::bar(0.3, 0.04),
            inertia(1.0, 0.0, 0.0, 0.0),
        ],
    );
    let mut rpr_dyads = shaper().dyads().to_vec();
    if let Dyad::Rpr { offset, .. } = &mut rpr_dyads[0] {
        *offset = 0.3;
    }
    let rpr = Linkage::new(
        P2::zeros(),
        rpr_dyads,
        shaper().inertia().to_vec(),
        12.0,
        P2::zeros(),
    )
    .unwrap();
    let mut six_dyads = stephenson().dyads().to_vec();
    if let Dyad::Rrr { l1, l2, .. } = &mut six_dyads[1] {
        (*l1, *l2) = (0.3, 0.22);
    }
    let six = Linkage::new(
        P2::zeros(),
        six_dyads,
        stephenson().inertia().to_vec(),
        40.0,
        P2::zeros(),
    )
    .unwrap();
    let cases = [
        ("RRR", four_bar(0.3, 0.25, 0.15, 0.18, Side::Left), 0),
        ("RRP", sc, 0),
        ("RPR", rpr, 0),
        ("six-bar", six, 1),
    ];
    let mut worst: f64 = 0.0;
    for (name, l, dyad) in cases {
        let u = l.unreachable(720, 1e-14);
        assert!(!u.is_empty(), "{name}");
        let lr = rotated(&l);
        for r in &u {
            assert_eq!(r.dyad, dyad, "{name}");
            for k in 3..=11 {
                let dt = 10f64.powi(-k);
                for t in [r.from - dt, r.to + dt] {
                    let pose = l.pose(t).unwrap();
                    assert!(
                        pose.kappa() > 0.01 / dt.sqrt(),
                        "{name}: κ {} at {dt}",
                        pose.kappa()
                    );
                    let f = l.fields(t, P2::zeros()).unwrap();
                    assert!(
                        f.force.norm().is_finite() && f.moment.is_finite() && f.torque.is_finite()
                    );
                    worst = worst.max(agree_rotated(name, &l, &lr, t));
                }
            }
            let mid = l.pose(0.5 * (r.from + r.to)).unwrap_err();
            assert!(mid.gap > 0.0 && mid.dyad == dyad);
        }
    }
    eprintln!("near the limits: worst |rotated − original| / bound = {worst:.3e}");
}

#[test]
fn bad_descriptions_are_typed_errors() {
    let on = |link| Point::On {
        link,
        at: P2::new(0.1, 0.0),
    };
    let rrr = |p, l1| Dyad::Rrr {
        p,
        l1,
        q: Point::Frame(P2::new(0.4, 0.0)),
        l2: 0.3,
        side: Side::Left,
    };
    let m = vec![Inertia::NONE; 3];
    assert!(Linkage::new(
        P2::zeros(),
        vec![rrr(on(1), 0.3)],
        m.clone(),
        1.0,
        P2::zeros()
    )
    .is_err());
    assert!(Linkage::new(
        P2::zeros(),
        vec![rrr(on(0), -0.3)],
        m.clone(),
        1.0,
        P2::zeros()
    )
    .is_err());
    assert!(Linkage::new(
        P2::zeros(),
        vec![rrr(on(0), 0.3)],
        m[..2].to_vec(),
        1.0,
        P2::zeros()
    )
    .is_err());
    assert!(Linkage::new(
        P2::zeros(),
        vec![rrr(on(0), 0.3)],
        m.clone(),
        f64::NAN,
        P2::zeros()
    )
    .is_err());
    let mut l = Linkage::new(P2::zeros(), vec![rrr(on(0), 0.35)], m, 1.0, P2::zeros()).unwrap();
    assert!(l.set_inertia(1, inertia(-1.0, 0.0, 0.0, 0.0)).is_err());
    assert!(l.set_inertia(5, Inertia::NONE).is_err());
}

#[test]
#[ignore]
fn timing() {
    for (name, l) in fixtures() {
        let n = 100_000;
        let t0 = std::time::Instant::now();
        let mut acc = 0.0;
        for k in 0..n {
            let pose = l.pose(k as f64 * 1e-4).unwrap();
            acc += l.balance_map(&pose, P2::zeros()).base.force.x;
        }
        let dt = t0.elapsed().as_secs_f64() / n as f64;
        let t1 = std::time::Instant::now();
        for k in 0..n / 10 {
            let pose = l.pose(k as f64 * 1e-4).unwrap();
            acc += l.reaction_map(&pose).unwrap().base[0];
        }
        let dr = t1.elapsed().as_secs_f64() / (n / 10) as f64;
        eprintln!(
            "{name}: pose+balance_map {:.2} us, pose+reaction_map {:.2} us ({acc:.1e})",
            dt * 1e6,
            dr * 1e6
        );
    }
}
