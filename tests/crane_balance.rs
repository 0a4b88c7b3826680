//! The luffing crane's boom counterweight and member forces (issue 19, thesis `003` ch. 1
//! Fig 1.5 and §2.2): the statics' drive torque against an independent virtual-work
//! evaluation (complex-step derivative of the potential energy, with its own pose code), the
//! certified counterweight against closed forms and a brute-force grid, the thesis's
//! M_Ah = N L_c sin α against the load moment, and the shipped scene.

use crate::common;

use cwsynth::families::crane::balance::{self, BalanceScene, CounterweightSpec};
use cwsynth::families::crane::model::{load_moment, Guide, Linkage};
use cwsynth::families::crane::statics::{statics, HoistRope, Loads, SelfWeight};
use cwsynth::families::{parse_str, solve_scene};
use cwsynth::geom::P2;
use cwsynth::report::Status;
use cwsynth::synth::counterweight::Status as CwStatus;
use cwsynth::synth::minimax::Settings;
use nalgebra::Complex;

const G: f64 = 9.80665;

/// A linkage: L_c and the step-1 angles (deg), k1, k2.
fn linkage(l_c: f64, deg: [f64; 4], k1: f64, k2: f64) -> Linkage {
    common::crane_linkage(l_c, deg, k1, k2)
}

/// The thesis's worked example (§3.4.2).
fn thesis() -> Linkage {
    linkage(22.8, [35.0, 10.0, 5.0, 12.0], 0.2, 0.4)
}

/// The Tukan 40T geometry the optimiser finds (results/crane-tukan-40t-optimise.json).
fn tukan() -> Linkage {
    common::tukan_linkage()
}

/// V(φ) = g Σ m y of every weight, the counterweight included, with its own pose (circle
/// intersection written out in complex arithmetic, the textbook form), at a complex φ.
fn potential_c(
    link: &Linkage,
    phi: Complex<f64>,
    w: &SelfWeight,
    q: f64,
    u: [f64; 2],
    sign: f64,
    rope: Option<HoistRope>,
) -> Complex<f64> {
    let Guide::Circle { centre: b, radius } = link.guide else {
        panic!("a tie")
    };
    let (bx, by) = (Complex::new(b.x, 0.0), Complex::new(b.y, 0.0));
    let dx = -phi.cos() * link.l_c;
    let dy = phi.sin() * link.l_c;
    let (vx, vy) = (bx - dx, by - dy);
    let d = (vx * vx + vy * vy).sqrt();
    let a = link.a;
    let foot = (d * d + a * a - radius * radius) / (d * 2.0);
    let h = (foot * (-foot) + a * a).sqrt();
    let (ux, uy) = (vx / d, vy / d);
    let ex = dx + ux * foot - uy * h * sign;
    let ey = dy + uy * foot + ux * h * sign;
    let cy = dy + (dy - ey) / link.k2;
    let cx = dx + (dx - ex) / link.k2;
    // The load hangs |S − C|/n lower than it would with a rope of constant length to C.
    let yl = match rope {
        Some(r) => {
            let (sx, sy) = (r.sheave.x - cx, r.sheave.y - cy);
            cy + (sx * sx + sy * sy).sqrt() / r.parts
        }
        None => cy,
    };
    let yj = dy + (cy - dy) * w.jib_centroid;
    let ycw = phi.sin() * u[0] - phi.cos() * u[1];
    (dy * (w.boom_mass * w.boom_centroid)
        + yj * w.jib_mass
        + (ey + by) * (0.5 * w.tie_mass)
        + yl * q
        + ycw)
        * G
}

