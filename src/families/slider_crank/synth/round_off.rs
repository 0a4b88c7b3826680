//! Bounds on the floating-point round-off of one evaluation of the force, torque, moment
//! and joint loads: the conditioning term of every stated error.

use super::scene::Scene;
use crate::geom::P2;

/// Bounds on the round-off of one evaluation of the shaking force (N), the drive torque
/// (N·m) and the shaking moment (N·m) of the counterweight `u`, at any crank angle: the
/// conditioning term of every stated error. Built from the kinematic bounds of
/// [`SliderCrank::round_off`] through the formulas of [`SliderCrank::shaking_force0`],
/// [`SliderCrank::drive_torque0`], [`SliderCrank::load_torque0`] and
/// [`SliderCrank::shaking_moment0`], each product's error as |a|δb + |b|δa + (rounding)·|ab|.
/// Tested against a double-double evaluation in `tests/certified.rs`.
pub fn round_off_bounds(scene: &Scene, u: P2) -> [f64; 3] {
    let eps = f64::EPSILON;
    let m = &scene.mech;
    let ro = m.round_off();
    let w2 = scene.omega * scene.omega;
    let mu = (m.rod.centroid / m.l).abs();
    let (m2, m3, m4) = (m.crank.mass, m.rod.mass, m.slider_mass);
    let r = m.r;
    let [x0, x1, x2] = ro.x;
    let [dx0, dx1, dx2] = ro.dx;
    let [p1, p2] = ro.psi;
    let [dp1, dp2] = ro.dpsi;
    let i_eff = m.rod.inertia.abs() + m.rod_inertia_excess().abs();
    let un = u.norm();
    let r2 = (m.crank.centroid).abs();
    // Shaking force: f₀ = −(m2 (r2/R) A'' + m3 G3'' + m4 x'' e_x), F = ω²(f₀ + Rot U).
    let (g1, g2) = (r + x1, r + x2);
    let f0 = m2 * r2 + m3 * g2 + m4 * x2;
    let force = w2 * ((m3 * mu + m4) * dx2 + 20.0 * eps * (f0 + un));
    // Drive torque: ω²(m3 G3'·G3'' + I ψ'ψ'' + m4 x'x'') − Σ m g·r' − F_p x' − g·Rot'U.
    let t_in = m3 * (g1 * mu * dx2 + g2 * mu * dx1 + 6.0 * eps * g1 * g2)
        + i_eff * (p1 * dp2 + p2 * dp1 + 6.0 * eps * p1 * p2)
        + m4 * (x1 * dx2 + x2 * dx1 + 6.0 * eps * x1 * x2);
    let t_in_size = m3 * g1 * g2 + i_eff * p1 * p2 + m4 * x1 * x2;
    let g = scene.loads.gravity.norm();
    let fp = scene.loads.process.max_abs();
    let t_load = g
        * (4.0 * eps * m2 * r2 + m3 * (mu * dx1 + 4.0 * eps * g1) + m4 * (dx1 + 4.0 * eps * x1))
        + fp * (dx1 + 4.0 * eps * x1);
    let t_load_size = g * (m2 * r2 + m3 * g1 + m4 * x1) + fp * x1;
    let torque = w2 * t_in
        + t_load
        + 6.0 * eps * g * un
        + 6.0 * eps * (w2 * t_in_size + t_load_size + g * un);
    // Shaking moment: −ω²(m3 G3 × G3'' + I ψ'' + m4 B × B'').
    let b0 = x0 + m.e.abs();
    let m_err = m3 * (b0 * (mu * dx2 + 4.0 * eps * g2) + g2 * (mu * dx0 + 4.0 * eps * b0))
        + i_eff * (dp2 + 2.0 * eps * p2)
        + m4 * (b0 * dx2 + x2 * dx0 + 4.0 * eps * b0 * x2)
        + 6.0 * eps * (m3 * b0 * g2 + i_eff * p2 + m4 * b0 * x2);
    // The balancers: a few roundings of n²|B_n| (cos nφ, sin nφ) each.
    let (mut bf, mut bm, mut bt) = (0.0, 0.0, 0.0);
    for b in &scene.balancers {
        let n = b.pair.order as f64;
        let mag = b.unbalance[0].abs() + b.unbalance[1].abs();
        bf += 8.0 * eps * n * n * mag;
        bm += 8.0 * eps * n * n * mag * b.pair.offset.abs();
        bt += 8.0 * eps * n * mag * g;
    }
    [
        force + w2 * bf,
        torque + bt,
        w2 * (m_err + bm) * (1.0 + 4.0 * eps),
    ]
}

/// A bound on the round-off of one evaluation of the joint loads (N) of
/// [`SliderCrank::joint_loads`] for the counterweight `u` of mass `cw_mass`: the kinematic
/// round-off of [`SliderCrank::round_off`] through the accelerations (each divided once by
/// k = L cos ψ ≥ k_min in F_43,y), and 64ε plus twice the relative round-off of k on the
/// size of every term.
pub fn joint_load_round_off(scene: &Scene, u: P2, cw_mass: f64) -> f64 {
    let eps = f64::EPSILON;
    let m = &scene.mech;
    let ro = m.round_off();
    let w2 = scene.omega * scene.omega;
    let a = m.r + m.e.abs();
    let kmin = ((m.l - a) * (m.l + a)).sqrt();
    let lever = 1.0 + (m.l + a) / kmin;
    let (m2, m3, m4) = (m.crank.mass, m.rod.mass, m.slider_mass);
    let i3 = m.rod.inertia.abs();
    let g = scene.loads.gravity.norm();
    let acc_err = w2 * ((m3 + m4) * ro.dx[2] * lever + i3 * ro.dpsi[1] / kmin);
    let size = (w2 * (m2 * m.crank.centroid.abs() + u.norm() + (m3 + m4) * (m.r + ro.x[2]))
        + w2 * i3 * ro.psi[1] / kmin
        + g * (m2 + m3 + m4 + cw_mass)
        + scene.loads.process.max_abs())
        * lever;
    acc_err + (64.0 * eps + 2.0 * ro.rho_k) * size
}
