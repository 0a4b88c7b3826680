//! The crane's real luffing drive (issue 38, thesis §1.1, Fig 1.5–1.7): the ideal torque T(φ)
//! about the boom foot A of [`super::balance`] carried by a hydraulic cylinder, a rope
//! tackle or a rack between a point P on the A-frame and a point Q on the boom — the force along it over
//! the luffing range, its stroke and its power, empty and loaded.
//!
//! Q turns with the boom: Q(φ) = s e_b + n e_n ([`boom_frame`]), so dQ/dφ = (Q_y, −Q_x). The
//! actuator's length ℓ = |Q − P| changes at
//!
//! ℓ′(φ) = e · dQ/dφ = −(Q × e),  e = (Q − P)/ℓ,
//!
//! whose magnitude is the actuator's lever arm about A, |r × e| with r = Q − A. A force U along
//! e on the boom (pushing, the cylinder extending) does the work U dℓ, so by virtual work
//! U ℓ′ = T: U = T/ℓ′ = T/(±|r × e|). A rope pulls, its tension S = −U: S ℓ′ = −T. The force is
//! reported in the actuator's working sense (the cylinder pushing, the rope pulling); a
//! negative rope tension is a slack rope — the rope cannot hold the boom there — and a
//! negative cylinder force is a pull (on the rod side).
//!
//! The stroke is |ℓ(φ_max) − ℓ(φ_min)| when ℓ′ keeps its sign over the range (else the
//! actuator passes a dead centre, where the force would be infinite: an error). With a
//! luffing time the actuator runs at the constant speed v = stroke/t_l (a pump's constant flow,
//! a winch's constant rope speed): the power is |U| v, and the boom's angular speed v/|ℓ′|
//! varies over the stroke. A rope tackle of n parts has the winch's line pull S/n and its rope
//! travel n·stroke (friction neglected).
//!
//! A rack (thesis §1.1's third drive) is pinned to the boom at Q and driven by a pinion of
//! pitch radius r_p in a gearbox that swings about P on the A-frame, so it is kinematically a
//! member of variable length P–Q like the cylinder: the same U (positive pushing), but it
//! works both ways without a rod side, its pinion carries the torque U·r_p, and at the rack's
//! constant speed v the pinion turns at v/r_p (mesh friction neglected).

use super::balance::{Balance, BalanceError, BalanceScene, Cases};
use super::model::Linkage;
use crate::geom::{cross, P2};
use crate::numeric::interval_peak;

/// Which actuator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ActuatorKind {
    /// A hydraulic cylinder, working by pushing.
    Cylinder,
    /// A rope tackle from a sheave on the A-frame to the boom, working by pulling.
    Rope,
    /// A rack pinned to the boom, driven by a pinion in a gearbox swinging about the A-frame
    /// point: pushes and pulls.
    Rack,
}

/// An actuator as the problem file states it (SI).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ActuatorSpec {
    /// Cylinder or rope.
    pub kind: ActuatorKind,
    /// P, its point on the A-frame (frame of A, x behind the foot, y up) (m).
    #[serde(rename = "frame_point_m")]
    pub frame_point: P2,
    /// (s, n), its point on the boom: s along the boom from A, n across it along e_n (m).
    #[serde(rename = "boom_point_m")]
    pub boom_point: [f64; 2],
    /// n, the rope tackle's parts (1 for a cylinder or a rack).
    pub parts: f64,
    /// r_p, the rack pinion's pitch radius (m; a rack only).
    #[serde(rename = "pinion_radius_m", skip_serializing_if = "Option::is_none")]
    pub pinion_radius: Option<f64>,
}

impl ActuatorSpec {
    /// Q(φ) = s e_b + n e_n.
    pub fn boom_point_at(&self, phi: f64) -> P2 {
        super::lever::boom_point_at(self.boom_point, phi)
    }

    /// ℓ(φ) = |Q(φ) − P|.
    pub fn length(&self, phi: f64) -> f64 {
        (self.boom_point_at(phi) - self.frame_point).norm()
    }

    /// ℓ′(φ) = −(Q × e), e = (Q − P)/ℓ (module doc); |ℓ′| is the lever arm about A.
    pub fn length_rate(&self, phi: f64) -> f64 {
        let q = self.boom_point_at(phi);
        let d = q - self.frame_point;
        -cross(q, d) / d.norm()
    }

    /// The force in the working sense that carries the drive torque T at φ: U = ±T/ℓ′.
    pub fn force(&self, phi: f64, torque: f64) -> f64 {
        self.sense() * torque / self.length_rate(phi)
    }

    /// The working sense: +1 a cylinder or a rack pushing, −1 a rope pulling.
    pub fn sense(&self) -> f64 {
        match self.kind {
            ActuatorKind::Cylinder | ActuatorKind::Rack => 1.0,
            ActuatorKind::Rope => -1.0,
        }
    }
}

