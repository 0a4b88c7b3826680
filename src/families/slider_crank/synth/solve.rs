//! The whole solve of a scene: the optimum, its figures, the warnings on the model, the
//! Pareto front, the joint loads and the baselines.

use super::baselines::{baselines_sampled, judge_baseline};
use super::drive::energy_fluctuation;
use super::fields::{moment0, torque_independent_of_counterweight, Normalised, Sampled};
use super::joint::sensitivity_table;
use super::loads::{check_load_limits, joint_load_peaks};
use super::metrics::{grid_extremes, metrics, metrics_sampled};
use super::optimise::optimise_with;
use super::outcome::{JointLoadPeaks, Metrics, Optimum, Outcome, ParetoPoint};
use super::realise::{realise, Realised};
use super::round_off::round_off_bounds;
use super::scene::{check, LoadLimits, Objective, Scene, SolveError};
use super::sweep::pareto_sampled;
use crate::families::slider_crank::model::{Kinematics, SliderCrank};
use crate::geom::P2;
use crate::numeric::PeriodicPeak;
use crate::synth::counterweight::Status;
use crate::synth::Shortfall;

/// Solves the scene: [`optimise`](fn@super::optimise), then the design's figures and the
/// baselines.
///
/// Degenerate objectives are flagged, not solved: without gravity the drive torque of a
/// constant-speed crank does not depend on its counterweight (the counterweight's inertia
/// adds no torque, [`crate::families::slider_crank::model::SliderCrank::drive_torque0`]), so "minimise
/// the peak torque" leaves U arbitrary. The design is then the minimax-force counterweight
/// under the same limits, and [`Outcome::degenerate`] says why.
pub fn solve(scene: &Scene) -> Result<Outcome, SolveError> {
    check(scene)?;
    let tab = Sampled::new(scene);
    let torque_fixed = torque_independent_of_counterweight(scene);
    let degenerate = degeneracy(scene, torque_fixed);
    let objective = if degenerate.is_some() {
        Objective::MinPeakForce
    } else {
        scene.objective
    };
    let mut optimum = optimise_with(
        scene,
        objective,
        scene.max_peak_force,
        scene.max_peak_torque,
        &tab.scan,
    )?;
    let mut infeasibility = Vec::new();
    if optimum.status == Status::Infeasible {
        let (shortfalls, closest) = shortfalls(scene, &tab, torque_fixed)?;
        infeasibility = shortfalls;
        if let Some(c) = closest {
            optimum = Optimum {
                status: Status::Infeasible,
                method: format!("{}; the closest design: {}", optimum.method, c.method),
                ..c
            };
        }
    }
    let Optimum {
        mut status,
        u,
        gap,
        method,
        mut warnings,
        balancers,
        duals,
        ..
    } = optimum;
    // The envelope's sensitivity table, where asked: the duals' report figure.
    let sensitivities = duals
        .filter(|_| scene.envelope.sensitivities)
        .map(|d| sensitivity_table(scene, &d).map_err(|e| e.to_string()));
    // The design's figures on the scene with its balancers (the scene itself without any);
    // the baselines on the scene as read (no balancers).
    let designed = scene.with_balancers(&balancers);
    let designed_tab = (!scene.balancers.is_empty()).then(|| Sampled::new(&designed));
    let (baseline_scene, scene) = (scene, &designed);
    let (baseline_tab, tab) = (&tab, designed_tab.as_ref().unwrap_or(&tab));
    let mech = &scene.mech;

    let mut design = metrics_sampled(scene, u, tab)?;
    let mut baselines = baselines_sampled(baseline_scene, baseline_tab)?;
    if scene.objective == Objective::MinEnergyFluctuation {
        design.energy_fluctuation = Some(energy_fluctuation(scene, u)?);
    }
    for b in baselines.values_mut() {
        judge_baseline(baseline_scene, b)?;
    }
    if scene.given() {
        given_over_limits(scene, &design, &mut warnings);
    }
    let counterweight = realise(
        P2::new(design.unbalance[0], design.unbalance[1]).norm(),
        &scene.counterweight,
        scene.objective,
    );
    let mm = peak_moment(scene, tab, design.peak)?;
    let exact_peak = exact_kinematics_peak(scene, u, design.peak, &mut warnings)?;
    gravity_warning(scene, &mut warnings);
    let pareto = pareto_front(scene, tab, torque_fixed, &mut warnings)?;
    let g = scene.loads.gravity.norm();
    let static_weight = mech.link_weight(&scene.loads) + g * counterweight.mass.unwrap_or(0.0);
    // Conditioning: say how many digits are left when round-off eats into them (near toggle).
    let round_off = round_off_bounds(scene, u);
    conditioning_warning(scene, round_off[0], design.peak, &mut warnings);
    // The gap is the refined peak minus the solver's sampled lower bound: the bound was
    // computed in floating point too, so it carries the same round-off as one evaluation.
    let gap = if gap >= 0.0 {
        gap + match objective {
            Objective::MinPeakTorque => round_off[1],
            _ => round_off[0],
        }
    } else {
        gap
    };
    let envelope = if baseline_scene.envelope.is_empty() {
        None
    } else {
        let energy = scene.objective == Objective::MinEnergyFluctuation;
        Some(
            baseline_scene
                .envelope
                .evaluate(baseline_scene, u, &balancers, energy)?,
        )
    };
    let joint_loads = if scene.bearing_loads || scene.load_limits != LoadLimits::default() {
        let jl = design_joint_loads(scene, u, &counterweight, tab, &mut warnings)?;
        check_load_limits(scene, &jl, &mut status, &mut warnings);
        Some(jl)
    } else {
        None
    };
    Ok(Outcome {
        status,
        design,
        counterweight,
        gap,
        peak_shaking_moment: mm.peak.fx,
        peak_shaking_moment_error: mm.error + round_off[2],
        pareto,
        static_weight,
        baselines,
        exact_peak,
        method,
        warnings,
        degenerate,
        designed: scene.clone(),
        joint_loads,
        infeasibility,
        envelope,
        sensitivities,
    })
}

