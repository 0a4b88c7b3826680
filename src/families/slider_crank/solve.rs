//! The slider-crank's whole solve: the counterweight synthesis ([`sc::solve`]), the paper's
//! printed counterweight evaluated as a baseline, and the speed sweep that re-optimises the
//! scene at every speed — every number the result reports, computed here and nowhere in
//! `numbers.rs` or `report.rs`.

use super::file::SliderCrankProblem;
use super::flywheel_design::{self, FlywheelDesign};
use super::synth::{self as sc, Metrics, SweepPoint};
use crate::dynamics::{self, Drive, DriveError, DriveFigures};
use crate::families::driver::Claim;
use crate::families::family::cw_status;
use crate::geom::P2;
use crate::report::Status;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::Var;
use std::f64::consts::TAU;

/// Every number of a solved slider-crank scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// What the solve claims: the exchange loop's status (`analysed` for a given
    /// counterweight, `degenerate` where a free one cannot move the objective), its method,
    /// the bound |U| sits on, the synthesis's warnings.
    pub claim: Claim,
    /// The design's keys: U, the realised counterweight and the balancers.
    pub design: sc::Design,
    /// The synthesis: design, objectives, the exchange loop's certificate, the Pareto front,
    /// the joint loads and the classical baselines.
    pub out: sc::Outcome,
    /// The paper's printed counterweight evaluated as the baseline `paper_counterweight`,
    /// where the file gives one (`Err`: why it could not be evaluated).
    pub paper_counterweight: Option<Result<Metrics, String>>,
    /// The file's `[design.reference]` counterweight evaluated as the baseline
    /// `reference_counterweight` (`Err`: why it could not be evaluated).
    pub reference_counterweight: Option<Result<Metrics, String>>,
    /// The lever radius of the classical formula (6) (`[paper].lever_radius`, else the
    /// counterweight's fixed radius), where there is one.
    pub lever: Option<f64>,
    /// The design's Lanchester balancer pairs, as the result lists them.
    pub balancers: Vec<BalancerFigures>,
    /// The speed sweep (`objective.speed_sweep`): one point per speed whose solve succeeded,
    /// and a warning per speed that failed.
    pub sweep: Option<(Vec<SweepPoint>, Vec<String>)>,
    /// The design's drive (`[mechanism.drive]`): `Err` says why it could not be computed.
    pub drive: Option<Result<DriveFigures, String>>,
    /// The envelope's sensitivity table (`[mechanism.envelope] sensitivities = true`): `Err`
    /// says why it could not be computed.
    pub sensitivities: Option<Result<Vec<sc::Sensitivity>, String>>,
    /// The design's figures at the crank angles of `objective.evaluate_at`, in their order.
    pub at_angles: Vec<AtAngle>,
    /// The joint loads' peaks in the drive's steady state (with `[mechanism.drive]` and the
    /// joint loads), beside the constant-speed ones.
    pub real_joint_loads: Option<RealJointLoads>,
    /// With `minimize = "flywheel-inertia"`: the search's design and evidence, and each
    /// baseline's least flywheel (by name, where its drive could be computed).
    pub flywheel: Option<(FlywheelDesign, Vec<(String, f64)>)>,
    /// With `[design.balancers] compare`: the scene without pairs, then with its first 1, 2,
    /// … orders, each solved as a scene of its own ([`compare_balancers`]).
    pub comparison: Vec<Compared>,
}

/// One scene of the balancer comparison: the file's scene with the leading `orders` of its
/// balancers only (none: the crank counterweight alone), and its whole solve.
#[derive(Debug, Clone)]
pub struct Compared {
    /// The scene solved (its balancers the compared pairs, no front).
    pub scene: sc::Scene,
    /// Its solve (`Err`: why it failed).
    pub out: Result<sc::Outcome, String>,
}

/// The scene `s` with no balancer pair, then with its first 1, 2, … pairs, up to all of
/// them: the same objective and limits, no Pareto front. Each is the solve a file with
/// those orders alone would make (`tests/felling_head_lanchester.rs` checks that).
fn compare_balancers(s: &sc::Scene) -> Vec<Compared> {
    (0..=s.balancers.len())
        .map(|k| {
            let scene = sc::Scene {
                balancers: s.balancers[..k].to_vec(),
                pareto_points: 0,
                ..s.clone()
            };
            let out = sc::solve(&scene).map_err(|e| e.to_string());
            Compared { scene, out }
        })
        .collect()
}

