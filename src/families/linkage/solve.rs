//! The linkage's whole solve: the counterweights ([`ls::solve`]: the certified minimax, RMS,
//! lightest or full-balance program and its front), each counterweight realised as an annular
//! sector about its joint, every joint's Newton–Euler load over the cycle without and with
//! them, and the Berkof–Lowen closed form of a four-bar — every number the result reports.

use super::file::{Goal, LinkageProblem, LinkageScene, Objective as ObjectiveSpec};
use super::model::ForceBalance;
use super::synth::{self as ls, JointPeak, Outcome};
use crate::dynamics::{Drive, DriveError, DriveFigures, SteadyState};
use crate::families::driver::Claim;
use crate::families::family::cw_status;
use crate::report::Status;
use crate::synth::counterweight::Status as CwStatus;
use crate::synth::shape::sector_realising;
use crate::synth::Shortfall;

/// Every number of a solved linkage scene.
#[derive(Debug, Clone)]
pub struct Solution {
    /// What the solve claims: the exchange loop's status and method, `infeasible` (with how)
    /// for a balance out of reach or limits no design meets, `analysed` without
    /// counterweights; a warning near a toggle and the solver's note.
    pub claim: Claim,
    /// The counterweights, the bare and balanced fields, the front.
    pub out: Outcome,
    /// Per counterweight of the design with a mass, the annular sector (rᵢ, rₒ, θ) about its
    /// joint that has its mass, centroid and inertia within its envelope (`None`: no sector
    /// does, no mass, or a plate, which `out.plates` cuts).
    pub sectors: Vec<Option<(f64, f64, f64)>>,
    /// The joints' peak loads, or why they could not be computed.
    pub joints: Result<JointLoads, String>,
    /// A four-bar's full force balance in closed form (Berkof–Lowen), where the linkage is one.
    pub berkof_lowen: Option<ForceBalance>,
    /// The design's drive (`[mechanism.drive]`; the bare linkage's without a design): `Err`
    /// says why it could not be computed.
    pub drive: Option<Result<DriveFigures, String>>,
    /// ΔE without and with the design, with `minimize = "energy-fluctuation"` (`Err`: why
    /// not computed).
    pub energy: Option<Result<EnergyFigures, String>>,
    /// The design over the operating envelope (`[mechanism.envelope]`; `Err`: why not
    /// computed).
    pub envelope: Option<Result<super::solve_envelope::EnvelopeOutcome, String>>,
    /// The drive in every named load case, with `[[mechanism.load_cases]]` and
    /// `[mechanism.drive]`.
    pub load_cases: Option<super::load_cases::LoadCaseDrives>,
    /// The path error of `[objective.path]`: the largest, each point's, and the bound on
    /// their error (`Err`: the linkage does not turn fully).
    pub path: Option<Result<PathError, String>>,
    /// The rocker's swing of `[objective.swing]` (`Err`: the linkage does not turn fully).
    pub swing: Option<Result<super::shape::TurnExtreme, String>>,
    /// The function error of `[objective.function]` and each point's (`Err`: the linkage
    /// does not assemble at a point).
    pub function: Option<Result<(super::shape::TurnExtreme, Vec<f64>), String>>,
    /// The least transmission angle over the turn, where `[design.synthesis]` bounds it.
    pub transmission: Option<Result<super::shape::TurnExtreme, String>>,
    /// The slider's stroke of `[objective.stroke]` (`Err`: the linkage does not turn fully).
    pub stroke: Option<Result<super::shape::TurnExtreme, String>>,
    /// The slider's dwell of `[objective.dwell]` (`Err`: the linkage does not turn fully).
    pub dwell: Option<Result<super::shape::Dwell, String>>,
    /// The crank ratio λ = r/l, where `[design.synthesis]` bounds it.
    pub crank_ratio: Option<f64>,
    /// The joints' least margin inside `design.synthesis.joint_box` over the turn.
    pub box_margin: Option<Result<super::shape::TurnExtreme, String>>,
}

/// The tracer's path against its precision points (`[objective.path]`).
#[derive(Debug, Clone)]
pub struct PathError {
    /// The largest distance from a precision point to the path (m).
    pub max: f64,
    /// Each point's distance (m).
    pub points: Vec<f64>,
    /// The bound on their error (m).
    pub error: f64,
}