/// How far off each limit of an infeasible scene is: the least peak force (and peak torque)
/// that any design within the bounds reaches, each minimised alone with every limit left out
/// (a certified minimax like the solve's own), and the closest design — the one that
/// minimises the first limit out of reach, or the first limit's when each is reachable alone.
fn shortfalls(
    scene: &Scene,
    tab: &Sampled,
    torque_fixed: bool,
) -> Result<(Vec<Shortfall>, Option<Optimum>), SolveError> {
    let relaxed = Scene {
        max_peak_force: None,
        max_peak_torque: None,
        max_shaking_moment: None,
        load_limits: LoadLimits::default(),
        ..scene.clone()
    };
    let least = |objective: Objective| -> Result<(Optimum, Metrics), SolveError> {
        let o = optimise_with(&relaxed, objective, None, None, &tab.scan)?;
        let m = metrics(&relaxed.with_balancers(&o.balancers), o.u)?;
        let m = over_envelope(&relaxed, &o, m)?;
        Ok((o, m))
    };
    let mut out = Vec::new();
    let mut closest: Option<(bool, Optimum)> = None;
    let mut keep = |s: Shortfall, o: Optimum, out: &mut Vec<Shortfall>| {
        let off = !s.reachable_alone();
        if closest.as_ref().is_none_or(|(was_off, _)| off && !was_off) {
            closest = Some((off, o));
        }
        out.push(s);
    };
    if let Some(limit) = scene.max_peak_force {
        let (o, m) = least(Objective::MinPeakForce)?;
        let e = o.gap.max(0.0) + m.peak_error;
        let s = Shortfall::at_most(
            "objective.max_peak_force",
            "peak shaking force",
            limit,
            m.peak,
            e,
            "N",
        );
        keep(s, o, &mut out);
    }
    if let Some(limit) = scene.max_peak_torque {
        // Where the torque does not depend on the counterweight every design's is the same:
        // the force optimum's, with no gap in torque.
        let (o, m) = if torque_fixed {
            let (o, m) = least(Objective::MinPeakForce)?;
            (Optimum { gap: 0.0, ..o }, m)
        } else {
            least(Objective::MinPeakTorque)?
        };
        let e = o.gap.max(0.0) + m.peak_torque_error;
        let s = Shortfall::at_most(
            "objective.max_peak_torque",
            "peak drive torque",
            limit,
            m.peak_torque,
            e,
            "N·m",
        );
        keep(s, o, &mut out);
    }
    if !scene.envelope.certified() {
        // With length tolerances the worst case itself is sampled, not proven.
        for s in &mut out {
            s.certified = false;
        }
    }
    Ok((out, closest.map(|(_, o)| o)))
}

/// Over an operating envelope a limit bounds the worst case: the figures `m` of the design
/// `o` replaced by their worst cases over the vertices (value and the binding vertex's
/// error); unchanged for a nominal scene.
fn over_envelope(scene: &Scene, o: &Optimum, mut m: Metrics) -> Result<Metrics, SolveError> {
    if scene.envelope.is_empty() {
        return Ok(m);
    }
    let mut env = scene.envelope.clone();
    env.monte_carlo = 0;
    let w = env.evaluate(scene, o.u, &o.balancers, false)?;
    m.peak = w.worst_peak_shaking_force.value;
    m.peak_error = w.worst_peak_shaking_force.error;
    m.peak_torque = w.worst_peak_drive_torque.value;
    m.peak_torque_error = w.worst_peak_drive_torque.error;
    Ok(m)
}