/// dV/dφ by the complex step, Im V(φ + ih)/h: no subtraction, exact to rounding. The branch
/// sign is the one whose real pose matches the linkage's.
fn virtual_work(
    link: &Linkage,
    phi: f64,
    w: &SelfWeight,
    q: f64,
    u: [f64; 2],
    rope: Option<HoistRope>,
) -> f64 {
    let e = link.pose(phi).unwrap().e;
    let sign = [1.0, -1.0]
        .into_iter()
        .min_by(|&s1, &s2| {
            let at = |s: f64| {
                let Guide::Circle { centre: b, radius } = link.guide else {
                    unreachable!()
                };
                let d = cwsynth::families::crane::model::boom_head(link.l_c, phi);
                let v = b - d;
                let dd = v.norm();
                let foot = (dd * dd + link.a * link.a - radius * radius) / (2.0 * dd);
                let h = (link.a * link.a - foot * foot).max(0.0).sqrt();
                let (ux, uy) = (v.x / dd, v.y / dd);
                let p = nalgebra::Vector2::new(
                    d.x + ux * foot - uy * h * s,
                    d.y + uy * foot + ux * h * s,
                );
                (p - e).norm()
            };
            at(s1).total_cmp(&at(s2))
        })
        .unwrap();
    let h = 1e-30;
    potential_c(link, Complex::new(phi, h), w, q, u, sign, rope).im / h
}