/// Every joint's peak load over the cycle.
#[derive(Debug, Clone)]
pub struct JointLoads {
    /// Without counterweights.
    pub bare: Vec<JointPeak>,
    /// With the design's counterweights (absent without a design; `Err`: why not computed).
    pub design: Option<Result<Vec<JointPeak>, String>>,
    /// At real speed: the design's (else the bare linkage's) peaks in the drive's periodic
    /// steady state, where the file has `[mechanism.drive]` and its steady state was computed.
    pub steady: Option<Result<Vec<JointPeak>, String>>,
}

impl Solution {
    /// The design vector, where there is a design and all of it is finite.
    pub fn design_x(&self) -> Option<&[f64]> {
        finite_design(&self.out)
    }
}

/// The design vector of `out`, where there is a design and all of it is finite.
fn finite_design(out: &Outcome) -> Option<&[f64]> {
    out.design
        .as_ref()
        .map(|s| s.x.as_slice())
        .filter(|x| x.iter().all(|v| v.is_finite()))
}

/// Solves the scene: the counterweights, their sectors, the joint loads, Berkof–Lowen.
pub fn solve(p: &LinkageProblem) -> Result<Solution, String> {
    let sc = &p.scene;
    let out = ls::solve(sc, &p.settings).map_err(|e| e.to_string())?;
    let sectors = match &out.design {
        Some(sol) => (0..sc.counterweights.len())
            .map(|j| {
                let d = sol.counterweight(j);
                let envelope = sc.counterweights[j].radius;
                // A plate is cut as a plate (`Outcome::plates`), not as a sector.
                (d.mass > 0.0 && sc.counterweights[j].areal_density().is_none())
                    .then(|| sector_realising(d.mass, d.radius, d.inertia, envelope))
                    .flatten()
            })
            .collect(),
        None => Vec::new(),
    };
    let mut claim = claim(&out);
    if let Some(shape) = &p.shape {
        super::synthesis::claim(shape, &mut claim);
    }
    let cws = &sc.counterweights;
    if !cws.is_empty()
        && cws.iter().all(|c| c.is_given())
        && matches!(claim.status, Status::Optimal | Status::Degenerate)
    {
        // Nothing designed: every counterweight's mass, centroid and inertia are the file's.
        claim.status = Status::Analysed;
        claim.status_detail = None;
        claim.method = format!(
            "analysis of the given counterweights (mass, centroid and inertia fixed); {}",
            claim.method
        );
    }
    if matches!(&out.design, Some(d) if d.status == CwStatus::Infeasible) {
        claim.status_detail = None;
        claim.infeasible(shortfalls(p));
    }
    let x = finite_design(&out);
    let drive = p
        .drive
        .as_ref()
        .map(|d| drive(p, d, x).map_err(|e| e.to_string()));
    let steady = drive
        .as_ref()
        .and_then(|d| d.as_ref().ok())
        .map(|d| &d.steady);
    let energy = (sc.objective.minimize == Goal::EnergyFluctuation).then(|| {
        Ok(EnergyFigures {
            bare: energy_fluctuation(p, None)?,
            design: x.map(|x| energy_fluctuation(p, Some(x))).transpose()?,
        })
    });
    let envelope = (!sc.envelope.is_empty()).then(|| {
        let peaks = match &out.design {
            Some(d) if x.is_some() && d.status != CwStatus::Infeasible => &d.peaks,
            _ => &out.bare,
        };
        super::solve_envelope::evaluate(sc, &out, peaks, x, &p.settings)
    });
    if let Some(Ok(e)) = &envelope {
        lengths_claim(sc, e, &mut claim);
    }
    let load_cases = p
        .drive
        .as_ref()
        .zip(drive.as_ref())
        .and_then(|(d, nominal)| super::load_cases::solve(sc, d, x, nominal, &mut claim.warnings));
    let path = p.path.as_ref().map(|path| {
        let l = &sc.linkage;
        super::shape::path_error(l, path, path.at)
            .map(|(max, points)| PathError {
                max,
                points,
                error: super::shape::path_error_bound(l, path, path.at),
            })
            .ok_or_else(|| "the linkage does not assemble over the whole turn".to_string())
    });
    let turns = || "the linkage does not assemble over the whole turn".to_string();
    let swing =
        (p.swing.as_ref()).map(|w| super::shape::swing(&sc.linkage, w.link).ok_or_else(turns));
    let function = (p.function.as_ref())
        .map(|f| super::shape::function_error(&sc.linkage, f).ok_or_else(turns));
    let stroke =
        (p.stroke.as_ref()).map(|w| super::shape::stroke(&sc.linkage, w.link).ok_or_else(turns));
    let dwell = (p.dwell.as_ref()).map(|d| super::shape::dwell(&sc.linkage, d).ok_or_else(turns));
    let crank_ratio = (p.synthesis.as_ref())
        .and_then(|s| s.max_crank_ratio)
        .and_then(|c| c.of(&sc.linkage, sc.crank_length));
    let box_margin = (p.synthesis.as_ref())
        .and_then(|s| s.joint_box)
        .map(|b| super::shape::box_margin(&sc.linkage, sc.crank_length, &b).ok_or_else(turns));
    let transmission = (p.synthesis.as_ref())
        .and_then(|s| s.min_transmission)
        .map(|_| super::shape::min_transmission(&sc.linkage).ok_or_else(turns));
    Ok(Solution {
        path,
        swing,
        function,
        transmission,
        stroke,
        dwell,
        crank_ratio,
        box_margin,
        load_cases,
        envelope,
        energy,
        claim,
        joints: joint_loads(p, x, steady),
        drive,
        out,
        sectors,
        berkof_lowen: sc.linkage.berkof_lowen().ok(),
    })
}