/// The force of one actuator in one load case.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ActuatorCase {
    /// The actuator's index in the file's order (from 0).
    pub actuator: usize,
    /// `empty` or `loaded`.
    pub case: String,
    /// The largest force in the working sense over the range (N).
    pub force_max_n: f64,
    /// Its boom angle (rad).
    pub phi_at_force_max_rad: f64,
    /// The smallest force in the working sense (N): negative is a slack rope or a pulling
    /// cylinder.
    pub force_min_n: f64,
    /// Its boom angle (rad).
    pub phi_at_force_min_rad: f64,
    /// Bound on the error of both (N): refinement plus the torque's stated error over the
    /// lever arm.
    pub force_error_n: f64,
    /// For a rope: the winch's largest line pull, force_max/n (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub winch_line_pull_max_n: Option<f64>,
    /// For a rack: the pinion's largest torque, max |U|·r_p (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pinion_torque_max_nm: Option<f64>,
    /// Its error, the force's times r_p (N·m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pinion_torque_error_nm: Option<f64>,
    /// With a luffing time: max |U|·v (W).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_power_w: Option<f64>,
    /// Its error (W).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_power_error_w: Option<f64>,
}

/// One actuator over the luffing range.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Actuator {
    /// The data.
    pub spec: ActuatorSpec,
    /// ℓ at φ_min and at φ_max (m).
    pub length_m: [f64; 2],
    /// |ℓ(φ_max) − ℓ(φ_min)| (m).
    pub stroke_m: f64,
    /// For a rope: the winch's rope travel n·stroke (m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rope_travel_m: Option<f64>,
    /// The smallest lever arm |ℓ′| over the range (m) and its boom angle (rad).
    pub lever_arm_min_m: f64,
    /// See `lever_arm_min_m`.
    pub phi_at_lever_arm_min_rad: f64,
    /// The largest lever arm |ℓ′| (m).
    pub lever_arm_max_m: f64,
    /// With a luffing time: v = stroke/t_l (m/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_m_per_s: Option<f64>,
    /// For a rack with a luffing time: the pinion's speed v/r_p (rpm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pinion_speed_rpm: Option<f64>,
    /// Per load case, with the designed counterweight (without one when none is designed);
    /// in the JSON, the section's `cases`.
    #[serde(skip)]
    pub cases: Vec<ActuatorCase>,
    /// The finding in plain words.
    pub verdict: String,
}

/// The actuators of the luffing drive.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LuffingActuators {
    /// How it was computed.
    pub method: String,
    /// Whether the designed boom counterweight is on the boom.
    pub with_counterweight: bool,
    /// t_l (s), with `mechanism.drive.luffing_time`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub luffing_time_s: Option<f64>,
    /// One per `[[mechanism.luffing_actuator]]`.
    pub actuators: Vec<Actuator>,
    /// Every actuator's rows, per load case.
    pub cases: Vec<ActuatorCase>,
}

/// Samples of the range for the peaks (refined by Brent to [`XTOL`]).
const SAMPLES: usize = 64;

/// Angle tolerance of the refinement (rad).
const XTOL: f64 = 1e-9;

/// The actuators `specs` driving `link` under `scene` with the balance's designed
/// counterweight, luffing in `luffing_time` s if given (module doc).
pub fn actuators(
    link: &Linkage,
    scene: &BalanceScene,
    bal: &Balance,
    specs: &[ActuatorSpec],
    luffing_time: Option<f64>,
) -> Result<LuffingActuators, BalanceError> {
    let c = Cases::new(link, scene);
    let (m, u) = bal
        .counterweight
        .as_ref()
        .map_or((0.0, [0.0; 2]), |cw| (cw.mass_kg, cw.static_moment_kgm));
    let actuators: Vec<Actuator> = specs
        .iter()
        .enumerate()
        .map(|(i, s)| actuator(&c, i, s, m, u, luffing_time))
        .collect::<Result<_, _>>()?;
    let cases = actuators.iter().flat_map(|a| a.cases.clone()).collect();
    Ok(LuffingActuators {
        method: "U = T/ℓ′ (virtual work), ℓ′ = −(Q × e) in closed form, T from the statics with the designed counterweight; the extremes of U and of |ℓ′| from 64 samples refined by Brent to 1e-9 rad".into(),
        with_counterweight: m > 0.0,
        luffing_time_s: luffing_time,
        actuators,
        cases,
    })
}