/// A given counterweight is analysed, not designed: say where it exceeds the scene's limits.
fn given_over_limits(scene: &Scene, m: &Metrics, warnings: &mut Vec<String>) {
    let over = [
        (
            "objective.max_peak_force",
            "peak shaking force",
            scene.max_peak_force,
            m.peak,
            "N",
        ),
        (
            "objective.max_peak_torque",
            "peak drive torque",
            scene.max_peak_torque,
            m.peak_torque,
            "N·m",
        ),
    ];
    for (key, q, limit, v, unit) in over {
        if let Some(l) = limit.filter(|&l| v > l) {
            warnings.push(format!(
                "the given counterweight exceeds {key} = {l} {unit}: its {q} is {v:.6} {unit}"
            ));
        }
    }
}

/// Why the scene's objective does not depend on the design, if it does not: the peak torque
/// without gravity (`torque_fixed`), or the peak moment with no balancer off the line
/// through the crank axis.
fn degeneracy(scene: &Scene, torque_fixed: bool) -> Option<String> {
    let mut degenerate = (torque_fixed && scene.objective == Objective::MinPeakTorque).then(|| {
        "the objective, the peak drive torque, does not depend on the counterweight: without \
         gravity a counterweight turning at constant speed adds no torque, so every \
         counterweight is equally 'optimal'; the design shown minimises the peak shaking force \
         instead (set model.gravity for a vertical machine, or minimise the shaking force)"
            .to_string()
    });
    if torque_fixed && scene.objective == Objective::MinEnergyFluctuation {
        degenerate = Some(
            "the objective, the energy fluctuation ΔE, does not depend on the design: without \
             gravity a counterweight (or a balancer) turning at constant speed only adds a \
             constant inertia, which changes no drive torque and so no energy curve; ΔE is the \
             same for every counterweight, and the design shown minimises the peak shaking \
             force instead (set model.gravity for a vertical machine; a flywheel, not a \
             counterweight, is the answer to ΔE here: mechanism.drive.cs)"
                .to_string(),
        );
    }
    if scene.objective == Objective::MinPeakMoment
        && scene.balancers.iter().all(|b| b.pair.offset == 0.0)
    {
        degenerate = Some(
            "the objective, the peak shaking moment, does not depend on the design: a crank \
             counterweight turning at constant speed adds no moment about the crank axis, and \
             balancer pairs on the line through it (offset 0) add none either; the design shown \
             minimises the peak shaking force instead (give the balancers their offsets)"
                .to_string(),
        );
    }
    degenerate
}

/// The refined peak of the shaking moment |ω² M₀(φ)| about the crank axis (N·m). It is zero
/// for an in-line slider with a lumped rod: its scale is the force's moment arm, the peak
/// force `peak_force` times (R + L).
fn peak_moment(scene: &Scene, tab: &Sampled, peak_force: f64) -> Result<PeriodicPeak, SolveError> {
    let mech = &scene.mech;
    let w2 = scene.omega * scene.omega;
    let nf = Normalised::new(scene);
    let (mm, _) = grid_extremes(
        &tab.scan
            .m0
            .iter()
            .map(|m| (m * w2).abs())
            .collect::<Vec<f64>>(),
        |p| moment0(scene, &nf.state(p)).abs() * w2,
        peak_force * (mech.r + mech.l),
        false,
        &scene.settings,
    )?;
    Ok(mm)
}

/// With two-harmonic kinematics, the design's peak force with the exact kinematics (N),
/// and a warning with its difference from the model's `peak`; `None` otherwise.
fn exact_kinematics_peak(
    scene: &Scene,
    u: P2,
    peak: f64,
    warnings: &mut Vec<String>,
) -> Result<Option<f64>, SolveError> {
    let mech = &scene.mech;
    if mech.kinematics != Kinematics::TwoHarmonic {
        return Ok(None);
    }
    let exact = Scene {
        mech: SliderCrank {
            kinematics: Kinematics::Exact,
            ..*mech
        },
        ..scene.clone()
    };
    let m = metrics(&exact, u)?;
    warnings.push(format!(
        "two-harmonic kinematics: the design's peak force with exact kinematics is {:.6} N ({:+.3e} N, {:+.3} %)",
        m.peak,
        m.peak - peak,
        100.0 * (m.peak - peak) / peak
    ));
    Ok(Some(m.peak))
}