fn masses(boom: f64, sb: f64, jib: f64, fj: f64, tie: f64) -> SelfWeight {
    SelfWeight {
        boom_mass: boom,
        boom_centroid: sb,
        jib_mass: jib,
        jib_centroid: fj,
        tie_mass: tie,
    }
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn in_range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The acceptance check: with the optimal counterweight, the statics' drive torque equals
/// the virtual-work derivative of the potential at 10 luffing positions, within its stated
/// error, on the thesis and Tukan geometries with random masses, loads and centroids.
#[test]
fn drive_torque_with_the_optimal_counterweight_is_virtual_work_at_ten_positions() {
    let mut rng = Rng(19);
    let mut worst: f64 = 0.0;
    for (i, link) in [thesis(), tukan(), thesis(), tukan(), thesis(), tukan()]
        .iter()
        .enumerate()
    {
        let w = masses(
            rng.in_range(5e3, 30e3),
            rng.in_range(0.3, 0.6),
            rng.in_range(2e3, 12e3),
            rng.in_range(-link.k2, 1.0),
            rng.in_range(0.5e3, 5e3),
        );
        let q = rng.in_range(0.0, 40e3);
        // The last three with an inclined hoist rope from a sheave behind the foot.
        let rope = (i >= 3).then(|| HoistRope {
            sheave: P2::new(rng.in_range(1.0, 6.0), rng.in_range(4.0, 14.0)),
            parts: (1 + i % 3) as f64,
        });
        let scene = BalanceScene {
            self_weight: w,
            jib_centroid: Some(w.jib_centroid),
            counterweight: Some(CounterweightSpec {
                max_mass: 100e3,
                lever: rng.in_range(3.0, 8.0),
                directions: (i % 2 == 0).then_some((150f64.to_radians(), 210f64.to_radians())),
                kind: cwsynth::families::crane::balance::CounterweightKind::Boom,
            }),
            load_mass: Some(q),
            rope,
            masses: true,
        };
        let bal = balance::solve(link, &scene, 5.0, &Settings::default(), 16).unwrap();
        let cw = bal.counterweight.as_ref().unwrap();
        assert_eq!(cw.status, CwStatus::Optimal, "scene {i}: {:?}", cw.note);
        let (u, m) = (cw.static_moment_kgm, cw.mass_kg);
        let [p0, p1] = link.phi_range;
        for k in 0..10 {
            let phi = p0 + (p1 - p0) * k as f64 / 9.0;
            for load in [0.0, q] {
                let pose = link.pose(phi).unwrap();
                let loads = Loads {
                    load_mass: load,
                    counterweight_mass: m,
                    counterweight_moment: u,
                    rope,
                };
                let s = statics(link, phi, &pose, &w, &loads).unwrap();
                let t_vw = virtual_work(link, phi, &w, load, u, rope);
                let diff = (s.drive_torque - t_vw).abs();
                // The complex step's own rounding: a few ε of the terms' sizes.
                let cs_round =
                    1e-14 * G * (w.boom_mass + w.jib_mass + w.tie_mass + load + m) * 40.0;
                assert!(
                    diff <= s.drive_torque_error + cs_round,
                    "scene {i} phi {phi}: statics {} vs virtual work {t_vw}: {diff:e} > {:e}",
                    s.drive_torque,
                    s.drive_torque_error
                );
                worst = worst.max(diff / t_vw.abs().max(1.0));
            }
        }
        assert!(
            bal.virtual_work_check.pass,
            "scene {i}: {:?}",
            bal.virtual_work_check
        );
    }
    assert!(worst < 1e-11, "relative difference {worst:e}");
}

/// Only the boom's weight: T₀ = g m_b s_b L_c cos φ, cancelled exactly by
/// u = (−m_b s_b L_c, 0), which the certified solve must find (peak ≈ 0).
#[test]
fn a_boom_alone_is_balanced_exactly_by_the_closed_form_counterweight() {
    let link = thesis();
    let w = masses(12e3, 0.45, 0.0, 0.3, 0.0);
    let scene = BalanceScene {
        self_weight: w,
        jib_centroid: Some(0.3),
        counterweight: Some(CounterweightSpec {
            max_mass: 50e3,
            lever: 5.0,
            directions: None,
            kind: cwsynth::families::crane::balance::CounterweightKind::Boom,
        }),
        load_mass: None,
        rope: None,
        masses: true,
    };
    let bal = balance::solve(&link, &scene, 5.0, &Settings::default(), 16).unwrap();
    let want = -12e3 * 0.45 * link.l_c;
    let unb = bal.unbalanced[0].peak_nm;
    let closed = G * 12e3 * 0.45 * link.l_c * link.phi_range[0].cos();
    assert!(
        (unb - closed).abs() <= bal.unbalanced[0].error_nm + 1e-9 * closed,
        "{unb} vs {closed}"
    );
    let cw = bal.counterweight.unwrap();
    assert_eq!(cw.status, CwStatus::Optimal, "{:?}", cw.note);
    // Certified to the engine's absolute floor (0.1 × 1e-9 of the unbalanced peak).
    assert!(
        cw.peak_drive_torque_nm <= 1e-9 * unb,
        "{}",
        cw.peak_drive_torque_nm
    );
    let u = cw.static_moment_kgm;
    assert!((u[0] - want).abs() <= 1e-8 * want.abs(), "{u:?} vs {want}");
    assert!(u[1].abs() <= 1e-8 * want.abs(), "{u:?}");
    assert!((cw.mass_kg - want.abs() / 5.0).abs() <= 1e-8 * cw.mass_kg);
}

/// The certified optimum against a brute force: a 2-D grid of u around it, each design's
/// peak over both cases on 2001 angles. No grid point beats the optimum by more than its
/// error, and the grid's best is within the grid's resolution of it.
#[test]
fn the_counterweight_is_the_brute_force_minimax() {
    let link = tukan();
    let w = masses(22e3, 0.45, 9e3, 0.29, 3.5e3);
    let q = 40e3;
    let scene = BalanceScene {
        self_weight: w,
        jib_centroid: Some(0.29),
        counterweight: Some(CounterweightSpec {
            max_mass: 1e6,
            lever: 6.0,
            directions: None,
            kind: cwsynth::families::crane::balance::CounterweightKind::Boom,
        }),
        load_mass: Some(q),
        rope: None,
        masses: true,
    };
    let bal = balance::solve(&link, &scene, 2.5, &Settings::default(), 16).unwrap();
    let cw = bal.counterweight.unwrap();
    assert_eq!(cw.status, CwStatus::Optimal);
    let [p0, p1] = link.phi_range;
    let angles: Vec<f64> = (0..=2000)
        .map(|k| p0 + (p1 - p0) * k as f64 / 2000.0)
        .collect();
    let t0: Vec<[f64; 2]> = angles
        .iter()
        .map(|&phi| {
            let pose = link.pose(phi).unwrap();
            [0.0, q].map(|load| {
                let l = Loads {
                    load_mass: load,
                    ..Loads::default()
                };
                statics(&link, phi, &pose, &w, &l).unwrap().drive_torque
            })
        })
        .collect();
    let peak = |u: [f64; 2]| -> f64 {
        angles
            .iter()
            .zip(&t0)
            .map(|(&phi, t)| {
                let c = G * (u[0] * phi.cos() + u[1] * phi.sin());
                (t[0] + c).abs().max((t[1] + c).abs())
            })
            .fold(0.0, f64::max)
    };
    let opt = cw.peak_drive_torque_nm;
    // The optimum's own dense peak: V is the refined peak, the grid can only be below it.
    let at_opt = peak(cw.static_moment_kgm);
    assert!(
        at_opt <= opt + cw.error_nm && at_opt >= opt * (1.0 - 1e-6),
        "{at_opt} vs {opt}"
    );
    let [u0, u1] = cw.static_moment_kgm;
    let span = 0.2 * u0.hypot(u1);
    let mut best = f64::INFINITY;
    let n = 60;
    for i in 0..=n {
        for j in 0..=n {
            let u = [
                u0 - span + 2.0 * span * i as f64 / n as f64,
                u1 - span + 2.0 * span * j as f64 / n as f64,
            ];
            let p = peak(u);
            assert!(
                p >= opt - cw.error_nm - 1e-9 * opt,
                "grid point {u:?} beats the optimum: {p} < {opt}"
            );
            best = best.min(p);
        }
    }
    // The grid's step is 2·span/n in u, g·step in torque at most.
    assert!(
        best - opt <= G * 2.0 * span / n as f64 * 1.5,
        "{best} vs {opt}"
    );
    // The balanced peak is an equioscillation: the two cases' peaks are both near V or one is.
    assert!(bal
        .balanced
        .iter()
        .any(|c| (c.peak_nm - opt).abs() <= cw.error_nm + 1e-9 * opt));
}

/// Thesis §2.2: the load's unbalanced moment about A is M_Ah = N L_c sin α, N the resultant
/// of the load and the tie force through the boom head. With a weightless jib and tie it is
/// the statics' head moment and equals the virtual-work load moment Q g dy_C/dφ.
#[test]
fn the_theses_head_moment_is_the_load_moment() {
    let link = thesis();
    let w = masses(0.0, 0.5, 0.0, 0.3, 0.0);
    let q = 10e3;
    let [p0, p1] = link.phi_range;
    for k in 0..=8 {
        let phi = p0 + (p1 - p0) * k as f64 / 8.0;
        let pose = link.pose(phi).unwrap();
        let l = Loads {
            load_mass: q,
            ..Loads::default()
        };
        let s = statics(&link, phi, &pose, &w, &l).unwrap();
        let n_l_sin = s.head_force * link.l_c * s.head_force_angle.sin();
        assert!((n_l_sin - s.head_moment.abs()).abs() <= 1e-9 * n_l_sin.max(1.0));
        assert!((s.head_moment - s.drive_torque).abs() <= s.drive_torque_error);
        let (m, e) = load_moment(&link, q * G, phi, 1e-3).unwrap();
        assert!(
            (m - s.drive_torque).abs() <= e + s.drive_torque_error,
            "{m} ± {e} vs {}",
            s.drive_torque
        );
    }
}

/// The shipped scene: a certified counterweight within its limits and sector, the check by
/// virtual work passed, the keys in the result.
#[test]
fn the_shipped_tukan_counterweight_scene_is_certified() {
    let path = common::problem("crane-tukan-40t-counterweight.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let r = solve_scene(&parse_str(&text, &path).unwrap());
    assert_eq!(r.status, Status::BestFound, "{:?}", r.warnings);
    let b = &r.extra["balance"];
    assert_eq!(b["counterweight"]["status"], "optimal");
    assert_eq!(b["virtual_work_check"]["pass"], true);
    assert_eq!(b["virtual_work_check"]["positions"], 10);
    let m = r.lookup("design.counterweight_mass_kg").unwrap();
    assert!(m > 0.0 && m <= 80e3, "{m}");
    let dir = r
        .lookup("design.counterweight_direction_rad")
        .unwrap()
        .to_degrees();
    assert!((150.0..=210.0).contains(&dir), "{dir}");
    let peak = b["counterweight"]["peak_drive_torque_nm"].as_f64().unwrap();
    let bare = b["unbalanced"][0]["peak_nm"].as_f64().unwrap();
    assert!(peak < 0.3 * bare, "{peak} vs {bare}");
    let mut r = r;
    r.complete();
    assert!(r.tables.iter().any(|t| t.suffix == "balance"));
}

#[test]
fn a_counterweight_needs_masses_and_a_sector_at_most_half_a_turn() {
    let path = common::problem("crane-tukan-40t-counterweight.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let no_masses = text.replace("[mechanism.self_weight]", "[mechanism.unused]");
    let e = common::err(&no_masses).to_string();
    assert!(
        e.contains("mechanism.unused") || e.contains("design.counterweight"),
        "{e}"
    );
    let no_masses = text.replace("[mechanism.self_weight]\n", "").replace(
        "boom_mass = \"22 t\"\nboom_centroid = 0.45\njib_mass = \"9 t\"\ntie_mass = \"3.5 t\"\n",
        "",
    );
    let e = common::err(&no_masses).to_string();
    assert!(
        e.contains("design.counterweight") && e.contains("self_weight"),
        "{e}"
    );
    let wide = common::with(
        &text,
        "directions = [\"150 deg\", \"210 deg\"]",
        "directions = [\"90 deg\", \"300 deg\"]",
    );
    let e = common::err(&wide).to_string();
    assert!(
        e.contains("design.counterweight.directions") && e.contains("180"),
        "{e}"
    );
    let bare = common::with(&text, "lever = \"6 m\"", "lever = 6");
    let e = common::err(&bare).to_string();
    assert!(e.contains("lever"), "{e}");
}

/// Thesis §2.2 (Fig 2.3): with an inclined hoist rope a level head does not give a level
/// load. The load's Δh against a dense brute force of y_C + |S − C|/n.
#[test]
fn an_inclined_rope_moves_the_load_as_a_brute_force_says() {
    let link = thesis();
    for (sheave, parts) in [
        (P2::new(3.0, 10.0), 1.0),
        (P2::new(8.0, 2.0), 2.0),
        (P2::new(-1.0, 20.0), 4.0),
    ] {
        let rope = HoistRope { sheave, parts };
        let lp = balance::load_path(&link, &rope, 32, 1e-9).unwrap();
        let [p0, p1] = link.phi_range;
        let ys: Vec<f64> = (0..=20_000)
            .map(|k| {
                let phi = p0 + (p1 - p0) * k as f64 / 20_000.0;
                let c = link.pose(phi).unwrap().c;
                c.y + ((sheave - c).norm()) / parts
            })
            .collect();
        let hi = ys.iter().cloned().fold(f64::MIN, f64::max);
        let lo = ys.iter().cloned().fold(f64::MAX, f64::min);
        let brute = hi - lo;
        // The brute force is a lower bound, within its spacing's |y''|h²/8 (~1e-9 m here).
        assert!(
            brute <= lp.load_delta_h_m + lp.load_delta_h_error_m,
            "{brute} vs {lp:?}"
        );
        assert!(lp.load_delta_h_m - brute <= 1e-8, "{brute} vs {lp:?}");
        assert!((lp.h3_m - (ys[0] - ys[20_000])).abs() < 1e-12);
    }
}
