//! The slider-crank as a one-degree-of-freedom machine for [`crate::dynamics`]: the design's
//! generalised inertia J(φ), its derivative and the torque of the weights and the process
//! load, so that ½ J′ ω² + G is exactly the constant-speed drive torque
//! ([`super::drive_torque`]) the rest of the family reports.

use super::scene::{Scene, SolveError};
use crate::dynamics::{constant_speed, DriveSettings};
use crate::families::slider_crank::model::{rot_cs, weight_torque_cs};
use crate::geom::P2;

/// ΔE of the drive at constant speed with the counterweight U = `u`, and its error bound
/// (J): [`crate::dynamics::constant_speed`] on [`machine`] (a constant inertia adds nothing
/// to ΔE, so the counterweight's own is left out).
pub fn energy_fluctuation(scene: &Scene, u: P2) -> Result<[f64; 2], SolveError> {
    let c = constant_speed(
        &machine(scene, u, 0.0),
        scene.omega,
        &DriveSettings::default(),
    )
    .map_err(|e| SolveError::Numeric(format!("the energy curve: {e}")))?;
    Ok([c.energy_fluctuation, c.energy_fluctuation_error])
}

/// (J, J′, G) of `scene` with the counterweight U = `u`:
/// J(φ) = 2 E₀(φ) + J_c with E₀ the links' kinetic energy per ω²
/// ([`crate::families::slider_crank::model::SliderCrank::kinetic_energy0`]: the crank as its
/// mass at its centroid) and J_c = `constant_inertia` (the counterweight's m r², anything
/// else turning with the crank); J′ = 2 T₀ with T₀ the inertial drive torque per ω²
/// (`drive_torque0`, which is dE₀/dφ); G = the weights' and the process force's torque
/// (`load_torque0`) plus the counterweight's and the balancers' weights. The balancers'
/// own inertia is not modelled (it only adds to J_c: leaving it out errs towards a larger
/// flywheel).
pub fn machine(
    scene: &Scene,
    u: P2,
    constant_inertia: f64,
) -> impl Fn(f64) -> [f64; 3] + Sync + '_ {
    move |phi: f64| {
        let m = &scene.mech;
        let Some(st) = m.state(phi) else {
            return [f64::NAN; 3];
        };
        let mut g =
            m.load_torque0(&st, &scene.loads) + weight_torque_cs(st.cs, scene.loads.gravity, u);
        if !scene.balancers.is_empty() {
            g += scene.balancer_torque(phi);
        }
        [
            2.0 * m.kinetic_energy0(&st) + constant_inertia,
            2.0 * m.drive_torque0(&st),
            g,
        ]
    }
}

/// The shaking force (N) at φ at real speed, with the crank at speed ω and angular
/// acceleration α: F = ω² (f₀ + Rot(φ)U) + α (p₀ − Rot(φ + π/2)U), the links' f₀ and p₀ of
/// [`crate::families::slider_crank::model::SliderCrank::momentum0`] and the counterweight's
/// centripetal and tangential parts. Balancers are left out (their tangential part is not
/// modelled): `None` with balancers, or where the mechanism does not assemble.
pub fn real_speed_force(scene: &Scene, u: P2, phi: f64, omega: f64, alpha: f64) -> Option<P2> {
    if !scene.balancers.is_empty() {
        return None;
    }
    let m = &scene.mech;
    let st = m.state(phi)?;
    let [c, s] = st.cs;
    let f0 = m.shaking_force0(&st) + rot_cs([c, s], u);
    let p0 = m.momentum0(&st) - rot_cs([-s, c], u);
    Some(f0 * (omega * omega) + p0 * alpha)
}