/// One actuator: its lengths, lever arms and, per case, its force extremes.
fn actuator(
    c: &Cases,
    index: usize,
    s: &ActuatorSpec,
    m: f64,
    u: [f64; 2],
    luffing_time: Option<f64>,
) -> Result<Actuator, BalanceError> {
    let [p0, p1] = c.link.phi_range;
    let sign0 = s.length_rate(p0).signum();
    let arm = |phi: f64| sign0 * s.length_rate(phi);
    let lo = interval_peak(|phi| -arm(phi), p0, p1, SAMPLES, XTOL)
        .map_err(|_| BalanceError::NoPose { phi: p0 })?;
    let hi =
        interval_peak(arm, p0, p1, SAMPLES, XTOL).map_err(|_| BalanceError::NoPose { phi: p0 })?;
    let arm_min = -lo.peak.fx;
    if !(arm_min > 1e-9 * hi.peak.fx.abs()) {
        return Err(BalanceError::DeadCentre { phi: lo.peak.x });
    }
    let length_m = [s.length(p0), s.length(p1)];
    let stroke = (length_m[1] - length_m[0]).abs();
    let speed = luffing_time.map(|t| stroke / t);
    let mut cases = Vec::new();
    for &(name, q) in &c.cases {
        let force = |phi: f64| {
            c.at(phi, q, m, u)
                .map_or(f64::NAN, |st| s.force(phi, st.drive_torque))
        };
        let fmax = interval_peak(force, p0, p1, SAMPLES, XTOL)
            .map_err(|_| BalanceError::NoPose { phi: p0 })?;
        let fmin = interval_peak(|phi| -force(phi), p0, p1, SAMPLES, XTOL)
            .map_err(|_| BalanceError::NoPose { phi: p0 })?;
        let stated = |phi: f64, f: f64| -> Result<f64, BalanceError> {
            let st = c.at(phi, q, m, u)?;
            Ok(st.drive_torque_error / s.length_rate(phi).abs() + 16.0 * f64::EPSILON * f.abs())
        };
        let err = fmax.error.max(fmin.error)
            + stated(fmax.peak.x, fmax.peak.fx)?.max(stated(fmin.peak.x, fmin.peak.fx)?);
        let peak = fmax.peak.fx.abs().max(fmin.peak.fx.abs());
        cases.push(ActuatorCase {
            actuator: index,
            case: name.into(),
            force_max_n: fmax.peak.fx,
            phi_at_force_max_rad: fmax.peak.x,
            force_min_n: -fmin.peak.fx,
            phi_at_force_min_rad: fmin.peak.x,
            force_error_n: err,
            winch_line_pull_max_n: (s.kind == ActuatorKind::Rope).then(|| fmax.peak.fx / s.parts),
            pinion_torque_max_nm: s.pinion_radius.map(|r| peak * r),
            pinion_torque_error_nm: s.pinion_radius.map(|r| err * r),
            peak_power_w: speed.map(|v| peak * v),
            peak_power_error_w: speed.map(|v| err * v),
        });
    }
    Ok(Actuator {
        verdict: verdict(s, &cases, stroke),
        spec: *s,
        length_m,
        stroke_m: stroke,
        rope_travel_m: (s.kind == ActuatorKind::Rope).then(|| s.parts * stroke),
        lever_arm_min_m: arm_min,
        phi_at_lever_arm_min_rad: lo.peak.x,
        lever_arm_max_m: hi.peak.fx,
        speed_m_per_s: speed,
        pinion_speed_rpm: speed
            .zip(s.pinion_radius)
            .map(|(v, r)| v / r * 60.0 / std::f64::consts::TAU),
        cases,
    })
}

/// The finding in plain words: the largest force, and a rope going slack or a cylinder
/// pulling where the torque changes sign.
fn verdict(s: &ActuatorSpec, cases: &[ActuatorCase], stroke: f64) -> String {
    let (what, works) = match s.kind {
        ActuatorKind::Cylinder => ("cylinder", "pushes"),
        ActuatorKind::Rope => ("rope tackle", "pulls"),
        ActuatorKind::Rack => ("rack", "pushes"),
    };
    let max = cases
        .iter()
        .map(|c| c.force_max_n)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut v = format!(
        "The {what} {works} at most {:.1} kN over a stroke of {stroke:.3} m",
        max / 1e3
    );
    for c in cases.iter().filter(|c| c.force_min_n < 0.0) {
        v += &match s.kind {
            ActuatorKind::Rope => format!(
                "; {}: the rope would have to push {:.1} kN, so it goes SLACK (the boom is over-balanced there: it cannot be held by this rope alone)",
                c.case,
                -c.force_min_n / 1e3
            ),
            ActuatorKind::Cylinder => format!(
                "; {}: it must also pull {:.1} kN (double-acting, the rod side)",
                c.case,
                -c.force_min_n / 1e3
            ),
            ActuatorKind::Rack => format!(
                "; {}: it also pulls {:.1} kN (the pinion's torque reverses: the mesh crosses its backlash and loads the other tooth flanks)",
                c.case,
                -c.force_min_n / 1e3
            ),
        };
    }
    if let Some(t) = pinion_torque_max(cases) {
        v += &format!("; its pinion carries at most {:.1} kN·m", t / 1e3);
    }
    v + "."
}

/// A rack's largest pinion torque over the load cases (N·m); `None` for a cylinder or rope.
pub(super) fn pinion_torque_max(cases: &[ActuatorCase]) -> Option<f64> {
    cases
        .iter()
        .filter_map(|c| c.pinion_torque_max_nm)
        .reduce(f64::max)
}
