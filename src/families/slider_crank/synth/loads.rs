//! The peak joint loads of a design over the cycle and the check of the load limits.

use super::fields::Sampled;
use super::metrics::grid_extremes;
use super::outcome::{JointLoadPeaks, LoadPeak};
use super::round_off::joint_load_round_off;
use super::scene::{Scene, SolveError};
use crate::geom::P2;
use crate::synth::counterweight::Status;

/// The peak joint loads of the design `u` (kg·m) of mass `cw_mass` over the cycle: sampled on
/// the scan grid, every local maximum refined as the peak force is.
pub(super) fn joint_load_peaks(
    scene: &Scene,
    u: P2,
    cw_mass: f64,
    tab: &Sampled,
) -> Result<JointLoadPeaks, SolveError> {
    let (mech, omega, s) = (&scene.mech, scene.omega, &scene.settings);
    let at = |phi: f64| {
        let st = mech.state(phi).expect("assembly checked");
        mech.joint_loads(&st, omega, &scene.loads, u, cw_mass)
    };
    let n = tab.scan.len();
    let h = std::f64::consts::TAU / n as f64;
    let samples: Vec<_> = (0..n).map(|k| at(k as f64 * h)).collect();
    let ro = joint_load_round_off(scene, u, cw_mass);
    let peak = |pick: &dyn Fn(&crate::families::slider_crank::model::JointLoads) -> f64| {
        let ys: Vec<f64> = samples.iter().map(pick).collect();
        let scale = ys.iter().fold(0.0, |a: f64, &b| a.max(b));
        grid_extremes(&ys, |p| pick(&at(p)), scale, false, s).map(|(pk, _)| LoadPeak {
            peak: pk.peak.fx,
            angle: pk.peak.x,
            error: pk.error + ro,
        })
    };
    Ok(JointLoadPeaks {
        main_bearing: peak(&|j| j.main.norm())?,
        crank_pin: peak(&|j| j.crank_pin.norm())?,
        wrist_pin: peak(&|j| j.wrist_pin.norm())?,
        guide: peak(&|j| j.guide.abs())?,
    })
}

/// The joint-load limits against the design's peaks: a peak above its limit by more than its
/// error makes the result `infeasible` (the pin and guide loads do not depend on the design,
/// so no design meets such a limit); one within its error of the limit, `inaccurate`.
pub(super) fn check_load_limits(
    scene: &Scene,
    jl: &JointLoadPeaks,
    status: &mut Status,
    warnings: &mut Vec<String>,
) {
    let ll = &scene.load_limits;
    for (name, key, lim, p) in [
        (
            "main bearing",
            "max_main_bearing_load",
            ll.main_bearing,
            jl.main_bearing,
        ),
        (
            "crank pin",
            "max_crank_pin_load",
            ll.crank_pin,
            jl.crank_pin,
        ),
        (
            "wrist pin",
            "max_wrist_pin_load",
            ll.wrist_pin,
            jl.wrist_pin,
        ),
        ("guide", "max_guide_load", ll.guide, jl.guide),
    ] {
        let Some(lim) = lim else { continue };
        // The main bearing's limit is a constraint of the design, met (to the engine's
        // tolerance) or declared infeasible by the engine; the others are only checked.
        let designed = name == "main bearing";
        let tol = if designed {
            scene.settings.rel_tol * lim
        } else {
            0.0
        };
        if p.peak - p.error > lim + tol {
            *status = Status::Infeasible;
            warnings.push(format!(
                "infeasible: objective.{key} = {lim} N cannot be met: the {name} load peaks at {:.6} N (± {:.1e} N) at φ = {:.3}°{}",
                p.peak,
                p.error,
                p.angle.to_degrees(),
                if name == "main bearing" {
                    ""
                } else {
                    " and does not depend on the counterweight or the balancers"
                }
            ));
        } else if !designed && p.peak + p.error > lim && *status == Status::Optimal {
            *status = Status::Inaccurate;
            warnings.push(format!(
                "objective.{key} = {lim} N: the {name} load peaks at {:.9} N ± {:.1e} N, within its error of the limit",
                p.peak, p.error
            ));
        }
    }
}