/// The joint loads' peaks at real speed: in the drive's periodic steady state, each
/// acceleration r″ω² + r′α ([`crate::families::slider_crank::model::SliderCrank::joint_loads_at`]),
/// over its nodes; each error the nodes' bound and the speeds' error
/// ([`crate::dynamics::SteadyState::inertial_peak`]) plus the round-off of one evaluation; and
/// each peak's change from the constant-speed peak (keys of `derived`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RealJointLoads {
    /// The main bearing's peak load at real speed (N).
    pub steady_peak_main_bearing_load_n: f64,
    /// Its error bound (N).
    pub steady_peak_main_bearing_load_error_n: f64,
    /// Its change from the constant-speed peak (%).
    pub steady_peak_main_bearing_load_change_pct: f64,
    /// The crank pin's (N).
    pub steady_peak_crank_pin_load_n: f64,
    /// Its error bound (N).
    pub steady_peak_crank_pin_load_error_n: f64,
    /// Its change (%).
    pub steady_peak_crank_pin_load_change_pct: f64,
    /// The wrist pin's (N).
    pub steady_peak_wrist_pin_load_n: f64,
    /// Its error bound (N).
    pub steady_peak_wrist_pin_load_error_n: f64,
    /// Its change (%).
    pub steady_peak_wrist_pin_load_change_pct: f64,
    /// The guide's normal force (N).
    pub steady_peak_guide_load_n: f64,
    /// Its error bound (N).
    pub steady_peak_guide_load_error_n: f64,
    /// Its change (%).
    pub steady_peak_guide_load_change_pct: f64,
}

/// [`RealJointLoads`] of the design in the steady state `st`, beside the constant-speed
/// peaks `at_speed`; `None` where the mechanism does not assemble at a node.
fn real_joint_loads(
    out: &sc::Outcome,
    st: &crate::dynamics::SteadyState,
    at_speed: &sc::JointLoadPeaks,
) -> Option<RealJointLoads> {
    use crate::families::slider_crank::model::JointLoads;
    let (s, u) = (&out.designed, P2::from(out.design.unbalance));
    let cw = out.counterweight.mass.unwrap_or(0.0);
    let ro = sc::joint_load_round_off(s, u, cw);
    // The loads once per node, then each joint's peak.
    let loads = st.at_nodes(|phi, w, a| {
        let state = s.mech.state(phi)?;
        Some(s.mech.joint_loads_at(&state, w, a, &s.loads, u, cw))
    })?;
    let peak = |pick: fn(&JointLoads) -> f64, c: &sc::LoadPeak| {
        let values: Vec<f64> = loads.iter().map(pick).collect();
        let p = st.inertial_peak(&values);
        (p.peak, p.error + ro, 100.0 * (p.peak - c.peak) / c.peak)
    };
    let main = peak(|j| j.main.norm(), &at_speed.main_bearing);
    let pin = peak(|j| j.crank_pin.norm(), &at_speed.crank_pin);
    let wrist = peak(|j| j.wrist_pin.norm(), &at_speed.wrist_pin);
    let guide = peak(|j| j.guide.abs(), &at_speed.guide);
    Some(RealJointLoads {
        steady_peak_main_bearing_load_n: main.0,
        steady_peak_main_bearing_load_error_n: main.1,
        steady_peak_main_bearing_load_change_pct: main.2,
        steady_peak_crank_pin_load_n: pin.0,
        steady_peak_crank_pin_load_error_n: pin.1,
        steady_peak_crank_pin_load_change_pct: pin.2,
        steady_peak_wrist_pin_load_n: wrist.0,
        steady_peak_wrist_pin_load_error_n: wrist.1,
        steady_peak_wrist_pin_load_change_pct: wrist.2,
        steady_peak_guide_load_n: guide.0,
        steady_peak_guide_load_error_n: guide.1,
        steady_peak_guide_load_change_pct: guide.2,
    })
}

/// The design's figures at one crank angle of `objective.evaluate_at` (the result's
/// `at_angles` rows), at constant speed, with the balancers; each error is the round-off
/// bound of one evaluation ([`sc::round_off_bounds`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AtAngle {
    /// φ (deg) from the crank pin towards the slider (inner dead centre).
    pub crank_angle_deg: f64,
    /// F_x (N), along the slider axis.
    pub force_x_n: f64,
    /// F_y (N), across it.
    pub force_y_n: f64,
    /// |F| (N).
    pub force_n: f64,
    /// The bound on |F|'s error (N).
    pub force_error_n: f64,
    /// The drive torque (N·m).
    pub drive_torque_nm: f64,
    /// The bound on its error (N·m).
    pub drive_torque_error_nm: f64,
    /// |F| without the design: no counterweight, no balancers (N), as the cycle table's
    /// `bare_force_n`.
    pub unbalanced_force_n: f64,
}