/// The drive of the design `x` (without one, the bare linkage's) in the nominal load case
/// ([`super::drive::figures`]).
fn drive(p: &LinkageProblem, d: &Drive, x: Option<&[f64]>) -> Result<DriveFigures, DriveError> {
    super::drive::figures(&p.scene, d, x)
}

/// ΔE at constant speed with its error bound, of the design `x` (the bare linkage's
/// without): the drive's own quadrature ([`super::drive::delta_e`]).
fn energy_fluctuation(p: &LinkageProblem, x: Option<&[f64]>) -> Result<(f64, f64), String> {
    super::drive::delta_e(&p.scene, x)
}

/// ΔE of the bare linkage and of the design, with `minimize = "energy-fluctuation"`.
#[derive(Debug, Clone)]
pub struct EnergyFigures {
    /// (ΔE, its error bound) without counterweights (J).
    pub bare: (f64, f64),
    /// The same with the design's, where there is a design.
    pub design: Option<(f64, f64)>,
}

/// How far off each peak limit of an infeasible linkage is: the peak force, moment and
/// torque each minimised alone (every limit and the full balance left out), a certified
/// minimax like the solve's own. A limit whose own solve does not certify gives no entry.
fn shortfalls(p: &LinkageProblem) -> Vec<Shortfall> {
    let o = &p.scene.objective;
    let limits = [
        (
            o.max_peak_force,
            Goal::PeakForce,
            "max_peak_force",
            "peak shaking force",
            "N",
        ),
        (
            o.max_peak_moment,
            Goal::PeakMoment,
            "max_peak_moment",
            "peak shaking moment",
            "N·m",
        ),
        (
            o.max_peak_torque,
            Goal::PeakTorque,
            "max_peak_torque",
            "peak drive torque",
            "N·m",
        ),
    ];
    let mut out = Vec::new();
    for (limit, goal, key, quantity, unit) in limits {
        let Some(limit) = limit else { continue };
        let relaxed = LinkageScene {
            objective: ObjectiveSpec {
                minimize: goal,
                max_peak_force: None,
                max_peak_moment: None,
                max_peak_torque: None,
                max_joint_force: None,
                full_force_balance: false,
                pareto_points: 0,
            },
            ..p.scene.clone()
        };
        let least = ls::solve(&relaxed, &p.settings).ok().and_then(|r| r.design);
        if let Some(d) = least.filter(|d| d.status == CwStatus::Optimal) {
            let key = format!("objective.{key}");
            out.push(Shortfall::at_most(
                &key,
                quantity,
                limit,
                d.objective,
                d.error.total,
                unit,
            ));
        }
    }
    out
}