/// Model only what the scene needs: say when gravity is left out but matters
/// (g/(Rω²) > 0.01), or is in but does not (g/(Rω²) < 10⁻³).
fn gravity_warning(scene: &Scene, warnings: &mut Vec<String>) {
    let mech = &scene.mech;
    let w2 = scene.omega * scene.omega;
    let g_ratio = 9.81 / (mech.r * w2);
    let g = scene.loads.gravity.norm();
    if g == 0.0 && g_ratio > 0.01 {
        warnings.push(format!(
            "gravity is not modelled but g/(Rω²) = {g_ratio:.3}: weights change the drive torque by up to about {:.0} % of its inertial part; set model.gravity for a vertical machine",
            100.0 * g_ratio
        ));
    } else if g > 0.0 && g / (mech.r * w2) < 1e-3 {
        warnings.push(format!(
            "gravity is modelled but g/(Rω²) = {:.2e}: its effect on the torque is below 0.1 %; it could be left out",
            g / (mech.r * w2)
        ));
    }
}

/// The torque–force Pareto front when the scene asks for one, or none (with a warning) when
/// the objectives do not trade off: the torque does not depend on the counterweight
/// (`torque_fixed`), or the ends' peak torques differ by no more than their gaps.
fn pareto_front(
    scene: &Scene,
    tab: &Sampled,
    torque_fixed: bool,
    warnings: &mut Vec<String>,
) -> Result<Vec<ParetoPoint>, SolveError> {
    if scene.pareto_points > 0 && torque_fixed {
        warnings.push(
            "no torque–force Pareto front: without gravity the drive torque does not depend on \
             the counterweight, so the two objectives do not trade off"
                .into(),
        );
        return Ok(Vec::new());
    }
    if scene.pareto_points == 0 {
        return Ok(Vec::new());
    }
    let front = pareto_sampled(scene, scene.pareto_points, tab)?;
    let (what, unit) = if scene.objective == Objective::MinEnergyFluctuation {
        ("ΔE", "J")
    } else {
        ("peak torque", "N·m")
    };
    // A front only where the two objectives trade off by more than their errors: ends
    // whose torques (or ΔE) differ by no more than their gaps are one design, not a front.
    Ok(match (front.first(), front.last()) {
        (Some(a), Some(b))
            if a.traded() - b.traded() <= a.gap() + b.gap() + 1e-12 * a.traded().abs() =>
        {
            warnings.push(format!(
                "no {what}–force Pareto front: the {what} optimum and the force optimum differ by {:.3e} {unit} in {what}, within their errors ({:.3e} {unit}): the objectives do not trade off",
                a.traded() - b.traded(),
                a.gap() + b.gap()
            ));
            Vec::new()
        }
        _ => front,
    })
}

/// A warning when the round-off of one force evaluation, `round_off_force` (N), exceeds
/// 10⁻¹⁰ of the design's peak force: about −log₁₀(round-off/peak) digits are reliable.
fn conditioning_warning(
    scene: &Scene,
    round_off_force: f64,
    peak: f64,
    warnings: &mut Vec<String>,
) {
    let mech = &scene.mech;
    let rel = round_off_force / peak.max(f64::MIN_POSITIVE);
    if rel > 1e-10 {
        warnings.push(format!(
            "ill-conditioned mechanism (assembly margin (L − R − |e|)/L = {:.2e}): round-off \
             alone can reach {:.1e} N in the shaking force, so about {:.0} significant digits \
             of the figures are reliable; the stated errors include it",
            (mech.l - mech.r - mech.e.abs()) / mech.l,
            round_off_force,
            (-rel.log10()).floor().max(0.0)
        ));
    }
}

/// The design's peak joint loads, with its counterweight's mass (0 where the scene does not
/// size it, with a warning when gravity makes that mass matter for the main bearing).
fn design_joint_loads(
    scene: &Scene,
    u: P2,
    counterweight: &Realised,
    tab: &Sampled,
    warnings: &mut Vec<String>,
) -> Result<JointLoadPeaks, SolveError> {
    let g = scene.loads.gravity.norm();
    let cw_mass = counterweight.mass.unwrap_or(0.0);
    if g > 0.0 && counterweight.mass.is_none() && u.norm() > 0.0 {
        warnings.push(
            "the main bearing load leaves out the counterweight's weight: the scene does \
             not size its mass (give design.radius or design.mass)"
                .into(),
        );
    }
    joint_load_peaks(scene, u, cw_mass, tab)
}