/// [`AtAngle`] at each angle of `angles` (rad) for the designed scene (and `bare`, the
/// file's scene, without the design).
fn at_angles(bare: &sc::Scene, out: &sc::Outcome, angles: &[f64]) -> Vec<AtAngle> {
    let (d, u) = (&out.designed, P2::from(out.design.unbalance));
    let [df, dt, _] = sc::round_off_bounds(d, u);
    angles
        .iter()
        .map(|&phi| {
            let f = sc::scene_force(d, u, phi);
            AtAngle {
                crank_angle_deg: phi.to_degrees(),
                force_x_n: f.x,
                force_y_n: f.y,
                force_n: f.norm(),
                force_error_n: df,
                drive_torque_nm: sc::drive_torque(d, u, phi),
                drive_torque_error_nm: dt,
                unbalanced_force_n: sc::scene_force(bare, P2::zeros(), phi).norm(),
            }
        })
        .collect()
}

/// The drive of the design U = `u`: ΔE, the least flywheel for the file's Cs, the steady
/// state with the file's flywheel (or the least one, or none), and the shaking force at
/// real speed (without balancers).
fn drive(p: &SliderCrankProblem, out: &sc::Outcome, d: &Drive) -> Result<DriveFigures, DriveError> {
    let s = &out.designed;
    let u = P2::from(out.design.unbalance);
    let m = sc::machine(s, u, out.counterweight.drive_inertia());
    let set = dynamics::DriveSettings::default();
    Ok(
        dynamics::drive(&m, p.core.omega, d, &set)?.with_real_speed(&d.motor, |phi, w, a| {
            sc::real_speed_force(s, u, phi, w, a).map(|f| f.norm())
        }),
    )
}

impl Solution {
    /// The result's baselines: the classical designs of `out.baselines`, then the paper's
    /// counterweight where it was evaluated.
    pub fn baselines(&self) -> impl Iterator<Item = (&str, &Metrics)> {
        let paper = match &self.paper_counterweight {
            Some(Ok(m)) => Some(("paper_counterweight", m)),
            _ => None,
        };
        let reference = match &self.reference_counterweight {
            Some(Ok(m)) => Some(("reference_counterweight", m)),
            _ => None,
        };
        self.out
            .baselines
            .iter()
            .map(|(k, m)| (k.as_str(), m))
            .chain(paper)
            .chain(reference)
    }

    /// The design's unbalance vector U (kg·m).
    pub fn unbalance(&self) -> P2 {
        P2::from(self.out.design.unbalance)
    }
}

/// With `minimize = "flywheel-inertia"`: the search from the certified force optimum `out`,
/// and the outcome of its design (the scene solved with U fixed there).
fn flywheel_outcome(
    p: &SliderCrankProblem,
    out: sc::Outcome,
) -> Result<(sc::Outcome, Option<FlywheelDesign>), String> {
    let Some(d) = p.drive.as_ref().filter(|_| p.flywheel_objective) else {
        return Ok((out, None));
    };
    let found = flywheel_design::design(p, d, P2::from(out.design.unbalance))?;
    let mut at = p.core.clone();
    at.counterweight.unbalance = Var::Fixed(found.u.norm());
    at.counterweight.angle = Var::Fixed(found.u.y.atan2(found.u.x).rem_euclid(TAU));
    let out = sc::solve(&at).map_err(|e| e.to_string())?;
    Ok((out, Some(found)))
}

/// The `best_found` claim of the flywheel search: its method, evidence and warnings.
fn flywheel_claim(out: &sc::Outcome, found: &FlywheelDesign) -> Claim {
    let mut c = Claim::new(Status::BestFound, found.evidence.method.clone());
    c.search = Some(found.evidence.clone());
    c.warnings = out.warnings.clone();
    c
}