/// What the solve claims of its design.
fn claim(out: &Outcome) -> Claim {
    let mut c = match (&out.design, out.balance_residual) {
        (_, Some(resid)) => {
            let mut c = Claim::new(
                Status::Infeasible,
                "full force balance: SVD of the force blocks at 64 angles",
            );
            c.status_detail = Some(format!(
                "full force balance is out of reach of these counterweights: the least-squares residual of the balance equations is {resid:.3e} of the unbalanced force (the counterweights' first moments cannot make the total centre of mass stationary; a four-bar needs them on crank and rocker)"
            ));
            c
        }
        (None, None) => Claim::new(
            Status::Analysed,
            "closed-form dyads; every peak refined from a scan",
        ),
        (Some(d), None) if d.status == CwStatus::Infeasible => {
            // No design: the limits cannot be met (a certificate on the sampled angles).
            let mut c = Claim::new(
                Status::Infeasible,
                format!(
                    "clarabel SOCP + exchange loop: infeasible on {} sampled angles, so on all angles",
                    d.angles
                ),
            );
            c.status_detail = Some(d.note.clone().unwrap_or_else(|| {
                "no design meets the limits within the counterweight limits".into()
            }));
            c
        }
        (Some(d), None) => {
            let mut c = Claim::new(cw_status(d.status), method(out, d));
            c.warnings.extend(d.note.clone());
            if let Some(l) = out.lighter {
                c.warnings.push(format!(
                    "the optimum is not unique (the counterweights can move along a set of designs with the same certified peak): the design shown is the lightest of that set, {:.6} kg in all, by a second program (least Σm with every objective peak at most the optimum); the exchange loop's design weighed {:.6} kg",
                    l.lightest, l.first
                ));
            }
            if let (Some(why), Status::Optimal) = (&out.degenerate, c.status) {
                c.status = Status::Degenerate;
                c.status_detail = Some(why.clone());
            }
            c
        }
    };
    if out.kappa_max > 1e3 {
        c.warnings.insert(0, format!(
            "the linkage passes near a toggle (dyad conditioning up to {:.3e}): its accelerations are large there and lose digits as ε·κ²; the stated errors include it",
            out.kappa_max
        ));
    }
    c
}

/// The method of a solved design: the engine (the exact disc or clarabel's SOCP), its rounds,
/// angles and iterations, the polish and the balance equalities.
fn method(out: &Outcome, sol: &crate::synth::minimax::Solution) -> String {
    format!(
        "closed-form dyads; {} + exchange loop: {} rounds, {} angles, {} IPM iterations{}{}",
        if sol.solver_status == crate::synth::minimax::DISC_SOLVER {
            "smallest enclosing disc (Welzl, support angles by Newton)"
        } else {
            "clarabel SOCP (rotated cones I·m ≥ |u|²)"
        },
        sol.rounds,
        sol.angles,
        sol.ipm_iterations,
        if sol.solver_status.contains(crate::synth::minimax::POLISHED) {
            "; optimality conditions (active maxima, angles, multipliers) polished by Newton"
        } else {
            ""
        },
        if out.balance_rows > 0 {
            format!(
                "; full force balance as {} equalities (SVD of the force blocks)",
                out.balance_rows
            )
        } else {
            String::new()
        }
    )
}

/// The joints' peak loads without counterweights and with the design `x`.
fn joint_loads(
    p: &LinkageProblem,
    x: Option<&[f64]>,
    steady: Option<&SteadyState>,
) -> Result<JointLoads, String> {
    let sc = &p.scene;
    let zeros = vec![0.0; crate::synth::minimax::PER_COUNTERWEIGHT * sc.counterweights.len()];
    let bare = ls::joint_peaks(sc, &zeros, &p.settings).map_err(|e| e.to_string())?;
    let design = x.map(|x| ls::joint_peaks(sc, x, &p.settings).map_err(|e| e.to_string()));
    let steady = steady
        .map(|st| ls::steady_joint_peaks(sc, x.unwrap_or(&zeros), st).map_err(|e| e.to_string()));
    Ok(JointLoads {
        bare,
        design,
        steady,
    })
}

/// The file-only analyses: none for the linkage (its curves over the cycle are drawn with its
/// plots).
pub type Analyses = ();

/// See [`Analyses`].
pub fn analyse(_: &LinkageProblem, _: &Solution) -> Analyses {}

/// With length tolerances the worst case is taken at the box's vertices, not proven over it
/// (lengths enter the kinematics non-linearly): an `optimal` design over those scenarios
/// claims `best_found`, with the Monte Carlo check as its evidence.
fn lengths_claim(
    sc: &super::file::LinkageScene,
    e: &super::solve_envelope::EnvelopeOutcome,
    claim: &mut Claim,
) {
    if sc.envelope.certified() || claim.status != Status::Optimal {
        return;
    }
    claim.status = Status::BestFound;
    claim.status_detail = Some(format!(
        "the worst case over the length tolerances is taken at the envelope's vertices, not proven (lengths enter the kinematics non-linearly); the design is certified over those {} scenarios{}",
        e.scenarios.len(),
        e.monte_carlo.as_ref().map_or(String::new(), |m| format!(
            "; {} Monte Carlo samples of the whole box: {} beyond a worst case",
            m.samples, m.beyond_worst_case
        ))
    ));
}