/// Solves the scene: the synthesis, the paper's counterweight as a baseline, the speed sweep.
pub fn solve(p: &SliderCrankProblem) -> Result<Solution, String> {
    let s = &p.core;
    let out = sc::solve(s).map_err(|e| e.to_string())?;
    let (out, found) = flywheel_outcome(p, out)?;
    let design = design(p, &out);
    let claim = match &found {
        Some(f) => flywheel_claim(&out, f),
        None => claim(s, &out, &design),
    };
    let mut sol = Solution {
        claim,
        design,
        balancers: balancer_figures(&out),
        out,
        lever: lever_radius(p),
        paper_counterweight: None,
        reference_counterweight: None,
        sweep: None,
        drive: None,
        sensitivities: None,
        at_angles: Vec::new(),
        real_joint_loads: None,
        flywheel: None,
        comparison: Vec::new(),
    };
    if p.compare_balancers {
        sol.comparison = compare_balancers(s);
    }
    sol.at_angles = at_angles(s, &sol.out, &p.evaluate_at);
    // A counterweight given as a baseline, evaluated as the design is.
    let judged = |u: P2| {
        sc::metrics(s, u)
            .and_then(|mut m| sc::judge_baseline(s, &mut m).map(|()| m))
            .map_err(|e| e.to_string())
    };
    // The paper's counterweight m at the lever radius r: U = (−m r, 0).
    let printed = p.paper.as_ref().and_then(|pd| pd.counterweight_mass);
    if let (Some(rad), Some(pm)) = (sol.lever, printed) {
        sol.paper_counterweight = Some(judged(P2::new(-pm * rad, 0.0)));
    }
    sol.reference_counterweight = p.reference.map(|u| judged(P2::from(u)));
    if let Some(sw) = &p.speed_sweep {
        sol.sweep = Some(sc::speed_sweep(s, sw, sol.unbalance()));
    }
    if let Some(d) = &p.drive {
        sol.drive = Some(drive(p, &sol.out, d).map_err(|e| e.to_string()));
    }
    if let (Some(found), Some(d)) = (found, &p.drive) {
        let bases = sol
            .baselines()
            .filter_map(|(n, m)| {
                flywheel_design::least_flywheel_of(p, d, P2::from(m.unbalance))
                    .map(|i| (n.to_string(), i))
            })
            .collect();
        sol.flywheel = Some((found, bases));
    }
    if let (Some(Ok(d)), Some(jl)) = (&sol.drive, &sol.out.joint_loads) {
        sol.real_joint_loads = real_joint_loads(&sol.out, &d.steady, jl);
    }
    sol.sensitivities = sol.out.sensitivities.clone();
    Ok(sol)
}

/// What the solve claims of its design: `analysed` for a given counterweight, `degenerate`
/// where a free one cannot move the objective, `infeasible` with how far off each limit is.
fn claim(s: &sc::Scene, out: &sc::Outcome, design: &sc::Design) -> Claim {
    let given = s.given();
    let mut c = Claim::new(
        match out.status {
            CwStatus::Optimal if given => Status::Analysed,
            st => cw_status(st),
        },
        out.method.clone(),
    );
    if let Some(why) = &out.degenerate {
        if !given {
            c.status = Status::Degenerate;
            c.status_detail = Some(why.clone());
        }
    }
    if let Some(e) = out.envelope.as_ref().filter(|e| !e.certified) {
        if c.status == Status::Optimal {
            c.status = Status::BestFound;
            c.status_detail = Some(format!(
                "the worst case over the length tolerances is taken at their ends, not proven (lengths enter the kinematics non-linearly); the design is certified over those {} scenarios{}",
                e.vertices.len(),
                e.monte_carlo.as_ref().map_or(String::new(), |m| format!(
                    "; {} quasi-Monte Carlo samples of the whole box: {} beyond the worst case",
                    m.samples, m.beyond_worst_case
                ))
            ));
        }
    }
    c.warnings = out.warnings.clone();
    if c.status == Status::Infeasible {
        c.infeasible(out.infeasibility.clone());
    } else {
        c.bounds = unbalance_bound(s, design);
    }
    c
}

/// The design's keys: U, the realised counterweight and the balancers.
fn design(p: &SliderCrankProblem, out: &sc::Outcome) -> sc::Design {
    sc::Design::new(
        out.design.unbalance,
        &out.counterweight,
        p.core.counterweight.shape.as_ref(),
    )
    .with_balancers(&out.designed.balancers)
}

/// |U| on a bound of its range: the envelope, the unbalance range or m_max·r_max decides the
/// counterweight, not the balance.
fn unbalance_bound(s: &sc::Scene, design: &sc::Design) -> Vec<crate::synth::ActiveBound> {
    if s.given() || s.counterweight.unbalance.fixed().is_some() {
        return Vec::new();
    }
    let (lo, hi) = sc::unbalance_bounds(&s.counterweight);
    let upper = match s.counterweight.shape.as_ref() {
        Some(sh) if hi >= sh.max_unbalance() => (
            "design.shape",
            "the plate fills its envelope: a larger counterweight would lower the objective; enlarge outer_radius_max, thickness or max_angle",
        ),
        _ if s.counterweight.mass.is_some() && hi < s.counterweight.unbalance.bounds().1 => (
            "design.mass",
            "the largest mass at the largest radius: a larger counterweight would lower the objective",
        ),
        _ => (
            "design.unbalance",
            "the unbalance range's upper end: a larger counterweight would lower the objective",
        ),
    };
    crate::synth::ActiveBound::check(
        "design.counterweight_unbalance_kgm",
        design.counterweight_unbalance_kgm,
        (lo, hi),
        1e-7,
        (
            "design.unbalance",
            "the unbalance range's lower end: a smaller counterweight would balance better",
        ),
        upper,
    )
    .into_iter()
    .collect()
}

/// The lever radius of formula (6): the paper's, else the counterweight's fixed radius.
fn lever_radius(p: &SliderCrankProblem) -> Option<f64> {
    p.paper
        .as_ref()
        .and_then(|pd| pd.lever_radius)
        .or_else(|| p.core.counterweight.radius.and_then(|v| v.fixed()))
}

/// One Lanchester balancer pair of the design, as the result lists it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BalancerFigures {
    /// Order n: the shafts turn at ±n·ω.
    pub order: u32,
    /// |B_n| (kg·m), the pair's unbalance.
    pub unbalance_kgm: f64,
    /// The phase of B_n, atan2(B_y, B_x) in [0, 2π) (0 for no unbalance).
    pub phase_rad: f64,
    /// |B_n|/2 on each shaft (kg·m).
    pub shaft_unbalance_kgm: f64,
    /// The pair's offset from the line through the crank axis (m).
    pub offset_m: f64,
    /// The peak of its force, ω² n² |B_n| (N).
    pub peak_force_n: f64,
    /// The peak of its couple about the crank axis, |offset| × force (N·m): zero for a pair
    /// on the line through the crank axis (an in-plane pair symmetric about that line adds no
    /// moment).
    pub peak_couple_nm: f64,
    /// The mass on each shaft, |B_n|/(2r) (kg), with `[design.balancers] radius` r.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shaft_mass_kg: Option<f64>,
}

/// The mass of every balancer shaft's eccentric mass together, Σ |B_n|/r_n (kg: two shafts
/// of |B_n|/(2r_n) per pair), where every pair has its radius (0 without pairs).
pub fn balancers_mass(balancers: &[sc::BalancerSpec]) -> Option<f64> {
    balancers
        .iter()
        .map(|b| {
            b.mass_radius
                .map(|r| b.unbalance[0].hypot(b.unbalance[1]) / r)
        })
        .sum::<Option<f64>>()
        .map(|m| m.max(0.0)) // an empty sum is −0
}

/// The design's balancer pairs ([`BalancerFigures`]), in the order they were designed.
fn balancer_figures(out: &sc::Outcome) -> Vec<BalancerFigures> {
    let s = &out.designed;
    let w2 = s.omega * s.omega;
    s.balancers
        .iter()
        .map(|b| {
            let (bx, by) = (b.unbalance[0], b.unbalance[1]);
            let mag = bx.hypot(by);
            let phase = if mag > 0.0 {
                by.atan2(bx).rem_euclid(std::f64::consts::TAU)
            } else {
                0.0
            };
            let n = b.pair.order as f64;
            let force = w2 * n * n * mag;
            BalancerFigures {
                order: b.pair.order,
                unbalance_kgm: mag,
                phase_rad: phase,
                shaft_unbalance_kgm: 0.5 * mag,
                offset_m: b.pair.offset,
                peak_force_n: force,
                peak_couple_nm: force * b.pair.offset.abs(),
                shaft_mass_kg: b.mass_radius.map(|r| 0.5 * mag / r),
            }
        })
        .collect()
}

/// The file-only analyses: none for the slider-crank.
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &SliderCrankProblem, _: &Solution) -> Analyses {}
